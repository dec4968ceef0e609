// The interactive preview. Without a display: the pass schedule keeps render's estimator
// (every pixel gets sample indices 0..spp-1 once, in order), the camera controller, the
// input script parser, and the one-line failure when there is no display. With a virtual
// display (Xvfb, started here on a free display number): the real binary's screenshot
// matches `render`'s PNG, and scripted keys and drags restart the accumulation.
#include <poll.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <csignal>
#include <cstddef>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/errors.h"
#include "gpu_fixture.h"
#include "image/image.h"
#include "preview/camera_controller.h"
#include "preview/input_script.h"
#include "preview/integrator_controls.h"
#include "preview/key_bindings.h"
#include "preview/layer_cycle.h"
#include "preview/pass_scheduler.h"
#include "scene/integrator_json.h"
#include "shared/types.h"

#include "png_reader.h"

using namespace penumbra;
using namespace penumbra::preview;
namespace fs = std::filesystem;

static_assert(sizeof(gpu::ToneMapConstants) == 16);
static_assert(offsetof(gpu::ToneMapConstants, scale) == 8);

// ---- Pass schedule ----------------------------------------------------------------------

// Replays a schedule row by row: each row must see sample indices 0, 1, 2, ... in order,
// and no slice may start sample s + 1 on a row while some row still lacks sample s.
void checkSchedule(uint32_t height, uint32_t spp, const std::function<uint64_t(int)>& budget) {
    PassScheduler scheduler(height, spp);
    std::vector<uint32_t> next(height, 0);  // the next sample index each row expects
    for (int frame = 0; !scheduler.finished(); ++frame) {
        ASSERT_LT(frame, 100000) << "schedule does not finish";
        auto slices = scheduler.next(budget(frame));
        ASSERT_FALSE(slices.empty());
        for (const PassSlice& slice : slices) {
            ASSERT_GE(slice.count, 1u);
            ASSERT_LE(slice.firstRow + slice.rowCount, height);
            for (uint32_t i = 0; i < slice.count; ++i) {
                const uint32_t sample = slice.firstSample + i;
                const uint32_t lowest = *std::min_element(next.begin(), next.end());
                ASSERT_LE(sample, lowest) << "sample " << sample << " started before every row had " << lowest;
                for (uint32_t row = slice.firstRow; row < slice.firstRow + slice.rowCount; ++row) {
                    ASSERT_EQ(next[row], sample) << "row " << row << " frame " << frame;
                    ++next[row];
                }
            }
        }
        const uint32_t lowest = *std::min_element(next.begin(), next.end());
        EXPECT_EQ(scheduler.samplesDone(), lowest);
    }
    for (uint32_t row = 0; row < height; ++row) ASSERT_EQ(next[row], spp) << "row " << row;
    EXPECT_TRUE(scheduler.next(1000).empty());
}

TEST(PreviewSchedule, EveryRowGetsEachSampleOnceAndInOrder) {
    checkSchedule(48, 16, [](int) { return 48; });     // one pass a frame
    checkSchedule(48, 16, [](int) { return 8; });      // bands of 8 rows
    checkSchedule(50, 7, [](int) { return 24; });      // bands that do not divide the film
    checkSchedule(48, 16, [](int) { return 48 * 5; }); // several passes a frame
    checkSchedule(48, 16, [](int) { return 70; });     // a pass and a band
    std::mt19937 rng(7);
    checkSchedule(37, 11, [&](int) { return uint64_t(1 + rng() % 200); });  // the adaptive budget's erratic sizes
}

TEST(PreviewSchedule, RestartBeginsAgainAtSampleZero) {
    PassScheduler scheduler(10, 4);
    scheduler.next(25);
    EXPECT_EQ(scheduler.samplesDone(), 2u);
    EXPECT_EQ(scheduler.rowsAhead(), 5u);
    scheduler.restart();
    EXPECT_EQ(scheduler.samplesDone(), 0u);
    auto slices = scheduler.next(10);
    ASSERT_EQ(slices.size(), 1u);
    EXPECT_EQ(slices[0].firstSample, 0u);
    EXPECT_EQ(slices[0].firstRow, 0u);
}

TEST(PreviewSchedule, AdaptiveBudgetStaysInBounds) {
    // Too slow: halves, never below 8 rows; multiples of 8 below one film.
    EXPECT_EQ(adaptRowBudget(64, 0.2, 0.04, 400), 32u);
    EXPECT_EQ(adaptRowBudget(8, 1.0, 0.04, 400), 8u);
    EXPECT_EQ(adaptRowBudget(100, 0.04, 0.04, 400) % 8, 0u);
    // Fast: at most doubles, at most 256 passes.
    EXPECT_EQ(adaptRowBudget(64, 0.001, 0.04, 400), 128u);
    EXPECT_EQ(adaptRowBudget(256 * 400, 0.001, 0.04, 400), 256u * 400);
    // A film shorter than 8 rows still gets whole passes.
    EXPECT_EQ(adaptRowBudget(4, 1.0, 0.04, 4), 4u);
}

// ---- Camera controller ------------------------------------------------------------------

