// besideOutOfView (host/render/out_of_view.h): the primitive beside the tree whose test camera
// rays leave out. It must name one only where no camera ray can hit it: checked by tracing
// camera rays through the whole film, its edges and corners included, on the CPU.
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "bvh/intersect.h"
#include "render/out_of_view.h"
#include "render/probe_rays.h"
#include "render/scene_arrays.h"

using namespace penumbra;
using glm::vec3;

namespace {

// A grid of 200 small triangles around the origin (enough for primitives to go beside the
// tree), a large floor, and a quad light at height `lightY` over the scene.
Scene sceneWithLightAt(float lightY) {
    Scene scene;
    scene.materials.push_back(Material{});
    scene.film.width = 64;
    scene.film.height = 48;
    scene.camera.eye = vec3(0.0f, 1.0f, 5.0f);
    scene.camera.target = vec3(0.0f, 0.5f, 0.0f);
    Shape mesh;
    mesh.type = ShapeType::Mesh;
    for (int i = 0; i < 200; ++i) {
        const vec3 c(float(i % 20) * 0.1f - 1.0f, float(i - i % 20) * 0.005f, 0.0f);  // rows of 20
        const auto first = uint32_t(mesh.positions.size());
        mesh.positions.insert(mesh.positions.end(), {c, c + vec3(0.05f, 0.0f, 0.0f), c + vec3(0.0f, 0.05f, 0.0f)});
        mesh.indices.insert(mesh.indices.end(), {first, first + 1, first + 2});
    }
    Shape floor;
    floor.type = ShapeType::Quad;
    floor.origin = vec3(-20.0f, 0.0f, -20.0f);
    floor.edgeU = vec3(0.0f, 0.0f, 40.0f);
    floor.edgeV = vec3(40.0f, 0.0f, 0.0f);
    Shape light;
    light.type = ShapeType::Quad;
    light.origin = vec3(-0.5f, lightY, -0.5f);
    light.edgeU = vec3(1.0f, 0.0f, 0.0f);
    light.edgeV = vec3(0.0f, 0.0f, 1.0f);
    light.emission = vec3(5.0f);
    scene.shapes = {mesh, floor, light};
    return scene;
}

// The beside primitive that is the light (its only emitter).
uint32_t lightPrimitive(const SceneArrays& arrays) {
    const Bvh& bvh = arrays.bvh;
    for (uint32_t k = 0; k < bvh.besideCount; ++k)
        if (bvh.primitives[bvh.besideFirst() + k].light != gpu::NO_LIGHT) return bvh.besideFirst() + k;
    return gpu::NO_HIT;
}

// How many camera rays, on a grid over the film that includes its edges, hit `primitive`.
int cameraRaysHitting(const gpu::RenderParams& params, const gpu::Primitive& primitive) {
    int hits = 0;
    constexpr int kSteps = 256;
    for (int i = 0; i <= kSteps; ++i)
        for (int j = 0; j <= kSteps; ++j) {
            const glm::vec2 film(float(i) / kSteps, float(j) / kSteps);
            float t;
            glm::vec2 uv;
            hits += intersectPrimitive(primitive, params.eye, cameraRayDirection(params, film), 3.4e38f, t, uv);
        }
    return hits;
}

}  // namespace

TEST(OutOfView, ALightAboveTheViewIsLeftOutOfCameraRays) {
    const Scene scene = sceneWithLightAt(4.0f);
    const SceneArrays arrays = buildSceneArrays(scene);
    ASSERT_EQ(arrays.bvh.besideCount, 2u) << "the floor and the light go beside the tree";
    const gpu::RenderParams params = makeRenderParams(scene, arrays);
    const uint32_t light = lightPrimitive(arrays);
    ASSERT_NE(light, gpu::NO_HIT);
    EXPECT_EQ(params.cameraOutOfView, light);
    EXPECT_EQ(cameraRaysHitting(params, arrays.bvh.primitives[light]), 0);
}

TEST(OutOfView, APrimitiveInViewIsTested) {
    // At height 1.6 the light is in the top of the view: camera rays hit it.
    const Scene scene = sceneWithLightAt(1.6f);
    const SceneArrays arrays = buildSceneArrays(scene);
    const gpu::RenderParams params = makeRenderParams(scene, arrays);
    const uint32_t light = lightPrimitive(arrays);
    ASSERT_NE(light, gpu::NO_HIT);
    EXPECT_GT(cameraRaysHitting(params, arrays.bvh.primitives[light]), 0);
    EXPECT_EQ(params.cameraOutOfView, gpu::NO_HIT) << "the floor and the light are both in view";
}

TEST(OutOfView, APrimitiveJustOutsideTheTopEdgeIsStillTested) {
    // The light's near edge lies on the view's top plane to within the margin: a ray through
    // the film's top edge passes within 1e-3 radians of it, so it is kept.
    Scene scene = sceneWithLightAt(4.0f);
    SceneArrays arrays = buildSceneArrays(scene);
    gpu::RenderParams params = makeRenderParams(scene, arrays);
    const vec3 top = cameraRayDirection(params, glm::vec2(0.5f, 0.0f));
    // The point 5 units along the top edge's ray, raised by 1e-4 of its distance: the
    // light's far edge, the quad reaching from there toward the camera (whose view's top
    // plane falls toward the eye).
    const vec3 edge = params.eye + 5.0f * top + vec3(0.0f, 5e-4f, 0.0f);
    scene.shapes[2].origin = vec3(-0.5f, edge.y, edge.z);
    arrays = buildSceneArrays(scene);
    params = makeRenderParams(scene, arrays);
    EXPECT_EQ(params.cameraOutOfView, gpu::NO_HIT);
    // Raised by a hundredth of its distance instead, it is left out, and no ray hits it.
    scene.shapes[2].origin.y = (params.eye + 5.0f * top).y + 0.05f;
    arrays = buildSceneArrays(scene);
    params = makeRenderParams(scene, arrays);
    EXPECT_EQ(params.cameraOutOfView, lightPrimitive(arrays));
    EXPECT_EQ(cameraRaysHitting(params, arrays.bvh.primitives[lightPrimitive(arrays)]), 0);
}

TEST(OutOfView, BehindTheCameraCountsAsOutOfView) {
    Scene scene = sceneWithLightAt(1.0f);
    scene.shapes[2].origin.z = 6.0f;  // behind the eye at z = 5, which looks toward -z
    const SceneArrays arrays = buildSceneArrays(scene);
    const gpu::RenderParams params = makeRenderParams(scene, arrays);
    EXPECT_EQ(params.cameraOutOfView, lightPrimitive(arrays));
    EXPECT_EQ(cameraRaysHitting(params, arrays.bvh.primitives[lightPrimitive(arrays)]), 0);
}

TEST(OutOfView, NonFiniteCameraLeavesNothingOut) {
    const Scene scene = sceneWithLightAt(4.0f);
    const SceneArrays arrays = buildSceneArrays(scene);
    gpu::RenderParams params = makeRenderParams(scene, arrays);
    params.tanHalfFovY = std::numeric_limits<float>::quiet_NaN();
    EXPECT_EQ(besideOutOfView(params, arrays.bvh), gpu::NO_HIT);
    params = makeRenderParams(scene, arrays);
    params.eye.x = std::numeric_limits<float>::infinity();
    EXPECT_EQ(besideOutOfView(params, arrays.bvh), gpu::NO_HIT);
}
