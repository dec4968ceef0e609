// Test helpers (see render_helpers.h).
#include "render_helpers.h"

#include <sys/wait.h>
#include <unistd.h>
#include <algorithm>
#include <cstdio>
#include <fstream>

#include <gtest/gtest.h>

#include "gpu_fixture.h"
#include "render/renderer.h"
#include "render/scene_arrays.h"
#include "scene/load.h"

namespace penumbra::test {

Scene sceneFromJson(const nlohmann::json& doc, const std::string& name) {
    auto path = outputPath(name + ".json");
    std::ofstream(path) << doc.dump(2);
    return loadScene(path);
}

Image renderScene(const Scene& scene) {
    Renderer renderer(gpuContext(), scene);
    renderer.renderAll();
    return renderer.readback(0.0);
}

double zScore(double alpha, int tests) {
    // Invert the two-sided normal tail 2 (1 - Phi(z)) = alpha / tests by bisection on erfc.
    double target = alpha / tests, lo = 0.0, hi = 40.0;
    for (int i = 0; i < 200; ++i) {
        double mid = 0.5 * (lo + hi);
        (std::erfc(mid / std::sqrt(2.0)) > target ? lo : hi) = mid;
    }
    return hi;
}

double tCritical(double alpha, int tests, int dof) {
    // Two-sided tail of Student's t by Simpson integration of its density on [0, t].
    double nu = dof;
    double logNorm = std::lgamma((nu + 1) / 2) - std::lgamma(nu / 2) - 0.5 * std::log(nu * M_PI);
    auto density = [&](double x) { return std::exp(logNorm - (nu + 1) / 2 * std::log1p(x * x / nu)); };
    auto tail = [&](double t) {
        const int n = 4000;
        double h = t / n, sum = density(0) + density(t);
        for (int i = 1; i < n; ++i) sum += density(i * h) * (i % 2 ? 4 : 2);
        return 1.0 - 2.0 * sum * h / 3.0;  // P(|T| > t)
    };
    double target = alpha / tests, lo = 0.0, hi = 60.0;
    for (int i = 0; i < 100; ++i) {
        double mid = 0.5 * (lo + hi);
        (tail(mid) > target ? lo : hi) = mid;
    }
    return hi;
}

double polygonIrradiance(const std::vector<glm::dvec3>& v, glm::dvec3 x, double Le) {
    double sum = 0;
    for (size_t i = 0; i < v.size(); ++i) {
        glm::dvec3 a = glm::normalize(v[i] - x), b = glm::normalize(v[(i + 1) % v.size()] - x);
        double theta = std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0));
        sum += theta * glm::normalize(glm::cross(a, b)).y;
    }
    return 0.5 * Le * std::abs(sum);
}

nlohmann::json topDownCamera(double cx, double cz, double half) {
    double fov = 2.0 * std::atan(half / 50.0) * 180.0 / M_PI;
    return {{"eye", {cx, 50, cz}}, {"target", {cx, 0, cz}}, {"up", {0, 0, -1}}, {"fov_y", fov}};
}

std::vector<double> expectedTopDown(const Scene& scene, const std::function<double(glm::dvec3)>& L, int sub,
                                    std::vector<double>* jitterVariance) {
    SceneArrays arrays = buildSceneArrays(scene);
    gpu::RenderParams p = makeRenderParams(scene, arrays);
    const int w = int(scene.film.width), h = int(scene.film.height);
    std::vector<double> out(size_t(w) * h);
    if (jitterVariance) jitterVariance->assign(out.size(), 0.0);
    for (int py = 0; py < h; ++py)
        for (int px = 0; px < w; ++px) {
            double sum = 0, sum2 = 0;
            for (int j = 0; j < sub; ++j)
                for (int i = 0; i < sub; ++i) {
                    double fx = (px + (i + 0.5) / sub) / w, fy = (py + (j + 0.5) / sub) / h;
                    glm::dvec3 dir = glm::dvec3(p.forward) + ((2 * fx - 1) * p.aspect * p.tanHalfFovY) * glm::dvec3(p.right) +
                                     ((1 - 2 * fy) * p.tanHalfFovY) * glm::dvec3(p.up);
                    glm::dvec3 hit = glm::dvec3(p.eye) + dir * (-double(p.eye.y) / dir.y);
                    double v = L(hit);
                    sum += v;
                    sum2 += v * v;
                }
            double n = double(sub) * sub, mean = sum / n;
            out[size_t(py) * w + px] = mean;
            if (jitterVariance) (*jitterVariance)[size_t(py) * w + px] = std::max(0.0, sum2 / n - mean * mean);
        }
    return out;
}

