// Specialization of the render kernels (render/kernel_options.h): the scene-feature bits,
// the pipeline switch when integrator options change, and the ray counter used by the
// benchmarks, on scenes whose ray counts are known exactly.
#include <gtest/gtest.h>

#include "gpu_fixture.h"
#include "render/renderer.h"
#include "render_helpers.h"

using namespace penumbra;
using nlohmann::json;

namespace {

// A camera looking straight down on a plane that fills the view (or, with `sky`, straight
// up at nothing); AO with cosine samples.
json planeScene(bool sky) {
    json camera = test::topDownCamera(0.0, 0.0, 1.0);
    if (sky) camera = {{"eye", {0, 1, 0}}, {"target", {0, 2, 0}}, {"up", {0, 0, 1}}, {"fov_y", 40}};
    return {
        {"camera", camera},
        {"film", {{"width", 24}, {"height", 16}}},
        {"sampler", {{"spp", 4}, {"seed", 3}}},
        {"integrator", {{"type", "ao"}, {"sampling", "cosine"}}},
        {"shapes", {{{"type", "quad"}, {"origin", {-50, 0, -50}}, {"edge_u", {0, 0, 100}}, {"edge_v", {100, 0, 0}}}}},
    };
}

}  // namespace

TEST(KernelOptions, SceneFeaturesListWhatTheSceneHolds) {
    json doc = planeScene(false);
    doc["materials"] = {{"shiny", {{"type", "phong"}, {"kd", 0.2}, {"ks", 0.5}, {"exponent", 20}}}};
    doc["shapes"].push_back({{"type", "sphere"}, {"center", {0, 1, 0}}, {"radius", 0.5}, {"emission", 1.0}});
    doc["shapes"][0]["material"] = "shiny";
    doc["lights"] = {{{"type", "point"}, {"position", {0, 3, 0}}, {"power", 10}}};
    Scene scene = test::sceneFromJson(doc, "features");
    uint32_t bits = sceneFeatures(buildSceneArrays(scene));
    uint32_t expected = (1u << (FEATURE_PRIMITIVE + gpu::PRIM_QUAD)) | (1u << (FEATURE_PRIMITIVE + gpu::PRIM_SPHERE)) |
                        (1u << (FEATURE_LIGHT + gpu::LIGHT_SPHERE)) | (1u << (FEATURE_LIGHT + gpu::LIGHT_POINT)) |
                        (1u << (FEATURE_MATERIAL + gpu::MATERIAL_PHONG));
    // Materials may include a default diffuse one for shapes without a material.
    EXPECT_EQ(bits & ~(1u << (FEATURE_MATERIAL + gpu::MATERIAL_DIFFUSE)), expected);
    EXPECT_EQ(makeKernelOptions(scene, buildSceneArrays(scene)).specialization().size(), size_t(SPEC_COUNT));
    // Two lights above; without the point light, the sphere is the only one.
    doc.erase("lights");
    const uint32_t single = sceneFeatures(buildSceneArrays(test::sceneFromJson(doc, "features")));
    EXPECT_EQ(single & ~(1u << (FEATURE_MATERIAL + gpu::MATERIAL_DIFFUSE)),
              (expected & ~(1u << (FEATURE_LIGHT + gpu::LIGHT_POINT))) | (1u << FEATURE_SINGLE_LIGHT));
}

TEST(KernelOptions, ChangingTheIntegratorOptionsChangesTheImage) {
    // Uniform and cosine AO differ sample by sample: if setIntegrator kept the old
    // specialized kernel, the two renders would be identical.
    Scene scene = test::sceneFromJson(planeScene(false), "switch");
    scene.shapes.push_back(scene.shapes[0]);
    scene.shapes.back().type = ShapeType::Sphere;
    scene.shapes.back().center = {0, 0.3f, 0};
    scene.shapes.back().radius = 0.25f;
    Renderer renderer(test::gpuContext(), scene);
    renderer.renderAll();
    Image cosine = renderer.readback(0.0);
    IntegratorSettings uniform = scene.integrator;
    uniform.aoSampling = AoSampling::Uniform;
    renderer.setIntegrator(uniform);
    renderer.reset();
    renderer.renderAll();
    Image uniformImage = renderer.readback(0.0);
    EXPECT_NE(cosine.rgb, uniformImage.rgb);
    renderer.setIntegrator(scene.integrator);
    renderer.reset();
    renderer.renderAll();
    EXPECT_EQ(renderer.readback(0.0).rgb, cosine.rgb);
}

