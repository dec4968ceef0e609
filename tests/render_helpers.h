// Test helpers that render scenes written inline as JSON, through the real loader and
// renderer on lavapipe, and statistics helpers for Monte Carlo tolerances.
#pragma once

#include <cmath>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include <nlohmann/json.hpp>

#include "image/image.h"
#include "scene/scene.h"

namespace penumbra::test {

// Writes `doc` to build/test-output/<name>.json and loads it as a scene.
Scene sceneFromJson(const nlohmann::json& doc, const std::string& name);
// Renders a loaded scene to an image (all of its spp).
Image renderScene(const Scene& scene);
inline Image renderJson(const nlohmann::json& doc, const std::string& name) {
    return renderScene(sceneFromJson(doc, name));
}

// A 1 x 1 partial render for the merge tests: `spp` samples (seed 0, sampler sobol) from
// sample `offset` on, whose rgb is `value`, with the AOV layers `aovs`.
inline Image onePixelPartial(int offset, int spp, float value, std::vector<AovLayer> aovs = {}) {
    Image image;
    image.width = image.height = 1;
    image.rgb = {value, value, value};
    image.meta.spp = spp;
    image.meta.seed = 0;
    image.meta.sampleOffset = offset;
    image.meta.sampler = "sobol";
    image.aovs = std::move(aovs);
    return image;
}

// Two-sided normal quantile for a per-test false-failure probability `alpha`, Bonferroni-
// corrected over `tests` tests: the z in |mean - expected| <= z * sigma / sqrt(N).
double zScore(double alpha, int tests);

// Student-t two-sided critical value for level alpha / tests with `dof` degrees of freedom.
double tCritical(double alpha, int tests, int dof);

// A camera that looks straight down (from height 50) on the square patch of the plane
// y = 0 centred at (cx, 0, cz) with half-size `half`, and `size` x `size` pixels.
nlohmann::json topDownCamera(double cx, double cz, double half);

// The expected image of a top-down view of y = 0 whose radiance at plane point x is L(x):
// L averaged over a sub x sub grid inside each pixel, with the renderer's camera basis.
// `jitterVariance`, if given, receives the variance of L over each pixel (the part of a
// pixel's sample variance that comes from spreading samples over the pixel).
std::vector<double> expectedTopDown(const Scene& scene, const std::function<double(glm::dvec3)>& L, int sub = 8,
                                    std::vector<double>* jitterVariance = nullptr);

// Unbiasedness check of an image against its expected values when the per-sample variance
// is unknown: the residuals are split into blocks of `block` x `block` pixels and each
// block's mean residual, and the whole image's, must pass a two-sided t-test at level
// alpha / ((blocks + 1) * tests).
// Returns the number of failing blocks; `report` receives the worst t statistic.
int blockTTest(const Image& image, const std::vector<double>& expected, int block, double alpha, int tests,
               std::string* report = nullptr);

// For each integrator object in `integrators`: `doc` rendered with it (a top-down view of
// y = 0, topDownCamera) passes blockTTest (8 x 8 blocks, level alpha over all of them)
// against radiance(x) at plane point x; a failing render is written beside the test output.
void expectTopDownMatches(const nlohmann::json& doc, const std::vector<nlohmann::json>& integrators,
                          const std::function<double(glm::dvec3)>& radiance, const std::string& name, double alpha);

// Irradiance at x (normal +y) from a polygon of constant radiance Le facing x, its vertices
// v in order (Lambert's formula; Arvo 1995): Le/2 |sum_i Theta_i (Gamma_i . n)|.
double polygonIrradiance(const std::vector<glm::dvec3>& v, glm::dvec3 x, double Le);

// Mean squared error of channel 0 against the expected values.
double meanSquaredError(const Image& image, const std::vector<double>& expected);

// Runs the penumbra executable with `args` (a shell-quoted string), capturing stderr into
// `err`; returns the exit status.
int runPenumbra(const std::string& args, std::string* err = nullptr, std::string* out = nullptr);
// The same under a wall-clock limit and an address-space limit, for inputs that once hung
// the program or exhausted its memory: `timeout` kills it after `seconds` (returned as -1,
// killed by a signal) and `ulimit -v` caps it at `memoryMiB`, so that a regression fails
// instead of stalling or swapping the test run.
int runPenumbraBounded(const std::string& args, int seconds, int memoryMiB, std::string* err = nullptr,
                       std::string* out = nullptr);
// The same for another executable of the build (e.g. PENUMBRA_FIGURE_EXECUTABLE).
int runProgram(const std::string& executable, const std::string& args, std::string* err = nullptr,
               std::string* out = nullptr);

}  // namespace penumbra::test