int blockTTest(const Image& image, const std::vector<double>& expected, int block, double alpha, int tests,
               std::string* report) {
    const int w = int(image.width), h = int(image.height);
    const int bx = w / block, by = h / block, n = block * block;
    // One test per block, plus one over the whole image, which has the most power against a
    // bias of constant sign.
    double tc = tCritical(alpha, (bx * by + 1) * tests, n - 1), worst = 0;
    int failures = 0;
    {
        double sum = 0, sum2 = 0;
        const size_t all = size_t(bx) * block * by * block;
        for (int y = 0; y < by * block; ++y)
            for (int x = 0; x < bx * block; ++x) {
                size_t p = size_t(y) * w + x;
                double r = image.rgb[3 * p] - expected[p];
                sum += r;
                sum2 += r * r;
            }
        double mean = sum / all, var = (sum2 - all * mean * mean) / (all - 1);
        double t = var > 0 ? mean / std::sqrt(var / all) : (mean == 0 ? 0 : INFINITY);
        worst = std::abs(t);
        if (std::abs(t) > tc) ++failures;
    }
    for (int b = 0; b < bx * by; ++b) {
        double sum = 0, sum2 = 0;
        for (int j = 0; j < block; ++j)
            for (int i = 0; i < block; ++i) {
                size_t p = size_t((b / bx) * block + j) * w + (b % bx) * block + i;
                double r = image.rgb[3 * p] - expected[p];
                sum += r;
                sum2 += r * r;
            }
        double mean = sum / n, var = (sum2 - n * mean * mean) / (n - 1);
        double t = var > 0 ? mean / std::sqrt(var / n) : (mean == 0 ? 0 : INFINITY);
        worst = std::max(worst, std::abs(t));
        if (std::abs(t) > tc) ++failures;
    }
    if (report) {
        double residual = 0, total = 0;
        for (size_t p = 0; p < expected.size(); ++p) residual += image.rgb[3 * p] - expected[p], total += expected[p];
        *report = "worst |t| = " + std::to_string(worst) + ", critical " + std::to_string(tc) +
                  ", mean relative residual " + std::to_string(residual / total);
    }
    return failures;
}

void expectTopDownMatches(const nlohmann::json& doc, const std::vector<nlohmann::json>& integrators,
                          const std::function<double(glm::dvec3)>& radiance, const std::string& name, double alpha) {
    for (size_t i = 0; i < integrators.size(); ++i) {
        nlohmann::json d = doc;
        d["integrator"] = integrators[i];
        Scene scene = sceneFromJson(d, name + "-" + std::to_string(i));
        Image image = renderScene(scene);
        std::vector<double> expected = expectedTopDown(scene, radiance);
        std::string report;
        int failures = blockTTest(image, expected, 8, alpha, int(integrators.size()), &report);
        EXPECT_EQ(failures, 0) << name << " with " << integrators[i].dump() << ": " << report;
        if (failures) writeExr(outputPath(name + "-" + std::to_string(i) + ".exr"), image);
    }
}

double meanSquaredError(const Image& image, const std::vector<double>& expected) {
    double sum = 0;
    for (size_t p = 0; p < expected.size(); ++p) sum += std::pow(image.rgb[3 * p] - expected[p], 2);
    return sum / double(expected.size());
}

namespace {
std::string slurp(const std::string& path) {
    std::ifstream in(path);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

// Runs a shell command line with stdout and stderr captured; its exit status.
int runCommandLine(const std::string& commandLine, std::string* err, std::string* out) {
    // Per process: ctest runs tests in parallel processes that share test-output/.
    const std::string tag = std::to_string(getpid());
    auto errPath = outputPath("cli-stderr-" + tag + ".txt").string();
    auto outPath = outputPath("cli-stdout-" + tag + ".txt").string();
    std::string cmd = commandLine + " >'" + outPath + "' 2>'" + errPath + "'";
    int status = std::system(cmd.c_str());
    if (err) *err = slurp(errPath);
    if (out) *out = slurp(outPath);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

int runPenumbra(const std::string& args, std::string* err, std::string* out) {
    return runProgram(PENUMBRA_EXECUTABLE, args, err, out);
}

int runPenumbraBounded(const std::string& args, int seconds, int memoryMiB, std::string* err, std::string* out) {
    // The limits apply to the shell, then to what it execs (timeout, then penumbra).
    const std::string bounded = "ulimit -v " + std::to_string(int64_t(memoryMiB) * 1024) + "; exec timeout -s KILL " +
                                std::to_string(seconds) + " '" + PENUMBRA_EXECUTABLE + "'";
    return runCommandLine(bounded + " " + args, err, out);
}

int runProgram(const std::string& executable, const std::string& args, std::string* err, std::string* out) {
    return runCommandLine("'" + executable + "' " + args, err, out);
}

}  // namespace penumbra::test