TEST(KernelOptions, RayCounterCountsCameraAndOcclusionRays) {
    // Every camera ray hits the plane and every cosine sample leaves it: two rays per
    // sample. Looking at the empty sky: only the camera ray.
    const uint64_t pixels = 24 * 16, passes = 3;
    Renderer plane(test::gpuContext(), test::sceneFromJson(planeScene(false), "plane"));
    EXPECT_EQ(plane.countRays(passes), 2 * pixels * passes);
    Renderer sky(test::gpuContext(), test::sceneFromJson(planeScene(true), "sky"));
    EXPECT_EQ(sky.countRays(passes), pixels * passes);
    // Counting runs its own kernel: the render kernel afterwards is the plain one and
    // produces the same image as a renderer that never counted.
    plane.reset();
    plane.renderAll();
    Renderer fresh(test::gpuContext(), test::sceneFromJson(planeScene(false), "plane"));
    fresh.renderAll();
    EXPECT_EQ(plane.readback(0.0).rgb, fresh.readback(0.0).rgb);
}

// render/node_reads.h: lavapipe before Mesa 25 reads nodes from texels, later ones through
// the buffer's device address where they can, everything else from the storage buffer; a
// driverInfo without a Mesa version counts as a later one.
TEST(NodeReads, DriverPicksWhereNodesComeFrom) {
    EXPECT_EQ(mesaMajorVersion("Mesa 22.3.6 (LLVM 15.0.6)"), 22);
    EXPECT_EQ(mesaMajorVersion("Mesa 25.0.7 (LLVM 15.0.6)"), 25);
    EXPECT_EQ(mesaMajorVersion("Mesa 100.1"), 100);
    EXPECT_EQ(mesaMajorVersion("Mesa devel"), 0);
    EXPECT_EQ(mesaMajorVersion("575.57.08"), 0);
    EXPECT_EQ(mesaMajorVersion(""), 0);
    auto device = [](const std::string& driverName, const std::string& driverInfo, bool int64 = false,
                     bool address = false) {
        gpu::DeviceInfo info = test::deviceWithDriver(driverName, driverInfo);
        info.shaderInt64 = int64;
        info.bufferDeviceAddress = address;
        return info;
    };
    EXPECT_EQ(nodeReadsFor(device("llvmpipe", "Mesa 22.3.6 (LLVM 15.0.6)")), NODE_READS_TEXELS);
    EXPECT_EQ(nodeReadsFor(device("llvmpipe", "Mesa 22.3.6 (LLVM 15.0.6)", true)), NODE_READS_TEXELS);
    EXPECT_EQ(nodeReadsFor(device("llvmpipe", "Mesa 24.2.8-1 (LLVM 19.1.4)")), NODE_READS_TEXELS);
    EXPECT_EQ(nodeReadsFor(device("llvmpipe", "Mesa 25.0.7-2~bpo12+1 (LLVM 15.0.6)")), NODE_READS_STORAGE);
    EXPECT_EQ(nodeReadsFor(device("llvmpipe", "Mesa 25.0.7-2~bpo12+1 (LLVM 15.0.6)", true)), NODE_READS_STORAGE_32);
    EXPECT_EQ(nodeReadsFor(device("llvmpipe", "Mesa 25.0.7-2~bpo12+1 (LLVM 15.0.6)", true, true)), NODE_READS_ADDRESS);
    EXPECT_EQ(nodeReadsFor(device("llvmpipe", "Mesa 25.0.7-2~bpo12+1 (LLVM 15.0.6)", false, true)), NODE_READS_STORAGE)
        << "the address loads are 32 bytes wide: no shaderInt64, no address loads";
    EXPECT_EQ(nodeReadsFor(device("llvmpipe", "Mesa 22.3.6 (LLVM 15.0.6)", true, true)), NODE_READS_TEXELS);
    EXPECT_EQ(nodeReadsFor(device("llvmpipe", "", true, true)), NODE_READS_ADDRESS);
    EXPECT_EQ(nodeReadsFor(device("llvmpipe", "")), NODE_READS_STORAGE);
    EXPECT_EQ(nodeReadsFor(device("NVIDIA", "575.57.08")), NODE_READS_STORAGE);
    EXPECT_EQ(nodeReadsFor(device("NVIDIA", "575.57.08", true)), NODE_READS_STORAGE_32);
    EXPECT_EQ(nodeReadsFor(device("NVIDIA", "575.57.08", true, true)), NODE_READS_STORAGE_32)
        << "address loads are measured on lavapipe only";
    EXPECT_EQ(nodeReadsValue(NodeReads::Texels, device("NVIDIA", "575.57.08", true)), NODE_READS_TEXELS);
    EXPECT_EQ(nodeReadsValue(NodeReads::Storage, device("llvmpipe", "Mesa 22.3.6")), NODE_READS_STORAGE);
    EXPECT_EQ(nodeReadsValue(NodeReads::Storage, device("llvmpipe", "Mesa 25.0.7", true)), NODE_READS_STORAGE);
    EXPECT_EQ(nodeReadsValue(NodeReads::Storage32, device("llvmpipe", "Mesa 22.3.6", true)), NODE_READS_STORAGE_32);
    EXPECT_EQ(nodeReadsValue(NodeReads::Storage32, device("NVIDIA", "575.57.08")), NODE_READS_STORAGE)
        << "no 32-byte loads without shaderInt64";
    EXPECT_EQ(nodeReadsValue(NodeReads::Address, device("NVIDIA", "575.57.08", true, true)), NODE_READS_ADDRESS);
    EXPECT_EQ(nodeReadsValue(NodeReads::Address, device("NVIDIA", "575.57.08", true)), NODE_READS_STORAGE_32)
        << "no address loads without bufferDeviceAddress";
    EXPECT_EQ(nodeReadsValue(NodeReads::Address, device("NVIDIA", "575.57.08", false, true)), NODE_READS_STORAGE);
    EXPECT_EQ(nodeReadsValue(NodeReads::Device, device("llvmpipe", "Mesa 22.3.6")), NODE_READS_TEXELS);
    // The kernels that read nodes 32 bytes at a time are the "_int64" variants, through the
    // device address the "_address" ones.
    EXPECT_EQ(nodeReadsKernel("integrators/direct", NODE_READS_STORAGE_32), "integrators/direct_int64");
    EXPECT_EQ(nodeReadsKernel("integrators/ao", NODE_READS_ADDRESS), "integrators/ao_address");
    EXPECT_EQ(nodeReadsKernel("integrators/direct", NODE_READS_STORAGE), "integrators/direct");
    EXPECT_EQ(nodeReadsKernel("integrators/ao", NODE_READS_TEXELS), "integrators/ao");
}

