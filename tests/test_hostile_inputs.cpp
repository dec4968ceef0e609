// Hostile inputs against the image readers, job files and merge (README, "input rules"):
// each case once hung the program, exhausted its memory or gave a wrong result. Those that
// could hang or grow run `penumbra` as a child under a time and memory limit
// (runPenumbraBounded), so that a regression fails here instead of stalling the test run.
#include <cmath>
#include <cstring>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "gltf_builder.h"
#include "gpu_fixture.h"
#include "image/image.h"
#include "core/errors.h"
#include "scene/load.h"
#include "render_helpers.h"
#include "scene_test_util.h"

using nlohmann::json;
namespace fs = std::filesystem;

namespace {

void writeBytes(const fs::path& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
}

// A scene of one quad whose albedo is the texture `texture` (relative to the scene).
fs::path writeTexturedScene(const fs::path& dir, const std::string& texture) {
    json doc = {{"materials", {{"m", {{"type", "diffuse"}, {"albedo", {{"texture", texture}}}}}}},
                {"shapes",
                 {{{"type", "quad"}, {"origin", {0, 0, 0}}, {"edge_u", {1, 0, 0}}, {"edge_v", {0, 0, 1}}, {"material", "m"}}}},
                {"film", {{"width", 4}, {"height", 4}}},
                {"sampler", {{"spp", 1}}}};
    return penumbra::test::writeFile(dir / "scene.json", doc.dump());
}

std::string quoted(const fs::path& p) { return "'" + p.string() + "'"; }

}  // namespace

TEST(HostileInputs, HdrHeaderLineStartingWithNulIsRefusedNotHung) {
    // stb_image ends an HDR header at a line that starts with a NUL byte, so its pixel data
    // starts after the next line ("-Y 1 +X 16"): a run-length encoded scanline whose first
    // channel is a literal run of 16 that the file ends inside, after which stb reads zeros,
    // runs of length 0, forever. The 15 bytes it swallows are "\n\n", an empty line and a
    // valid scanline (runs of 16): what a check that looks for the first empty line found.
    const std::string valid = std::string("\x02\x02\x00\x10", 4) + std::string("\x90\x01\x90\x01\x90\x01\x90\x80", 8);
    const std::string hdr = std::string("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\0\n-Y 1 +X 16\n", 47) +
                            std::string("\x02\x02\x00\x10\x10", 5) + "\n\n\n" + valid;
    fs::path dir = penumbra::test::freshTempDir();
    writeBytes(dir / "nul.hdr", hdr);
    fs::path scene = writeTexturedScene(dir, "nul.hdr");
    std::string err;
    int status = penumbra::test::runPenumbraBounded(
        "render " + quoted(scene) + " -o " + quoted(dir / "out.exr") + " --quiet", 10, 2048, &err);
    EXPECT_EQ(status, 2) << err;
    EXPECT_NE(err.find("nul.hdr: cannot decode HDR image: "), std::string::npos) << err;
    EXPECT_FALSE(fs::exists(dir / "out.exr"));
}
