// Kernels as shader objects on lavapipe (gpu/shader_objects.h): compiled once, then taken
// back from disk by later processes (gpu/kernel_binaries.h), a damaged binary compiled anew,
// and the image the same bit for bit whether a kernel is a pipeline, a shader object compiled
// from SPIR-V or one taken from disk.
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gpu/kernel.h"
#include "gpu_fixture.h"
#include "render/renderer.h"
#include "render_helpers.h"
#include "test_scenes.h"

using namespace penumbra;
namespace fs = std::filesystem;

namespace {

// Points the kernel binaries at `folder` for the scope.
class ScopedKernelCache {
public:
    explicit ScopedKernelCache(const fs::path& folder) {
        if (const char* old = std::getenv("PENUMBRA_KERNEL_CACHE")) m_old = old;
        setenv("PENUMBRA_KERNEL_CACHE", folder.c_str(), 1);
    }
    ~ScopedKernelCache() {
        m_old ? setenv("PENUMBRA_KERNEL_CACHE", m_old->c_str(), 1) : unsetenv("PENUMBRA_KERNEL_CACHE");
    }

private:
    std::optional<std::string> m_old;
};

const std::vector<VkDescriptorType> kSmokeBindings = {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER};

std::shared_ptr<gpu::Pipeline> smokePipeline() {
    return std::make_shared<gpu::Pipeline>(test::gpuContext(), "tests/smoke", kSmokeBindings, 8);
}

// The smoke kernel on `pipeline` still computes (gpu_fixture.h).
bool kernelWorks(const std::shared_ptr<gpu::Pipeline>& pipeline) {
    gpu::Kernel kernel(test::gpuContext(), pipeline);
    return test::smokeKernelComputes(kernel, 5);
}

std::vector<fs::path> binaryFiles(const fs::path& folder) {
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(folder))
        if (entry.path().extension() == ".bin") files.push_back(entry.path());
    return files;
}

bool shaderObjectsHere() { return test::gpuContext().shaderObjects() != nullptr; }

bool sameImage(const Image& a, const Image& b) { return a.width == b.width && a.height == b.height && a.rgb == b.rgb; }

}  // namespace

TEST(ShaderObjects, LavapipeWithTheFeatureMakesKernelsShaderObjects) {
    const gpu::DeviceInfo& info = test::gpuContext().info();
    EXPECT_EQ(shaderObjectsHere(), info.driverName == "llvmpipe" && info.shaderObject) << info.driverInfo;
    auto pipeline = smokePipeline();
    EXPECT_EQ(pipeline->shader() != VK_NULL_HANDLE, shaderObjectsHere());
    EXPECT_EQ(pipeline->handle() != VK_NULL_HANDLE, !shaderObjectsHere());
    EXPECT_TRUE(kernelWorks(pipeline));
}

TEST(ShaderObjects, AKernelIsCompiledOnceThenTakenFromDisk) {
    if (!shaderObjectsHere()) GTEST_SKIP() << "kernels are pipelines on this device";
    const fs::path folder = test::freshOutputDir("shader_objects", "once");
    ScopedKernelCache cache(folder);
    auto first = smokePipeline();
    EXPECT_FALSE(first->fromDisk());
    ASSERT_EQ(binaryFiles(folder).size(), 1u);
    auto second = smokePipeline();
    EXPECT_TRUE(second->fromDisk());
    EXPECT_TRUE(kernelWorks(first));
    EXPECT_TRUE(kernelWorks(second));
}

TEST(ShaderObjects, ADamagedBinaryIsCompiledAnewAndReplaced) {
    if (!shaderObjectsHere()) GTEST_SKIP() << "kernels are pipelines on this device";
    const fs::path folder = test::freshOutputDir("shader_objects", "damaged");
    ScopedKernelCache cache(folder);
    smokePipeline();
    const auto files = binaryFiles(folder);
    ASSERT_EQ(files.size(), 1u);
    {
        // Flip the last bytes of the driver's binary (the key before it stays intact).
        std::fstream file(files[0], std::ios::in | std::ios::out | std::ios::binary);
        file.seekg(-16, std::ios::end);
        char tail[16];
        file.read(tail, 16);
        for (char& c : tail) c = char(~c);
        file.seekp(-16, std::ios::end);
        file.write(tail, 16);
    }
    auto rebuilt = smokePipeline();
    EXPECT_FALSE(rebuilt->fromDisk());
    EXPECT_TRUE(kernelWorks(rebuilt));
    auto again = smokePipeline();  // the damaged file was replaced
    EXPECT_TRUE(again->fromDisk());
    EXPECT_TRUE(kernelWorks(again));
}

TEST(ShaderObjects, PipelineCompiledAndFromDiskKernelsRenderTheSameImage) {
    if (!shaderObjectsHere()) GTEST_SKIP() << "kernels are pipelines on this device";
    // MIS over a quad light with a sphere: most of the direct kernel's code runs. Options
    // away from the kernel's defaults, so that a kernel that lost its constants would differ.
    nlohmann::json doc = test::litFloorOnOddFilmScene(4, 7);
    doc["integrator"] = {{"type", "direct"},
                         {"strategy", "mis"},
                         {"heuristic", "balance"},
                         {"light_samples", 2},
                         {"quad_sampling", "area"}};
    doc["shapes"].push_back({{"type", "sphere"}, {"center", {0.5, 0.4, 0}}, {"radius", 0.4}});
    const Scene scene = test::sceneFromJson(doc, "shader_objects_same_image");
    const fs::path folder = test::freshOutputDir("shader_objects", "same_image");
    ScopedKernelCache cache(folder);

    gpu::ContextOptions pipelinesOnly;
    pipelinesOnly.shaderObjects = false;
    gpu::Context pipelineContext(pipelinesOnly);
    ASSERT_EQ(pipelineContext.shaderObjects(), nullptr);
    Renderer asPipeline(pipelineContext, scene);
    asPipeline.renderAll();
    const Image reference = asPipeline.readback(0.0);
    ASSERT_GT(*std::max_element(reference.rgb.begin(), reference.rgb.end()), 0.0f);  // not black
    EXPECT_TRUE(binaryFiles(folder).empty());                                        // pipelines store nothing

    const Image compiled = test::renderScene(scene);
    EXPECT_FALSE(binaryFiles(folder).empty());
    const Image fromDisk = test::renderScene(scene);
    EXPECT_TRUE(sameImage(reference, compiled));
    EXPECT_TRUE(sameImage(reference, fromDisk));
}