Camera testCamera() {
    Camera camera;
    camera.eye = {0, 1, 4};
    camera.target = {0, 1, 0};
    camera.up = {0, 1, 0};
    camera.fovY = 40;
    return camera;
}

TEST(PreviewCamera, OrbitKeepsTheDistanceAndHalfAnImageHeightIsNinetyDegrees) {
    CameraController controller(testCamera());
    controller.orbit(200, 0, 400);  // half the view height: a quarter turn about up
    const Camera& c = controller.camera();
    EXPECT_NEAR(glm::length(c.eye - c.target), 4.0f, 1e-5f);
    EXPECT_NEAR(c.eye.y, 1.0f, 1e-5f);
    // Dragging right turns the scene right: the eye moves to the camera's left (-x).
    EXPECT_NEAR(c.eye.x, -4.0f, 1e-4f);
    EXPECT_NEAR(c.eye.z, 0.0f, 1e-4f);
    EXPECT_EQ(c.target, testCamera().target);
}

TEST(PreviewCamera, OrbitNeverFlipsOverThePole) {
    CameraController controller(testCamera());
    controller.orbit(0, 5000, 400);  // far more than 180 degrees downwards
    const Camera& c = controller.camera();
    glm::vec3 dir = glm::normalize(c.eye - c.target);
    EXPECT_GT(dir.y, 0.99f);  // above the target, looking down
    EXPECT_LT(dir.y, 1.0f);   // but not exactly along up, which would leave no basis
    EXPECT_NEAR(glm::length(c.eye - c.target), 4.0f, 1e-4f);
}

TEST(PreviewCamera, PanMovesEyeAndTargetTogetherByTheFilmAtTargetDepth) {
    CameraController controller(testCamera());
    controller.pan(100, 0, 400);  // a quarter of the view height to the right
    const Camera& c = controller.camera();
    // The film spans 2 * 4 * tan(20 deg) world units vertically at the target's depth;
    // the content follows the cursor, so the camera moves left.
    const float expected = -0.25f * 2.0f * 4.0f * std::tan(glm::radians(20.0f));
    EXPECT_NEAR(c.eye.x, expected, 1e-5f);
    EXPECT_NEAR(c.target.x, expected, 1e-5f);
    EXPECT_NEAR(c.eye.z - c.target.z, 4.0f, 1e-5f);
}

TEST(PreviewCamera, ZoomScalesTheDistanceAndResetRestores) {
    CameraController controller(testCamera());
    controller.zoom(2);
    EXPECT_NEAR(glm::length(controller.camera().eye - controller.camera().target), 4.0f * 0.81f, 1e-5f);
    controller.zoom(-2);
    EXPECT_NEAR(glm::length(controller.camera().eye - controller.camera().target), 4.0f, 1e-5f);
    controller.orbit(33, -20, 400);
    controller.pan(5, 7, 400);
    controller.reset();
    EXPECT_EQ(controller.camera().eye, testCamera().eye);
    EXPECT_EQ(controller.camera().target, testCamera().target);
}

// ---- Input scripts and keys -------------------------------------------------------------

TEST(PreviewScript, ParsesEveryEventKindInFrameOrder) {
    auto events = parseInputScript(
        "# a comment\n"
        "frame 5 drag 10 -2   # orbit\n"
        "\n"
        "frame 3 key 2\n"
        "frame 3 key ESC\n"
        "frame 7 drag 1 2 right\n"
        "frame 8 scroll -1.5\n"
        "frame 9 resize 300 200\n",
        "test.script");
    ASSERT_EQ(events.size(), 6u);
    EXPECT_EQ(events[0].frame, 3u);
    EXPECT_EQ(events[0].event.action, Action::StrategyBsdf);
    EXPECT_EQ(events[1].event.action, Action::Quit);
    EXPECT_EQ(events[2].frame, 5u);
    EXPECT_EQ(events[2].event.type, InputEvent::Type::Drag);
    EXPECT_EQ(events[2].event.button, MouseButton::Left);
    EXPECT_EQ(events[2].event.dx, 10.0);
    EXPECT_EQ(events[2].event.dy, -2.0);
    EXPECT_EQ(events[3].event.button, MouseButton::Right);
    EXPECT_EQ(events[4].event.type, InputEvent::Type::Scroll);
    EXPECT_EQ(events[4].event.dy, -1.5);
    EXPECT_EQ(events[5].event.type, InputEvent::Type::Resize);
    EXPECT_EQ(events[5].event.width, 300);
}

TEST(PreviewScript, ErrorsNameTheFileAndLine) {
    auto expectError = [](const std::string& text, const std::string& mention) {
        try {
            parseInputScript(text, "bad.script");
            ADD_FAILURE() << "no error for: " << text;
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find(mention), std::string::npos) << e.what();
            EXPECT_EQ(std::string(e.what()).rfind("bad.script:", 0), 0u) << e.what();
        }
    };
    expectError("frame 1 key 2\nframe 2 key x\n", "bad.script:2: unknown key 'x'");
    expectError("frame 0 key 2\n", "bad.script:1:");
    expectError("frame 1.5 key 2\n", "whole numbers");
    expectError("frame 1 drag 1\n", "missing drag dy");
    expectError("frame 1 drag 1 nan\n", "finite");
    expectError("frame 1 jump\n", "unknown event 'jump'");
    expectError("frame 1 key 2 3\n", "unexpected '3'");
    expectError("key 2\n", "expected 'frame N");
}

