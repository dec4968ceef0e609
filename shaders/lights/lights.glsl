// Lights (lecture, "Light Sources"; SCENE_FORMAT.md): choosing a light, and the dispatch to
// each kind's sampler, density and emitted radiance (one file per kind: point.glsl,
// spot.glsl, directional.glsl, environment.glsl with environment_map.glsl, sphere.glsl, quad.glsl, mesh.glsl). Every pdf returned
// here is in SOLID ANGLE at the shading point x, for the given light alone (selection
// probability not included): area-measure densities are converted by areaToSolidAngle
// (light_sample.glsl) and nowhere else. Delta lights have no density: their samples carry
// isDelta.
#ifndef PENUMBRA_LIGHTS_GLSL
#define PENUMBRA_LIGHTS_GLSL

#include "shared/types.h"
#include "common/specialization.glsl"
#include "lights/light_data.glsl"
#include "lights/light_sample.glsl"
#include "lights/alias.glsl"
#include "lights/point.glsl"
#include "lights/spot.glsl"
#include "lights/directional.glsl"
#include "lights/environment.glsl"
#include "lights/sphere.glsl"
#include "lights/quad.glsl"
#include "lights/mesh.glsl"

// Picks a light from the selection (sub-)table at [offset, offset + count) with a 32-bit
// fraction; pmf is its probability within that table. `rest` is what is left of the
// fraction, uniform on [0,1) given the light chosen (alias.glsl, sampleAlias), for that
// light's sample.
uint selectLight(uint offset, uint count, uint bits, out float pmf, out float rest) {
    AliasEntry e = sampleAlias(offset, count, bits, false, rest);
    pmf = e.pmf;
    return e.item;
}

// Radiance leaving an emitter with front normal nFront toward a viewer in direction -wi
// (wi points from the viewer to the emitter).
vec3 emittedRadiance(Light light, vec3 nFront, vec3 wi) {
    if (lightIs(light, LIGHT_SPHERE)) return sphereEmittedRadiance(light);
    return polygonEmittedRadiance(light, nFront, wi);
}

// Samples a direction toward light `index` from x (shading normal n, used by the
// constant environment's cosine sampling). u: three uniform numbers; modes: how area lights are
// sampled. Returns false when the sample carries nothing (back side of a one-sided light,
// x inside a sphere light, ...).
bool sampleLight(uint index, vec3 x, vec3 n, vec3 u, LightSamplingModes modes, out LightSample ls) {
    Light light = loadLight(index);
    ls = emptyLightSample(n);
    if (lightIs(light, LIGHT_POINT)) return samplePointLight(light, x, ls);
    if (lightIs(light, LIGHT_SPOT)) return sampleSpotLight(light, x, ls);
    if (lightIs(light, LIGHT_DIRECTIONAL)) return sampleDirectionalLight(light, ls);
    if (lightIs(light, LIGHT_ENVIRONMENT)) return sampleEnvironmentLight(light, n, u, ls);
    if (lightIs(light, LIGHT_SPHERE)) return sampleSphereLight(light, x, u.xy, modes.sphere, ls);
    if (lightIs(light, LIGHT_QUAD)) return sampleQuadLight(light, x, u, modes, ls);
    if (lightIs(light, LIGHT_MESH)) return sampleMeshLight(light, x, u, modes, ls);
    return false;
}

// Density (solid angle, at x) with which sampleLight(index, x, n, ., modes) produces wi,
// given that the ray x + t wi first hits this light at y (geometric normal ny) at distance d,
// on primitive `primitive`; for the environment, y, ny, d and primitive are ignored. `quad`:
// a quad light's density at x where a light sample from x already knows it.
float lightPdf(uint index, vec3 x, vec3 n, vec3 wi, vec3 y, vec3 ny, float d, uint primitive, LightSamplingModes modes,
               KnownQuadDensity quad) {
    Light light = loadLight(index);
    if (lightIs(light, LIGHT_ENVIRONMENT)) return environmentPdf(light, n, wi);
    if (lightIs(light, LIGHT_POINT) || lightIs(light, LIGHT_SPOT) || lightIs(light, LIGHT_DIRECTIONAL)) return 0.0;
    if (lightIs(light, LIGHT_SPHERE)) return sphereLightPdf(light, x, y, ny, d, modes.sphere);
    if (lightIs(light, LIGHT_QUAD)) return quadLightPdf(light, x, wi, ny, d, modes, quad);
    if (lightIs(light, LIGHT_MESH)) return meshLightPdf(light, x, wi, ny, d, primitive, modes);
    return 0.0;
}

float lightPdf(uint index, vec3 x, vec3 n, vec3 wi, vec3 y, vec3 ny, float d, uint primitive, LightSamplingModes modes) {
    return lightPdf(index, x, n, wi, y, ny, d, primitive, modes, unknownQuadDensity());
}

// ---- Parts of lights: light selection "bvh" chooses a mesh light's triangles one by one ----
// `triangle`: the mesh triangle chosen (leaf-order primitive), or NO_HIT for the whole light.

// sampleLight for light `index`, or for triangle `triangle` of it alone (meshTriangleLight).
bool sampleLightPart(uint index, uint triangle, vec3 x, vec3 n, vec3 u, LightSamplingModes modes, out LightSample ls) {
    if (triangle == NO_HIT || !hasLight(LIGHT_MESH)) return sampleLight(index, x, n, u, modes, ls);
    ls = emptyLightSample(n);
    Primitive p = loadLightPrimitive(triangle);
    return sampleMeshTriangle(meshTriangleLight(loadLight(index), p), triangle, p, x, u.xy, modes, ls);
}

// The density with which sampleLightPart produces wi toward the light part hit at y on
// `primitive` (lightPdf's arguments): a mesh light's triangle alone, any other light whole.
float lightPartPdf(uint index, vec3 x, vec3 n, vec3 wi, vec3 y, vec3 ny, float d, uint primitive,
                   LightSamplingModes modes, KnownQuadDensity quad) {
    Light light = loadLight(index);
    if (!lightIs(light, LIGHT_MESH)) return lightPdf(index, x, n, wi, y, ny, d, primitive, modes, quad);
    return meshLightPdf(meshTriangleLight(light, loadLightPrimitive(primitive)), x, wi, ny, d, primitive, modes);
}

#endif
