// What a closest hit means for shading: position, geometric (front) normal, interpolated
// shading normal, texture coordinates, material and light of the primitive; and where to
// start the next ray from that point. Declares the per-vertex normal and uv buffers;
// traversal is in bvh.glsl.
//
// Normals are NOT flipped toward the viewer here: geometricNormal is always the front
// normal of SCENE_FORMAT.md (triangles: counter-clockwise, normalize(cross(v1-v0, v2-v0));
// quads: normalize(cross(edge_u, edge_v)); spheres: outward), and shadingNormal is the
// interpolated vertex normal as given. Integrators decide which side they are on (one-sided
// emitters need the unflipped front normal).
#ifndef PENUMBRA_SURFACE_GLSL
#define PENUMBRA_SURFACE_GLSL

#include "shared/types.h"
#include "geometry/bvh.glsl"
#include "geometry/uvs.glsl"

// Per-vertex shading normals of triangles whose typeAndNormals >> 2 is non-zero
// (normals[(typeAndNormals >> 2) - 1]).
layout(std430, binding = BINDING_NORMALS) readonly restrict buffer TriangleNormalsBuffer { TriangleNormals normals[]; };
// Per-vertex tangents of every primitive in leaf order, read only in scenes with normal maps.
layout(std430, binding = BINDING_TANGENTS) readonly restrict buffer TriangleTangentsBuffer { TriangleTangents tangents[]; };

struct SurfacePoint {
    vec3 position;         // on the primitive (world space)
    vec3 geometricNormal;  // unit front normal, never flipped
    vec3 shadingNormal;    // unit; interpolated vertex normal, else the geometric normal
    uint material;         // index into materials[]
    uint light;            // index into lights[], NO_LIGHT if the primitive does not emit
    uint primitiveType;    // PRIM_*
    // Texture coordinates (SCENE_FORMAT.md "Textures (v2)"): mesh `uvs` interpolated, quad
    // (s, t), sphere (atan2(x, -z) / 2 pi wrapped to [0, 1), acos(y) / pi) of the unit
    // direction from the centre. Computed only in textured scenes (hasTextures()), else 0:
    // an untextured kernel pays nothing for them.
    vec2 uv;
    // Interpolated vertex tangent (xyz, not unit) and bitangent sign (w) of a normal-mapped
    // mesh (shared/types.h, TriangleTangents); computed only where hasNormalMaps(), else 0.
    vec4 tangent;
};

const float SURFACE_INV_TWO_PI = 0.15915494309189535;
const float SURFACE_INV_PI = 0.3183098861837907;

// The surface point of primitive hit.primitive (hit.instance aside) for the ray origin + t
// dir that found it, in the primitive's own frame. Positions come from the primitive's own
// parameters (barycentrics, (s, t), or the sphere's centre and radius), which is more
// accurate than origin + t dir, so that offsetRayOrigin starts from a point on the surface.
// `perPrimitive`: read the leaf-order uvs and tangents (not for a group's primitives, which
// are untextured and have none: render/instance_arrays.h).
SurfacePoint primitiveSurfaceAt(Hit hit, vec3 origin, vec3 dir, bool perPrimitive) {
    Primitive primitive = loadPrimitive(hit.primitive);  // texel fetch: no per-lane load loop
    SurfacePoint sp;
    sp.material = primitive.material;
    sp.light = primitive.light;
    sp.primitiveType = primitive.typeAndNormals & PRIM_TYPE_MASK;
    sp.uv = vec2(0.0);
    sp.tangent = vec4(0.0);
    if (hasPrimitive(PRIM_SPHERE) && sp.primitiveType == PRIM_SPHERE) {
        vec3 outward = normalize(origin + hit.t * dir - primitive.p0);
        sp.position = primitive.p0 + primitive.p1.x * outward;
        sp.geometricNormal = outward;
        sp.shadingNormal = outward;
        if (hasTextures()) {
            // atan(y, x) is in [-pi, pi]: shift negative angles by one turn; u = 1 only
            // where rounding lands exactly on the seam, which wraps to 0.
            float u = atan(outward.x, -outward.z) * SURFACE_INV_TWO_PI;
            u = u < 0.0 ? u + 1.0 : u;
            sp.uv = vec2(u >= 1.0 ? 0.0 : u, acos(clamp(outward.y, -1.0, 1.0)) * SURFACE_INV_PI);
        }
    } else if (hasPrimitive(PRIM_QUAD) && sp.primitiveType == PRIM_QUAD) {
        sp.position = primitive.p0 + hit.uv.x * primitive.p1 + hit.uv.y * primitive.p2;
        sp.geometricNormal = normalize(cross(primitive.p1, primitive.p2));
        sp.shadingNormal = sp.geometricNormal;
        sp.uv = hit.uv;  // (s, t)
    } else {
        vec3 b = vec3(1.0 - hit.uv.x - hit.uv.y, hit.uv.x, hit.uv.y);
        sp.position = b.x * primitive.p0 + b.y * primitive.p1 + b.z * primitive.p2;
        sp.geometricNormal = normalize(cross(primitive.p1 - primitive.p0, primitive.p2 - primitive.p0));
        sp.shadingNormal = sp.geometricNormal;
        uint normalsIndex = primitive.typeAndNormals >> 2;
        if (normalsIndex != 0u) {
            TriangleNormals tn = normals[normalsIndex - 1u];
            vec3 n = b.x * tn.n0.xyz + b.y * tn.n1.xyz + b.z * tn.n2.xyz;
            float len2 = dot(n, n);
            if (len2 > 0.0) sp.shadingNormal = n * inversesqrt(len2);  // degenerate: keep geometric
        }
        if (hasTextures() && perPrimitive) {
            TriangleUvs t = uvs[hit.primitive];
            sp.uv = b.x * t.uv01.xy + b.y * t.uv01.zw + b.z * t.uv2.xy;
        }
        if (hasNormalMaps() && perPrimitive) {
            TriangleTangents tt = tangents[hit.primitive];
            sp.tangent = b.x * tt.t0 + b.y * tt.t1 + b.z * tt.t2;
        }
    }
    return sp;
}