TEST(PreviewKeys, HelpListsEveryScriptKey) {
    std::string help = keyHelp();
    for (const char* key : {"1", "2", "3", "4", "H", "S", "+", "-", "P", "R", "Q, Esc"})
        EXPECT_NE(help.find("\n  " + std::string(key) + " "), std::string::npos) << key << " missing from:\n" << help;
    for (const char* name : {"1", "2", "3", "4", "h", "s", "+", "-", "p", "r", "q", "esc", "Esc", "H"})
        EXPECT_TRUE(actionForKeyName(name).has_value()) << name;
    EXPECT_EQ(*actionForKeyName("s"), Action::CycleSphereSampling);
}

// The option keys' lines of `penumbra preview --help`, word for word as they were before the
// registry made them (a user-facing text: the label, the values in key order, the notes).
TEST(PreviewKeys, OptionHelpLinesStayAsTheyWere) {
    const std::string help = keyHelp();
    for (const char* line : {
             "1                   strategy light (direct integrator)",
             "2                   strategy bsdf",
             "3                   strategy mis",
             "4                   strategy mixture",
             "5                   strategy ris",
             "H                   MIS heuristic: balance <-> power",
             "S                   sphere sampling: area -> cap -> solid_angle",
             "T                   quad sampling: area <-> solid_angle",
             "M                   mesh-light triangle sampling: area <-> solid_angle",
             "L                   light selection: uniform -> power -> bvh (rebuilds the light tables)",
         })
        EXPECT_NE(help.find("\n  " + std::string(line) + "\n"), std::string::npos) << line << " missing from:\n"
                                                                                   << help;
}

// ---- Integrator keys ----------------------------------------------------------------------

TEST(PreviewIntegratorKeys, ChangeTheOptionsAndTheJsonThatSavesRecord) {
    IntegratorSettings settings;  // direct, mis, power, solid_angle
    EXPECT_EQ(integratorLabel(settings), "mis power, spheres solid_angle");
    EXPECT_FALSE(applyIntegratorAction(settings, Action::StrategyMis));  // already mis: no restart
    EXPECT_TRUE(applyIntegratorAction(settings, Action::StrategyBsdf));
    EXPECT_EQ(settings.strategy, Strategy::Bsdf);
    EXPECT_EQ(integratorJson(settings)["strategy"], "bsdf");
    EXPECT_TRUE(applyIntegratorAction(settings, Action::ToggleHeuristic));
    EXPECT_EQ(settings.heuristic, Heuristic::Balance);
    EXPECT_EQ(integratorJson(settings)["heuristic"], "balance");
    const SphereSampling cycle[] = {SphereSampling::Area, SphereSampling::Cap, SphereSampling::SolidAngle};
    const char* names[] = {"area", "cap", "solid_angle"};
    for (int i = 0; i < 3; ++i) {
        EXPECT_TRUE(applyIntegratorAction(settings, Action::CycleSphereSampling));
        EXPECT_EQ(settings.sphereSampling, cycle[i]);
        EXPECT_EQ(integratorJson(settings)["sphere_sampling"], names[i]);
    }
    EXPECT_EQ(integratorLabel(settings), "bsdf, spheres solid_angle");
    EXPECT_FALSE(applyIntegratorAction(settings, Action::ExposureUp));

    IntegratorSettings ao;
    ao.type = IntegratorType::AmbientOcclusion;
    EXPECT_FALSE(applyIntegratorAction(ao, Action::StrategyLight));  // ao has no strategies
    EXPECT_EQ(ao.strategy, Strategy::Mis);
    EXPECT_EQ(integratorLabel(ao), "ao cosine");
}

// Every key the option registry gives (scene/integrator_options.h) is bound, listed in the
// help, and changes its option of a settings object of its integrator type: a per-value key
// sets its value (again: no restart), a cycling key steps to the next value in table order.
TEST(PreviewIntegratorKeys, EveryRegistryKeyIsBoundAndChangesItsOption) {
    ASSERT_FALSE(optionKeys().empty());
    for (size_t i = 0; i < optionKeys().size(); ++i) {
        const OptionKey& key = optionKeys()[i];
        const IntegratorOption& option = *key.option;
        const Action action = *optionKeyAction(i);
        EXPECT_EQ(actionForKeyName(std::string(1, key.key)), action) << option.json << " " << key.key;
        EXPECT_TRUE(isIntegratorAction(action));
        const std::string upper(1, char(std::toupper(static_cast<unsigned char>(key.key))));
        EXPECT_NE(keyHelp().find("\n  " + upper + " " + std::string(18, ' ') + option.preview.label), std::string::npos)
            << option.json << " key " << upper << " missing from:\n"
            << keyHelp();
        IntegratorSettings settings;
        settings.type = option.integrator;
        const double before = optionValue(option, settings);
        if (key.value >= 0) {
            const double wanted = option.values[size_t(key.value)].value;
            EXPECT_EQ(applyIntegratorAction(settings, action), wanted != before) << option.json;
            EXPECT_EQ(optionValue(option, settings), wanted) << option.json;
            EXPECT_FALSE(applyIntegratorAction(settings, action)) << option.json << ": already set";
        } else {
            EXPECT_TRUE(applyIntegratorAction(settings, action)) << option.json;
            const OptionValue* now = valueNumbered(option.values, uint32_t(before));
            ASSERT_NE(now, nullptr);
            const size_t next = size_t(now - option.values.data() + 1) % option.values.size();
            EXPECT_EQ(optionValue(option, settings), double(option.values[next].value)) << option.json;
            if (option.given) EXPECT_TRUE(settings.*option.given) << option.json << ": the header must list it";
        }
        IntegratorSettings other;
        other.type = option.integrator == IntegratorType::Direct ? IntegratorType::AmbientOcclusion
                                                                 : IntegratorType::Direct;
        EXPECT_FALSE(applyIntegratorAction(other, action)) << option.json << " on another integrator";
    }
    EXPECT_FALSE(optionKeyAction(optionKeys().size()).has_value());
}