// The node reads are the same bytes through different views: the same samples give the same
// image, bit for bit, on a scene traced through the BVH (not inline).
TEST(NodeReads, TexelsAndStorageGiveTheSameImage) {
    json doc = planeScene(false);
    for (int i = 0; i < 12; ++i)
        doc["shapes"].push_back({{"type", "sphere"},
                                 {"center", {-0.5 + 0.09 * i, 0.05 * (i % 3), 0.04 * i - 0.2}},
                                 {"radius", 0.04 + 0.01 * (i % 4)}});
    Scene scene = test::sceneFromJson(doc, "node-reads");
    auto render = [&](NodeReads mode) {
        Renderer renderer(test::gpuContext(), scene);
        renderer.setInlineGeometry(InlineGeometry::Off);
        renderer.setNodeReads(mode);
        renderer.renderAll();
        return renderer.readback(0.0);
    };
    const Image texels = render(NodeReads::Texels);
    size_t occluded = 0;
    for (float v : texels.rgb) occluded += v < 0.99f;
    EXPECT_GT(occluded, texels.rgb.size() / 20) << "the spheres should occlude part of the plane";
    // Storage32 is the 32-byte loads on the test device (lavapipe has shaderInt64), Address
    // those loads through the device address (it has bufferDeviceAddress).
    ASSERT_TRUE(test::gpuContext().info().shaderInt64) << "the test device should have shaderInt64";
    ASSERT_TRUE(test::gpuContext().info().bufferDeviceAddress) << "the test device should have bufferDeviceAddress";
    const std::pair<NodeReads, const char*> modes[] = {{NodeReads::Storage, "16-byte storage loads"},
                                                       {NodeReads::Storage32, "32-byte storage loads"},
                                                       {NodeReads::Address, "32-byte loads through the address"}};
    for (const auto& [mode, name] : modes) {
        const Image storage = render(mode);
        ASSERT_EQ(texels.rgb.size(), storage.rgb.size());
        size_t differing = 0;
        for (size_t i = 0; i < texels.rgb.size(); ++i) differing += texels.rgb[i] != storage.rgb[i];
        EXPECT_EQ(differing, 0u) << name;
    }
}