#ifdef PENUMBRA_INSTANCES_GLSL
// A hit in instance hit.instance's group: the surface point in the group's frame, moved into
// the world by the instance's to_world, normals by the inverse transpose of its linear part
// (= worldToObject's linear part, transposed; a mirroring map keeps the front the image of
// the front, as the loader keeps it for copies), with the instance's material if it has one.
SurfacePoint instanceSurfaceAt(Hit hit, vec3 origin, vec3 dir) {
    Instance instance = instances[hit.instance];
    vec3 o, d;
    rayToObject(instance, origin, dir, o, d);
    SurfacePoint sp = primitiveSurfaceAt(hit, o, d, false);
    vec4 p = vec4(sp.position, 1.0);
    sp.position = vec3(dot(instance.objectToWorld0, p), dot(instance.objectToWorld1, p), dot(instance.objectToWorld2, p));
    // mat3(a, b, c) takes a, b, c as its columns: with W's rows as columns it is W^T.
    mat3 normalMap = mat3(instance.worldToObject0.xyz, instance.worldToObject1.xyz, instance.worldToObject2.xyz);
    sp.geometricNormal = normalize(normalMap * sp.geometricNormal);
    sp.shadingNormal = normalize(normalMap * sp.shadingNormal);
    if (instance.material != NO_MATERIAL_OVERRIDE) sp.material = instance.material;
    return sp;
}
#endif

// The surface point of `hit` (which must be a hit: hit.primitive != NO_HIT) for the ray
// origin + t dir that found it, in the world (primitiveSurfaceAt, or instanceSurfaceAt for
// a hit in an instance).
SurfacePoint surfaceAt(Hit hit, vec3 origin, vec3 dir) {
#ifdef PENUMBRA_INSTANCES_GLSL
    if (hasPrimitive(PRIM_INSTANCE) && hit.instance != NO_HIT) return instanceSurfaceAt(hit, origin, dir);
#endif
    return primitiveSurfaceAt(hit, origin, dir, true);
}

// Wächter & Binder 2019, "A Fast and Robust Method for Avoiding Self-Intersection", Ray
// Tracing Gems ch. 6: moves p off the surface along n by a few ULPs of each coordinate
// (integer arithmetic on the float bits, so the step scales with |p|), or by a fixed
// epsilon for coordinates near zero where ULPs are too small. n = the unit geometric normal
// flipped to the side the new ray leaves on (not the shading normal).
const float OFFSET_ORIGIN = 1.0 / 32.0;
const float OFFSET_FLOAT_SCALE = 1.0 / 65536.0;
const float OFFSET_INT_SCALE = 256.0;

vec3 offsetRayOrigin(vec3 p, vec3 n) {
    ivec3 ofI = ivec3(OFFSET_INT_SCALE * n);
    vec3 pI = intBitsToFloat(floatBitsToInt(p) + mix(ofI, -ofI, lessThan(p, vec3(0.0))));
    return mix(pI, p + OFFSET_FLOAT_SCALE * n, lessThan(abs(p), vec3(OFFSET_ORIGIN)));
}

// The normals a two-sided surface is shaded with, seen from wo (towards the viewer): the
// geometric normal turned to the viewer's side, the shading normal turned to the same side
// as it, and, where that shading normal still faces away from the viewer (it would reflect
// nothing), the geometric one instead. The direct integrator shades with these and the
// normal AOV reports them (integrators/direct.comp, integrators/aov.glsl).
void viewerSideNormals(SurfacePoint sp, vec3 wo, out vec3 ng, out vec3 ns) {
    ng = dot(sp.geometricNormal, wo) >= 0.0 ? sp.geometricNormal : -sp.geometricNormal;
    ns = dot(sp.shadingNormal, ng) >= 0.0 ? sp.shadingNormal : -sp.shadingNormal;
    if (dot(ns, wo) <= 0.0) ns = ng;
}

#endif