// ---- The program, with and without a display ---------------------------------------------

namespace {

std::string slurp(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

std::string sceneFile(const std::string& name) { return std::string(PENUMBRA_SOURCE_DIR) + "/scenes/" + name; }

// A directory of its own under build/test-output/ for one test's files (P saves land in
// the working directory).
fs::path freshDir(const std::string& name) {
    fs::path dir = test::outputPath("preview-" + name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

// Runs penumbra in `dir` with `env` prefixed (e.g. "DISPLAY=:3"), at most two minutes;
// stderr goes to `err`. Returns the exit status (124 when it timed out).
int runIn(const fs::path& dir, const std::string& env, const std::string& args, std::string* err) {
    fs::path errPath = dir / "stderr.txt";
    std::string cmd = "cd '" + dir.string() + "' && " + env + " timeout 120 '" + PENUMBRA_EXECUTABLE + "' " + args +
                      " >'" + (dir / "stdout.txt").string() + "' 2>'" + errPath.string() + "'";
    int status = std::system(cmd.c_str());
    if (err) *err = slurp(errPath);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// Finds an executable on PATH.
std::string onPath(const std::string& name) {
    const char* path = std::getenv("PATH");
    std::stringstream dirs(path ? path : "/usr/bin:/bin");
    for (std::string dir; std::getline(dirs, dir, ':');) {
        fs::path candidate = fs::path(dir.empty() ? "." : dir) / name;
        if (access(candidate.c_str(), X_OK) == 0) return candidate.string();
    }
    return {};
}

// An Xvfb server for this test process on a display number it picks itself (-displayfd),
// so parallel tests never collide; killed (by its pid) when the process ends.
class Xvfb {
public:
    static Xvfb& instance() {
        static Xvfb server;
        return server;
    }
    bool available() const { return !m_display.empty(); }
    const std::string& display() const { return m_display; }
    const std::string& problem() const { return m_problem; }
    ~Xvfb() {
        if (m_pid > 0) {
            kill(m_pid, SIGTERM);
            waitpid(m_pid, nullptr, 0);
        }
    }

private:
    Xvfb() {
        std::string binary = onPath("Xvfb");
        if (binary.empty()) {
            m_problem = "Xvfb is not installed (Debian package xvfb; tools/setup installs it)";
            return;
        }
        int fds[2];
        if (pipe(fds) != 0) {
            m_problem = "pipe() failed";
            return;
        }
        m_pid = fork();
        if (m_pid == 0) {
            prctl(PR_SET_PDEATHSIG, SIGTERM);  // never outlive the test
            close(fds[0]);
            std::string fd = std::to_string(fds[1]);
            std::string log = test::outputPath("xvfb.log").string();
            if (FILE* f = std::freopen(log.c_str(), "w", stderr)) (void)f;
            execl(binary.c_str(), "Xvfb", "-displayfd", fd.c_str(), "-screen", "0", "1024x768x24", "-nolisten", "tcp",
                  static_cast<char*>(nullptr));
            _exit(127);
        }
        close(fds[1]);
        std::string number;
        pollfd pfd{fds[0], POLLIN, 0};
        while (number.find('\n') == std::string::npos && poll(&pfd, 1, 15000) > 0) {
            char buffer[16];
            ssize_t n = read(fds[0], buffer, sizeof buffer);
            if (n <= 0) break;
            number.append(buffer, size_t(n));
        }
        close(fds[0]);
        if (number.find('\n') == std::string::npos) {
            m_problem = "Xvfb did not start within 15 s (see build/test-output/xvfb.log)";
            return;
        }
        m_display = ":" + number.substr(0, number.find('\n'));
    }

    pid_t m_pid = -1;
    std::string m_display;
    std::string m_problem;
};

#ifdef PENUMBRA_HAVE_GLFW
#define REQUIRE_PREVIEW_BUILD() (void)0
#else
#define REQUIRE_PREVIEW_BUILD() GTEST_SKIP() << "built without GLFW: penumbra has no preview"
#endif

#define REQUIRE_XVFB()                                                              \
    do {                                                                            \
        REQUIRE_PREVIEW_BUILD();                                                    \
        if (onPath("Xvfb").empty()) GTEST_SKIP() << Xvfb::instance().problem();     \
        ASSERT_TRUE(Xvfb::instance().available()) << Xvfb::instance().problem();   \
    } while (0)

std::string displayEnv() { return "env -u WAYLAND_DISPLAY DISPLAY=" + Xvfb::instance().display(); }

using test::Png;
using test::readPng;

int maxLevelDifference(const Png& a, const Png& b) {
    int worst = 0;
    for (size_t i = 0; i < a.pixels.size(); ++i) worst = std::max(worst, std::abs(int(a.pixels[i]) - int(b.pixels[i])));
    return worst;
}

// The Cornell box, small and quick: 64 x 48 pixels, 16 spp.
std::string smallCornell() {
    std::string args = "'";
    args += sceneFile("cornell.json");
    args += "' --width 64 --height 48 --spp 16";
    return args;
}

}  // namespace

TEST(PreviewProgram, NoDisplayExitsOneWithOneLine) {
    REQUIRE_PREVIEW_BUILD();
    fs::path dir = freshDir("no-display");
    std::string err;
    int status = runIn(dir, "env -u DISPLAY -u WAYLAND_DISPLAY", "preview " + smallCornell(), &err);
    EXPECT_EQ(status, 1) << err;
    ASSERT_FALSE(err.empty());
    EXPECT_EQ(err.find('\n'), err.size() - 1) << "not one line: " << err;
    EXPECT_NE(err.find("display"), std::string::npos) << err;
    // render never touches the window system.
    status = runIn(dir, "env -u DISPLAY -u WAYLAND_DISPLAY", "render " + smallCornell() + " -o r.exr --quiet", &err);
    EXPECT_EQ(status, 0) << err;
}

TEST(PreviewProgram, UnreachableDisplayExitsOneWithOneLine) {
    REQUIRE_PREVIEW_BUILD();
    fs::path dir = freshDir("bad-display");
    std::string err;
    int status = runIn(dir, "env -u WAYLAND_DISPLAY DISPLAY=:9999", "preview " + smallCornell(), &err);
    EXPECT_EQ(status, 1) << err;
    ASSERT_FALSE(err.empty());
    EXPECT_EQ(err.find('\n'), err.size() - 1) << "not one line: " << err;
}

TEST(PreviewProgram, BadScriptExitsTwoNamingFileAndLine) {
    fs::path dir = freshDir("bad-script");
    std::ofstream(dir / "bad.script") << "frame 1 key 2\nframe 2 wiggle\n";
    std::string err;
    int status = runIn(dir, "env -u DISPLAY -u WAYLAND_DISPLAY", "preview " + smallCornell() + " --script bad.script", &err);
    EXPECT_EQ(status, 2) << err;
    EXPECT_NE(err.find("bad.script:2:"), std::string::npos) << err;
}

TEST(PreviewProgram, ScreenshotMatchesRenderPng) {
    REQUIRE_XVFB();
    fs::path dir = freshDir("screenshot");
    std::string err;
    // Adaptive frame budget: converges within a few frames at this size.
    int status = runIn(dir, displayEnv(), "preview " + smallCornell() + " --frames 200 --screenshot shown.png", &err);
    ASSERT_EQ(status, 0) << err;
    EXPECT_NE(err.find("preview: 16/16 spp"), std::string::npos) << err;
    status = runIn(dir, "", "render " + smallCornell() + " -o rendered.exr --png rendered.png --quiet", &err);
    ASSERT_EQ(status, 0) << err;
    Png shown = readPng(dir / "shown.png"), rendered = readPng(dir / "rendered.png");
    ASSERT_EQ(shown.width, 64);
    ASSERT_EQ(shown.height, 48);
    ASSERT_EQ(rendered.pixels.size(), shown.pixels.size());
    // Same sums (same samples, same order); only the GPU's pow and division may differ.
    EXPECT_LE(maxLevelDifference(shown, rendered), 1) << "see " << dir;
}

// The A key (docs/guide/preview.md): once, the first AOV as layerPixels pictures the
// render's layer (the same sums, pictured on the host); three times with two AOVs, back to
// the tone-mapped image.
TEST(PreviewProgram, LayerKeyShowsEachAovThenTheImageAgain) {
    REQUIRE_XVFB();
    fs::path dir = freshDir("screenshot-layers");
    const std::string scene = smallCornell() + " --aov depth,shape_id";
    std::ofstream(dir / "once.script") << "frame 1 key a\n";
    std::ofstream(dir / "thrice.script") << "frame 1 key a\nframe 2 key a\nframe 3 key a\n";
    std::string err;
    ASSERT_EQ(runIn(dir, displayEnv(), "preview " + scene + " --script once.script --frames 200 --screenshot depth.png",
                    &err),
              0)
        << err;
    ASSERT_EQ(runIn(dir, displayEnv(), "preview " + scene + " --script thrice.script --frames 200 --screenshot rgb.png",
                    &err),
              0)
        << err;
    ASSERT_EQ(runIn(dir, "", "render " + scene + " -o rendered.exr --png rendered.png --quiet", &err), 0) << err;
    const Image rendered = readExr(dir / "rendered.exr");
    const std::vector<uint32_t> packed = layerPixels(rendered, "depth");
    Png depth = readPng(dir / "depth.png");
    ASSERT_EQ(depth.pixels.size(), packed.size() * 3);
    int worst = 0;
    for (size_t i = 0; i < packed.size(); ++i)
        for (int c = 0; c < 3; ++c)
            worst = std::max(worst, std::abs(int(depth.pixels[3 * i + c]) - int((packed[i] >> (8 * c)) & 0xff)));
    // The preview renders the same samples in another dispatch shape: its sums may differ in
    // the last float bits, which can move a depth by one code.
    EXPECT_LE(worst, 1) << "see " << dir;
    Png rgb = readPng(dir / "rgb.png"), png = readPng(dir / "rendered.png");
    ASSERT_EQ(rgb.pixels.size(), png.pixels.size());
    EXPECT_LE(maxLevelDifference(rgb, png), 1) << "see " << dir;
    EXPECT_GT(maxLevelDifference(rgb, depth), 64) << "the depth picture is not the image";
}

TEST(PreviewProgram, ExposureAndTonemapOptionsMatchRenderPng) {
    REQUIRE_XVFB();
    fs::path dir = freshDir("screenshot-tonemap");
    const std::string look = " --exposure 1.5 --tonemap filmic";
    std::string err;
    int status =
        runIn(dir, displayEnv(), "preview " + smallCornell() + look + " --frames 200 --screenshot shown.png", &err);
    ASSERT_EQ(status, 0) << err;
    EXPECT_NE(err.find("preview: 16/16 spp"), std::string::npos) << err;
    status = runIn(dir, "", "render " + smallCornell() + look + " -o looked.png --quiet", &err);
    ASSERT_EQ(status, 0) << err;
    status = runIn(dir, "", "render " + smallCornell() + " -o plain.png --quiet", &err);
    ASSERT_EQ(status, 0) << err;
    Png shown = readPng(dir / "shown.png"), looked = readPng(dir / "looked.png"), plain = readPng(dir / "plain.png");
    ASSERT_EQ(looked.pixels.size(), shown.pixels.size());
    ASSERT_EQ(plain.pixels.size(), shown.pixels.size());
    // The GPU's curve is the host's (within the GPU's pow and division), and it shows.
    EXPECT_LE(maxLevelDifference(shown, looked), 1) << "see " << dir;
    EXPECT_GT(maxLevelDifference(shown, plain), 16) << "see " << dir;
}

// The preview of `scene` (a file in `dir`) matches `penumbra render` of it within one level
// (same samples in the same order; only the GPU's pow and division may differ), and differs
// by more than 64 levels somewhere from the render of `without`, the same scene without the
// feature under test: the feature shows in the preview, not merely in neither image.
void expectPreviewAsRendered(const fs::path& dir, const std::string& scene, const std::string& without) {
    std::string err;
    int status = runIn(dir, displayEnv(), "preview " + scene + " --frames 200 --screenshot shown.png", &err);
    ASSERT_EQ(status, 0) << err;
    status = runIn(dir, "", "render " + scene + " -o rendered.exr --png rendered.png --quiet", &err);
    ASSERT_EQ(status, 0) << err;
    status = runIn(dir, "", "render " + without + " -o without.exr --png without.png --quiet", &err);
    ASSERT_EQ(status, 0) << err;
    Png shown = readPng(dir / "shown.png"), rendered = readPng(dir / "rendered.png"),
        control = readPng(dir / "without.png");
    ASSERT_EQ(rendered.pixels.size(), shown.pixels.size());
    EXPECT_LE(maxLevelDifference(shown, rendered), 1) << "see " << dir;
    ASSERT_EQ(control.pixels.size(), shown.pixels.size());
    EXPECT_GT(maxLevelDifference(shown, control), 64) << "see " << dir;
}

TEST(PreviewProgram, TexturedModelShowsItsTextureAsRendered) {
    REQUIRE_XVFB();
    fs::path dir = freshDir("screenshot-textured");
    // A pbr quad whose base colour is the glTF sample logo (assimp-testmodels, tools/setup).
    fs::copy_file("/usr/share/assimp/models/glTF2/BoxTextured-glTF/CesiumLogoFlat.png", dir / "logo.png");
    auto writeScene = [&](const std::string& file, const std::string& baseColor) {
        std::ofstream(dir / file) << R"({
            "camera": {"eye": [0, 3, 3], "target": [0, 0, 0], "up": [0, 1, 0], "fov_y": 40},
            "film": {"width": 64, "height": 48}, "sampler": {"spp": 4},
            "materials": {"m": {"type": "pbr", "base_color": )"
                                  << baseColor << R"(, "roughness": 0.6}},
            "shapes": [{"type": "quad", "origin": [-1, 0, -1], "edge_u": [2, 0, 0], "edge_v": [0, 0, 2],
                        "material": "m"}],
            "lights": [{"type": "environment", "radiance": 1}]})";
    };
    writeScene("textured.json", R"({"texture": "logo.png"})");
    writeScene("untextured.json", "[1, 1, 1]");  // what the texture's scale alone would give
    // The logo shows: the preview is far from the quad without its texture.
    expectPreviewAsRendered(dir, "textured.json", "untextured.json");
}

TEST(PreviewProgram, EnvironmentMapShowsInTheBackgroundAsRendered) {
    REQUIRE_XVFB();
    fs::path dir = freshDir("screenshot-environment");
    // A 16 x 8 sky whose columns change hue and whose rows darken towards the ground, behind
    // a diffuse sphere it lights: camera rays that escape must read the map in the preview too.
    Image map;
    map.width = 16;
    map.height = 8;
    for (uint32_t row = 0; row < map.height; ++row)
        for (uint32_t col = 0; col < map.width; ++col) {
            float fade = 1.0f - float(row) / float(map.height);
            map.rgb.insert(map.rgb.end(), {fade * float(col % 4) / 3.0f, fade * float(col >> 2u) / 3.0f, 0.8f * fade});
        }
    writeExr(dir / "sky.exr", map);
    auto writeScene = [&](const std::string& file, const std::string& environment) {
        std::ofstream(dir / file) << R"({
            "camera": {"eye": [0, 0.5, 3], "target": [0, 0.8, 0], "up": [0, 1, 0], "fov_y": 70},
            "film": {"width": 64, "height": 48}, "sampler": {"spp": 4},
            "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 0.6}],
            "lights": [)" << environment
                                  << "]}";
    };
    writeScene("mapped.json", R"({"type": "environment", "file": "sky.exr"})");
    writeScene("constant.json", R"({"type": "environment", "radiance": 0.5})");
    // The map shows: the preview is far from the same scene under a constant sky.
    expectPreviewAsRendered(dir, "mapped.json", "constant.json");
}

TEST(PreviewProgram, StrategyKeyRestartsAccumulation) {
    REQUIRE_XVFB();
    fs::path dir = freshDir("strategy-key");
    std::ofstream(dir / "keys.script") << "frame 10 key 2   # bsdf: restart, frames 10.. add samples 0..\n"
                                          "frame 20 key p   # save before frame 20 renders: 10 spp\n";
    std::string err;
    // One pass per frame: frame N adds one sample, so the counts below are exact.
    int status = runIn(dir, displayEnv(),
                       "preview " + smallCornell() + " --rows-per-frame 48 --frames 20 --script keys.script", &err);
    ASSERT_EQ(status, 0) << err;
    EXPECT_NE(err.find("preview: 11/16 spp"), std::string::npos) << err;  // not 16/16: restarted at frame 10
    ASSERT_TRUE(fs::exists(dir / "cornell-preview-1.exr")) << err;
    ASSERT_TRUE(fs::exists(dir / "cornell-preview-1.png")) << err;
    EXPECT_NE(err.find("cornell-preview-1.exr"), std::string::npos) << err;
    Image saved = readExr(dir / "cornell-preview-1.exr");
    EXPECT_EQ(saved.meta.spp.value_or(-1), 10);
    EXPECT_NE(saved.meta.integrator.value_or("").find("\"strategy\":\"bsdf\""), std::string::npos)
        << saved.meta.integrator.value_or("");
}

TEST(PreviewProgram, LightSelectionKeyRebuildsAndRestarts) {
    REQUIRE_XVFB();
    fs::path dir = freshDir("light-selection-key");
    std::ofstream(dir / "keys.script") << "frame 10 key l   # bvh: a new renderer, frames 10.. add samples 0..\n"
                                          "frame 20 key p   # save before frame 20 renders: 10 spp\n";
    std::string err;
    int status = runIn(dir, displayEnv(),
                       "preview " + smallCornell() + " --rows-per-frame 48 --frames 20 --script keys.script", &err);
    ASSERT_EQ(status, 0) << err;
    EXPECT_NE(err.find("preview: 11/16 spp"), std::string::npos) << err;
    ASSERT_TRUE(fs::exists(dir / "cornell-preview-1.exr")) << err;
    Image saved = readExr(dir / "cornell-preview-1.exr");
    EXPECT_EQ(saved.meta.spp.value_or(-1), 10);
    EXPECT_NE(saved.meta.integrator.value_or("").find("\"light_selection\":\"bvh\""), std::string::npos)
        << saved.meta.integrator.value_or("");
}

TEST(PreviewProgram, CameraDragRestartsAndResetRestoresTheSceneCamera) {
    REQUIRE_XVFB();
    fs::path dir = freshDir("camera-drag");
    std::ofstream(dir / "drag.script") << "frame 5 drag 40 0\nframe 12 key p\n";
    std::string err;
    int status = runIn(dir, displayEnv(),
                       "preview " + smallCornell() + " --rows-per-frame 48 --frames 12 --script drag.script "
                       "--screenshot moved.png", &err);
    ASSERT_EQ(status, 0) << err;
    EXPECT_NE(err.find("preview: 8/16 spp"), std::string::npos) << err;  // frames 5..12 after the restart
    EXPECT_EQ(readExr(dir / "cornell-preview-1.exr").meta.spp.value_or(-1), 7);

    // Orbit, pan, zoom, then R: back to the scene's camera, and converged to render's image.
    std::ofstream(dir / "reset.script") << "frame 2 drag 30 10\nframe 3 drag 5 5 right\nframe 4 scroll 2\n"
                                           "frame 5 key r\n";
    status = runIn(dir, displayEnv(),
                   "preview " + smallCornell() + " --rows-per-frame 48 --frames 30 --script reset.script "
                   "--screenshot reset.png", &err);
    ASSERT_EQ(status, 0) << err;
    EXPECT_NE(err.find("preview: 16/16 spp"), std::string::npos) << err;
    status = runIn(dir, "", "render " + smallCornell() + " -o rendered.exr --png rendered.png --quiet", &err);
    ASSERT_EQ(status, 0) << err;
    Png moved = readPng(dir / "moved.png"), reset = readPng(dir / "reset.png"), rendered = readPng(dir / "rendered.png");
    ASSERT_EQ(reset.pixels.size(), rendered.pixels.size());
    ASSERT_EQ(moved.pixels.size(), rendered.pixels.size());
    EXPECT_LE(maxLevelDifference(reset, rendered), 1);
    EXPECT_GT(maxLevelDifference(moved, rendered), 40) << "the drag did not move the camera";
}

TEST(PreviewProgram, ResizeAndExposureKeepRunning) {
    REQUIRE_XVFB();
    fs::path dir = freshDir("resize");
    std::ofstream(dir / "resize.script") << "frame 2 resize 300 100\nframe 4 key +\nframe 5 key +\n"
                                            "frame 6 resize 90 400\nframe 8 key -\n";
    std::string err;
    int status = runIn(dir, displayEnv(),
                       "preview " + smallCornell() + " --frames 40 --script resize.script --screenshot bright.png",
                       &err);
    ASSERT_EQ(status, 0) << err;
    EXPECT_NE(err.find("preview: 16/16 spp"), std::string::npos) << err;  // exposure and size do not restart
    status = runIn(dir, "", "render " + smallCornell() + " -o rendered.exr --png rendered.png --quiet", &err);
    ASSERT_EQ(status, 0) << err;
    // The screenshot stays at the film's size, tone-mapped at the final exposure (+0.5).
    Png bright = readPng(dir / "bright.png"), rendered = readPng(dir / "rendered.png");
    ASSERT_EQ(bright.width, 64);
    ASSERT_EQ(bright.height, 48);
    double sumBright = 0, sumRendered = 0;
    for (size_t i = 0; i < bright.pixels.size(); ++i) {
        sumBright += bright.pixels[i];
        sumRendered += rendered.pixels[i];
    }
    EXPECT_GT(sumBright, sumRendered * 1.05);
}

// L cycles the light selection (the preview then builds a new Renderer: the light tables).
TEST(PreviewIntegratorKeys, LCyclesTheLightSelection) {
    EXPECT_EQ(*actionForKeyName("l"), Action::CycleLightSelection);
    EXPECT_NE(keyHelp().find("\n  L "), std::string::npos) << keyHelp();
    EXPECT_TRUE(isIntegratorAction(Action::CycleLightSelection));
    IntegratorSettings settings;  // power
    const LightSelection cycle[] = {LightSelection::Bvh, LightSelection::Uniform, LightSelection::Power};
    const char* names[] = {"bvh", "uniform", "power"};
    for (int i = 0; i < 3; ++i) {
        EXPECT_TRUE(applyIntegratorAction(settings, Action::CycleLightSelection));
        EXPECT_EQ(settings.lightSelection, cycle[i]);
        EXPECT_EQ(integratorJson(settings)["light_selection"], names[i]);
    }
    settings.lightSelection = LightSelection::Bvh;
    EXPECT_EQ(integratorLabel(settings), "mis power, spheres solid_angle, lights bvh");
}

TEST(PreviewIntegratorKeys, TAndMToggleQuadAndTriangleSampling) {
    EXPECT_EQ(*actionForKeyName("t"), Action::ToggleQuadSampling);
    EXPECT_EQ(*actionForKeyName("m"), Action::ToggleTriangleSampling);
    EXPECT_NE(keyHelp().find("\n  T "), std::string::npos) << keyHelp();
    EXPECT_NE(keyHelp().find("\n  M "), std::string::npos) << keyHelp();
    IntegratorSettings settings;  // quad solid_angle, triangle area
    EXPECT_TRUE(applyIntegratorAction(settings, Action::ToggleQuadSampling));
    EXPECT_EQ(settings.quadSampling, QuadSampling::Area);
    EXPECT_EQ(integratorJson(settings)["quad_sampling"], "area");
    EXPECT_TRUE(applyIntegratorAction(settings, Action::ToggleQuadSampling));
    EXPECT_EQ(settings.quadSampling, QuadSampling::SolidAngle);
    EXPECT_EQ(integratorJson(settings)["quad_sampling"], "solid_angle");
    EXPECT_TRUE(applyIntegratorAction(settings, Action::ToggleTriangleSampling));
    EXPECT_EQ(settings.triangleSampling, TriangleSampling::SolidAngle);
    EXPECT_EQ(integratorJson(settings)["triangle_sampling"], "solid_angle");
    EXPECT_TRUE(isIntegratorAction(Action::ToggleQuadSampling));
    EXPECT_TRUE(isIntegratorAction(Action::ToggleTriangleSampling));
}
