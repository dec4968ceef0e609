// GPU data layouts shared by the C++ host and the GLSL shaders: defined once, here.
// Every struct is std430 / std140 compatible (a vec3 is always followed by one 4-byte
// scalar, so both sides agree without hidden padding); tests/test_layout.cpp checks
// sizeof and offsetof on the C++ side. Binding numbers are macros so that GLSL can
// use them inside layout() qualifiers.
#ifndef PENUMBRA_SHARED_TYPES_H
#define PENUMBRA_SHARED_TYPES_H

#ifdef __cplusplus
#include <cstdint>
#include <glm/glm.hpp>
namespace penumbra::gpu {
using vec3 = glm::vec3;
using vec4 = glm::vec4;
using uint = std::uint32_t;
#define PENUMBRA_CONST inline constexpr
#else
#define PENUMBRA_CONST const
#endif

// ---- Descriptor bindings of the render kernels (set 0) -------------------------------
#define BINDING_PARAMS 0       // uniform RenderParams
#define BINDING_ACCUM 1        // AccumSum per pixel (below): the sum of samples and their count
#define BINDING_NODES 2        // WideNode[] as a texel buffer (see below; read where kNodeReads says)
#define BINDING_PRIMITIVES 3   // Primitive[] in BVH leaf order (storage buffer: tests)
#define BINDING_NORMALS 4      // TriangleNormals[]
#define BINDING_MATERIALS 5    // Material[] as a texel buffer (MATERIAL_TEXELS texels each)
#define BINDING_LIGHTS 6       // Light[] as a texel buffer (LIGHT_TEXELS texels each)
#define BINDING_LIGHT_TABLE 7  // AliasEntry[] as a texel buffer: light selection (item = light index)
#define BINDING_MESH_TABLE 8   // AliasEntry[] as a texel buffer: mesh-light triangles (item = primitive index)
// uint[3]: the rays traced (when SPEC_COUNT_RAYS is set), the tile queue's next pixel, and
// the invocations whose loops the driver cut short (SPEC_LOOPS_MAY_BE_CUT)
#define BINDING_COUNTERS 9
#define BINDING_PRIMITIVE_TEXELS 10   // the same Primitive[] as a texel buffer: traversal
#define BINDING_MATERIAL_TEXTURES 11  // texel buffer: which fields of each material are textured
#define BINDING_TEXTURE_TEXELS 12     // texel buffer: the texels of every texture
#define BINDING_UVS 13                // TriangleUvs[] per primitive in leaf order (textured scenes)
#define BINDING_ENV_TEXELS 14         // texel buffer: environment map radiance, RGB32F + pad per texel
#define BINDING_ENV_TABLE 15          // AliasEntry[] as a texel buffer: environment map texels (item = texel)
#define BINDING_NODE_WORDS 16  // the same WideNode[] as a storage buffer of uvec4 (or u64vec4) words (kNodeReads)
#define BINDING_ACCUM_COMPENSATION 17  // AccumCompensation per pixel (below): what the sums rounded away
#define BINDING_AOV 18                 // AOV_VEC4S vec4 per pixel: the AOV sums (shared/aov.h), when SPEC_AOVS != 0
// Texel buffer, when SPEC_LIGHT_BVH != 0: the light BVH's nodes, items and per-primitive
// trails (shared/light_bvh.h; RenderParams says where each part starts)
#define BINDING_LIGHT_BVH 19
#define BINDING_TANGENTS 20   // TriangleTangents[] per primitive in leaf order (scenes with normal maps)
#define BINDING_INSTANCES 21  // Instance[] (below), scenes with instances (two-level BVH)
#define BINDING_COUNT 22

// ---- BVH ------------------------------------------------------------------------------
// Flattened depth-first: an interior node's left child is the next node, `offset` is the
// right child; a leaf (primCount > 0) covers primitives[offset, offset + primCount).
struct BvhNode {
    vec3 boundsMin;
    uint offset;
    vec3 boundsMax;
    uint primCount;
};

// What the traversal reads (Bvh::wideNodes, BINDING_NODES): the binary tree collapsed into
// nodes of up to four children (host/bvh/wide.cpp), each child's box quantized to one byte
// per plane in the node's own frame, after Ylitie, Karras & Laine 2017 ("Efficient
// Incoherent Ray Traversal on GPUs Through Compressed Wide BVHs", HPG), with 4 children
// where they use 8. A child's box is, per axis,
//     lo = base + plane(E, q_lo),  hi = base + plane(E, q_hi),
//     plane(E, q) = the float with exponent field E and q in mantissa bits 8-15
//                 = 2^(E - 127) + q * 2^(E - 142),
// one rounding, in the sum. The shader builds plane(E, q) from the bits, with no conversion
// of q to a float and no multiply: the planes lie 2^(E - 142) apart, and base is the
// smallest corner of the children's boxes less 2^(E - 127), rounded down
// (docs/performance-history/round-19.md). The builder rounds q_lo down and q_hi up until the float
// result contains the child's box: the decoded box is never smaller. One traversal step
// reads one node, 64 bytes, and tests four boxes; the binary child pairs it replaced needed
// 64 bytes for two (docs/performance-history/round-07.md).
//
//   base    the frame's base, per axis (above)
//   meta    bits 0-7, 8-15, 16-23: E of the x, y, z planes; bits 24-27: which children exist
//   loX..hiZ  one plane of every child: byte c (bits 8c to 8c + 7) belongs to child c
//   child   where child c leads: offset | primCount << BVH_COUNT_SHIFT; primCount == 0:
//           an interior child, offset = its WideNode; primCount > 0: a leaf, primitives
//           [offset, offset + primCount)
// Node 0 is the root. A child slot that does not exist has its meta bit clear.
struct WideNode {
    vec3 base;
    uint meta;
    uint loX, loY, loZ, hiX;
    uint hiY, hiZ, child0, child1;
    uint child2, child3, unused0, unused1;
};
#define WIDE_NODE_ARITY 4u
PENUMBRA_CONST uint WIDE_CHILD_MASK_SHIFT = 24u;
PENUMBRA_CONST uint WIDE_ALL_CHILDREN = (1u << WIDE_NODE_ARITY) - 1u;  // a child mask with every bit
// A traversal stack entry of the kernels that keep their stack in a local array: a node
// whose children it still has to visit, as node | childMask << WIDE_STACK_MASK_SHIFT (a
// node index below 2^27, see below). The "_address" kernels push child references instead
// (geometry/bvh.glsl, traverse).
PENUMBRA_CONST uint WIDE_STACK_MASK_SHIFT = 28u;
PENUMBRA_CONST uint WIDE_STACK_NODE_MASK = (1u << WIDE_STACK_MASK_SHIFT) - 1u;
//
// Texel buffers (BINDING_NODES, BINDING_PRIMITIVE_TEXELS) are views of the same bytes as
// the structs, in RGBA32UI texels of 16 bytes (the storage-buffer view BINDING_NODE_WORDS
// in uvec4 words of 16 bytes, numbered alike): a WideNode is texels 4n to 4n + 3 in field
// order; a Primitive is texels 3i (p0, typeAndNormals), 3i + 1 (p1, material), 3i + 2
// (p2, light). Floats are read back with uintBitsToFloat.
PENUMBRA_CONST uint WIDE_NODE_TEXELS = 4u;
PENUMBRA_CONST uint PRIMITIVE_TEXELS = 3u;
// A WideNode child packs offset | primCount << BVH_COUNT_SHIFT: leaves hold
// at most BVH_MAX_LEAF_SIZE primitives, and scenes at most BVH_MAX_PRIMITIVES (the texel
// buffer limit, 2^27 texels on lavapipe, allows fewer still: 44.7M primitives).
#define BVH_COUNT_SHIFT 27u
PENUMBRA_CONST uint BVH_OFFSET_MASK = (1u << BVH_COUNT_SHIFT) - 1u;
PENUMBRA_CONST uint BVH_MAX_LEAF_SIZE = 31u;
PENUMBRA_CONST uint BVH_MAX_PRIMITIVES = 1u << BVH_COUNT_SHIFT;

// 1 + 2 gamma(3): widens the exit distance of the slab test so that rounding never culls a
// box the ray touches (Ize 2013, "Robust BVH Ray Traversal", JCGT 2(2); pbrt-v4
// Bounds3::IntersectP). The CPU (host/bvh/intersect.h) and the GLSL read this one constant.
PENUMBRA_CONST float BOX_EXIT_SCALE = 1.0000004f;

// Deepest leaf the builder produces (root = depth 0). A traversal whose stack entries are
// nodes keeps at most one deferred node per level on its stack, so a stack of
// BVH_MAX_DEPTH entries never overflows.
#define BVH_MAX_DEPTH 64
// Traversal stacks per invocation of the kernels that keep them in memory (the "_address"
// kernels, geometry/bvh.glsl): one per ray that tracePair traverses together.
PENUMBRA_CONST uint BVH_STACKS_PER_INVOCATION = 2u;
// Closest-hit result meaning "no primitive was hit".
PENUMBRA_CONST uint NO_HIT = 0xffffffffu;

// ---- Primitives -----------------------------------------------------------------------
PENUMBRA_CONST uint PRIM_TRIANGLE = 0u;  // p0, p1, p2 = vertices, counter-clockwise = front
PENUMBRA_CONST uint PRIM_SPHERE = 1u;    // p0 = centre, p1.x = radius
PENUMBRA_CONST uint PRIM_QUAD = 2u;      // p0 = origin, p1 = edge_u, p2 = edge_v
// An instance of a group in the top-level tree (two-level BVH, geometry/instances.glsl):
// p0, p1 = its world box's corners (p2 = p1, so that a triangle's bounds are that box);
// typeAndNormals >> 2 = its index in instances[].
PENUMBRA_CONST uint PRIM_INSTANCE = 3u;
PENUMBRA_CONST uint PRIM_TYPE_MASK = 3u;
#define PRIM_KIND_COUNT 4u  // one more than the last PRIM_*: scene feature bits (below)
PENUMBRA_CONST uint NO_LIGHT = 0xffffffffu;

// typeAndNormals: bits 0-1 the PRIM_* type; bits 2-31 hold (index into normals[] + 1),
// 0 meaning "no shading normals, use the geometric normal".
struct Primitive {
    vec3 p0;
    uint typeAndNormals;
    vec3 p1;
    uint material;  // index into materials[]
    vec3 p2;
    uint light;     // index into lights[] when the primitive emits, else NO_LIGHT
};

// A placement of a group (BINDING_INSTANCES; host/render/instance_arrays.h): the rows of
// its 3x4 map from the world into the group's frame and of the inverse, the instance's
// to_world; the root of the group's own tree among the wide nodes (its nodes and
// primitives follow the scene's own); the instance's material or NO_MATERIAL_OVERRIDE.
struct Instance {
    vec4 worldToObject0, worldToObject1, worldToObject2;
    vec4 objectToWorld0, objectToWorld1, objectToWorld2;
    uint root;
    uint material;
    uint pad0, pad1;
};
PENUMBRA_CONST uint NO_MATERIAL_OVERRIDE = 0xffffffffu;

struct TriangleNormals {
    vec4 n0, n1, n2;  // per-vertex shading normals (xyz), interpolated barycentrically
};

// Per-vertex tangents of a normal-mapped triangle (glTF TANGENT, or computed: host/scene/
// tangents.h): xyz the tangent (the direction of increasing u), w = +-1 the bitangent's sign,
// B = w cross(N, T) (glTF 2.0 section 3.7.2.1). Zero where a primitive has none.
struct TriangleTangents {
    vec4 t0, t1, t2;
};

// ---- Materials (SCENE_FORMAT.md) -------------------------------------------------------
PENUMBRA_CONST uint MATERIAL_DIFFUSE = 0u;  // kd = albedo, ks = 0
PENUMBRA_CONST uint MATERIAL_PHONG = 1u;    // kd/pi + ks (n+2)/(2pi) cos^n(alpha)
PENUMBRA_CONST uint MATERIAL_PBR = 2u;      // glTF metallic-roughness (bsdf/pbr.glsl)
#define MATERIAL_KIND_COUNT 3u              // one more than the last MATERIAL_*: scene feature bits (below)

// Packing per type (render/material_arrays.cpp; textures rely on these slots):
//   diffuse  kd = albedo                      ks = 0                       exponent unused
//   phong    kd, ks as in the scene           exponent = n
//   pbr      kd = base_color                  ks.x = metallic, ks.y = roughness,
//                                             ks.z unused (0)              exponent unused (0)
struct Material {
    vec3 kd;
    uint type;
    vec3 ks;
    float exponent;
};
PENUMBRA_CONST uint MATERIAL_TEXELS = 2u;  // RGBA32UI texels per Material (bsdf/materials.glsl)

// ---- Textures (SCENE_FORMAT.md "Textures (v2)"; shaders/textures/textures.glsl) ----------
// A textured material field replaces one value slot of the Material above with
// scale x texture(u, v), clamped to [0, 1] (the range of every texturable field):
//   TEXTURE_SLOT_KD    kd.rgb   diffuse `albedo`, phong `kd`, pbr `base_color`
//   TEXTURE_SLOT_KS    ks.rgb   phong `ks`
//   TEXTURE_SLOT_KS_X  ks.x     pbr `metallic`   (one channel of the texture)
//   TEXTURE_SLOT_KS_Y  ks.y     pbr `roughness`  (one channel of the texture)
// A new texturable field names its slot here and in host/scene (TextureSlot); the BRDF
// code never sees textures, only the Material they produced.
PENUMBRA_CONST uint TEXTURE_SLOT_KD = 0u;
PENUMBRA_CONST uint TEXTURE_SLOT_KS = 1u;
PENUMBRA_CONST uint TEXTURE_SLOT_KS_X = 2u;
PENUMBRA_CONST uint TEXTURE_SLOT_KS_Y = 3u;
// Not a Material slot: scales the emitted radiance of the emitting primitives that use the
// material (glTF emissiveTexture; textures/textures.glsl, emissionTexture). The Light keeps
// emissiveFactor x strength, the texture's largest possible value times it.
PENUMBRA_CONST uint TEXTURE_SLOT_EMISSION = 4u;
// Not a Material slot either: the alpha test of glTF alphaMode MASK (textures/alpha_mask.glsl).
// The reference reads the base colour texture's alpha (channel 3); scale.x is
// baseColorFactor.a and scale.y the alphaCutoff: a triangle point whose scale.x x alpha is
// below scale.y is no surface for any ray.
PENUMBRA_CONST uint TEXTURE_SLOT_ALPHA = 5u;
// Not a Material slot: a tangent-space normal map (glTF normalTexture; textures/normal_map.glsl).
// scale.x is the normalTexture's scale, applied to the decoded x and y.
PENUMBRA_CONST uint TEXTURE_SLOT_NORMAL = 6u;

// BINDING_MATERIAL_TEXTURES, RGBA32UI texels: texel i (i < material count) is material i's
// (first texel of its texture references, reference count, 0, 0); a reference is two
// texels, the TextureRef below. BINDING_TEXTURE_TEXELS, RGBA32UI texels: every texture's
// RGBA texels as half floats, row-major from the top row, two per buffer texel (texel j is
// (x, y) of buffer texel j/2 for even j, (z, w) for odd j; each pair of halves packed as
// packHalf2x16(r, g), packHalf2x16(b, a)). Textures follow each other without padding.
struct TextureRef {
    vec3 scale;        // the field's scale S (a number field: scale.x)
    uint slotChannel;  // TEXTURE_SLOT_* | channel << 8 (number slots: 0 = R ... 3 = A)
    uint firstTexel;   // of the texture in BINDING_TEXTURE_TEXELS, in texels
    uint width;
    uint height;
    uint wrap;  // TEXTURE_WRAP_* along u | (along v) << 2
};
PENUMBRA_CONST uint TEXTURE_REF_TEXELS = 2u;
// In a scene where some texture's coordinates are transformed (glTF KHR_texture_transform;
// SPEC_TEXTURES has TEXTURES_TRANSFORMED), every reference is followed by its transform, so
// references are TEXTURE_REF_TEXELS + TEXTURE_TRANSFORM_TEXELS texels apart; other scenes
// keep the short references and compile the transform out.
struct TextureTransform {
    vec4 u;  // u' = dot(u.xyz, (u, v, 1)); w unused
    vec4 v;  // v' = dot(v.xyz, (u, v, 1)); w unused
};
PENUMBRA_CONST uint TEXTURE_TRANSFORM_TEXELS = 2u;
PENUMBRA_CONST uint TEXTURE_WRAP_REPEAT = 0u;
PENUMBRA_CONST uint TEXTURE_WRAP_CLAMP = 1u;   // glTF CLAMP_TO_EDGE
PENUMBRA_CONST uint TEXTURE_WRAP_MIRROR = 2u;  // glTF MIRRORED_REPEAT

// Per-vertex texture coordinates of a triangle (mesh `uvs`; zero without them), indexed
// by the primitive's leaf-order index. Quads and spheres compute theirs (geometry/surface.glsl).
struct TriangleUvs {
    vec4 uv01;  // (u0, v0, u1, v1)
    vec4 uv2;   // (u2, v2, 0, 0)
};

// The smallest GGX alpha (= roughness^2) of `pbr`: roughness below 0.01 renders as 0.01.
// A float direction or half vector is known to ~2.4e-7 rad, and D varies on the angular
// scale alpha (|d ln D / d theta_h| <= 2 / alpha), so D is evaluated to ~2.4e-7 * 2 / alpha
// relative: 0.5% here, 5% at 1e-5. D's peak 1 / (pi alpha^2) = 3.2e7 and alpha^4 = 1e-16
// stay well inside float range. A true mirror would be a delta lobe, which light sampling
// cannot hit; this one stays a (very sharp) density that every strategy can weigh.
PENUMBRA_CONST float PBR_MIN_ALPHA = 1e-4f;

// ---- Lights -----------------------------------------------------------------------------
PENUMBRA_CONST uint LIGHT_POINT = 0u;        // position, emission = intensity (W/sr)
PENUMBRA_CONST uint LIGHT_DIRECTIONAL = 1u;  // position = unit direction of travel, emission = irradiance
PENUMBRA_CONST uint LIGHT_ENVIRONMENT = 2u;  // emission = constant radiance, or a map (LIGHT_ENVIRONMENT_MAP)
PENUMBRA_CONST uint LIGHT_SPHERE = 3u;       // first = primitive index, emission = radiance
PENUMBRA_CONST uint LIGHT_QUAD = 4u;         // first = primitive index, emission = radiance
PENUMBRA_CONST uint LIGHT_MESH = 5u;         // meshTable[first, first + count), emission = radiance
PENUMBRA_CONST uint LIGHT_SPOT = 6u;         // position, emission = intensity on the axis (W/sr); see below
#define LIGHT_KIND_COUNT 7u                  // one more than the last LIGHT_*: scene feature bits (below)
PENUMBRA_CONST uint LIGHT_TWO_SIDED = 1u;    // flags bit: quad / mesh emit from both faces
PENUMBRA_CONST uint LIGHT_ENVIRONMENT_MAP = 2u;  // flags bit: the environment reads its map (below)
// flags bit of a quad light whose edges are orthogonal (to 1e-5 of their lengths' product:
// scene files write rectangles in decimals), decided once on the host: sampled in solid
// angle as a spherical rectangle, any other quad as two spherical triangles (lights/quad.glsl).
PENUMBRA_CONST uint LIGHT_RECTANGLE = 4u;

// An environment with a map (SCENE_FORMAT.md `environment` with `file`) has no area or mesh
// table: `first` and `count` hold the map's width and height, and its radiance is the texel
// (BINDING_ENV_TEXELS, already multiplied by the light's `radiance`), sampled by the alias
// table at BINDING_ENV_TABLE (shaders/lights/environment_map.glsl mirrors
// host/render/environment_map.cpp). `emission` keeps the `radiance` factor, and `position`
// the map's mean radiance over solid angle (the texels already multiplied), which sets its
// power for light selection.

// A spot light has no area, mesh table or sides; its axis and cone use those fields:
// `first` and `count` hold the float bits (floatBitsToUint) of the unit axis in octahedral
// coordinates (Cigolle et al. 2014, "A Survey of Efficient Representations for Independent
// Unit Vectors", JCGT 3(2): encoded in host/render/light_arrays.cpp, decoded in
// shaders/lights/spot.glsl), `area` the cosine of the outer angle and
// `flags` the float bits of the cosine of the inner angle.
struct Light {
    uint type;
    uint first;
    uint count;
    uint flags;
    vec3 emission;
    float area;            // total emitting area (area lights), else 0
    vec3 position;
    float selectionProb;   // probability that light selection picks this light
};
PENUMBRA_CONST uint LIGHT_TEXELS = 3u;  // RGBA32UI texels per Light (lights/light_data.glsl)

// One pixel of the accumulation, written only by addSample (integrators/kernel_common.glsl):
// Kahan's compensated sum (Higham, "Accuracy and Stability of Numerical Algorithms", 2nd
// ed., section 4.3). `sum` is the running float sum and `compensation` what its additions
// rounded away, so that sum - compensation is the sum of the samples to a few float
// roundings at any count up to 2^31 (a plain float32 sum of a constant 0.3 drifted to 0.27
// at 2^24 samples). Where every addition was exact, compensation stays 0 and `sum` is the
// plain sum, bit for bit. The count is an integer, exact at every spp (a float count stops
// at 2^24). Two buffers of 16 bytes a pixel rather than one of 32, so that the largest film
// a device's maxStorageBufferRange allows stays what it was (8 M pixels on lavapipe).
struct AccumSum {  // BINDING_ACCUM
    vec3 sum;
    uint count;
};
struct AccumCompensation {  // BINDING_ACCUM_COMPENSATION
    vec3 compensation;
    uint unused;
};

// Walker/Vose alias table entry: pick slot i uniformly, keep it with `probability`,
// otherwise take `alias`. `pmf` is the discrete probability of slot i itself.
struct AliasEntry {
    float probability;
    uint alias;
    uint item;
    float pmf;
};

// ---- Integrator options ---------------------------------------------------------------
PENUMBRA_CONST uint AO_UNIFORM = 0u;
PENUMBRA_CONST uint AO_COSINE = 1u;

PENUMBRA_CONST uint STRATEGY_LIGHT = 0u;
PENUMBRA_CONST uint STRATEGY_BSDF = 1u;
PENUMBRA_CONST uint STRATEGY_MIS = 2u;
PENUMBRA_CONST uint STRATEGY_MIXTURE = 3u;
PENUMBRA_CONST uint STRATEGY_RIS = 4u;  // resampled importance sampling (integrators/ris.glsl)

PENUMBRA_CONST uint HEURISTIC_BALANCE = 0u;
PENUMBRA_CONST uint HEURISTIC_POWER = 1u;

PENUMBRA_CONST uint SPHERE_AREA = 0u;
PENUMBRA_CONST uint SPHERE_CAP = 1u;
PENUMBRA_CONST uint SPHERE_SOLID_ANGLE = 2u;

PENUMBRA_CONST uint QUAD_AREA = 0u;         // uniform on the quad's area
PENUMBRA_CONST uint QUAD_SOLID_ANGLE = 1u;  // uniform in its solid angle (spherical rectangle / 2 triangles)

PENUMBRA_CONST uint TRIANGLE_AREA = 0u;         // mesh lights: uniform on the chosen triangle's area
PENUMBRA_CONST uint TRIANGLE_SOLID_ANGLE = 1u;  // uniform in the chosen triangle's solid angle
// Quads and triangles of a smaller solid angle (sr) than this are sampled on their area
// instead of their solid angle, and so are those seen at grazing angles: with some vertex
// less than asin(SPHERICAL_MIN_ELEVATION_SINE) (1.7 degrees) above their plane. Measured
// bounds: lights/lights.glsl says why and how.
PENUMBRA_CONST float SPHERICAL_MIN_SOLID_ANGLE = 1e-3f;
PENUMBRA_CONST float SPHERICAL_MIN_ELEVATION_SINE = 0.03f;

// ---- Sampler (shaders/common/rng.glsl) --------------------------------------------------
PENUMBRA_CONST uint SAMPLER_INDEPENDENT = 0u;  // independent hashes per sample and dimension
PENUMBRA_CONST uint SAMPLER_SOBOL = 1u;        // padded Owen-scrambled Sobol' (common/sobol.glsl)

// ---- Specialization constants of the render kernels (constant_id) ----------------------
// Options that select code rather than data are compiled into the kernel, not read from
// RenderParams: llvmpipe runs eight invocations in SIMD lanes and executes both sides of
// every branch under a mask, so a runtime switch pays for all the code it skips. Fixing
// them per pipeline lets the compiler drop the unused strategies, light types, primitive
// types and materials (what it bought: docs/performance-history/round-01.md). host/render/kernel_options.cpp fills
// them; shaders/common/specialization.glsl
// declares them.
#define SPEC_COUNT_RAYS 0        // 1: count traced rays into BINDING_COUNTERS (benchmarks)
#define SPEC_STRATEGY 1          // STRATEGY_*
#define SPEC_HEURISTIC 2         // HEURISTIC_*
#define SPEC_LIGHT_SAMPLES 3     // N1
#define SPEC_BSDF_SAMPLES 4      // N2
#define SPEC_SPHERE_SAMPLING 5   // SPHERE_*
#define SPEC_AO_SAMPLING 6       // AO_*
#define SPEC_SCENE_FEATURES 7    // FEATURE_* bits: what the scene contains
#define SPEC_SAMPLER 8           // SAMPLER_*
#define SPEC_QUAD_SAMPLING 9     // QUAD_*
#define SPEC_TRIANGLE_SAMPLING 10  // TRIANGLE_*
#define SPEC_TEXTURES 11           // TEXTURES_* bits: some material is textured (uvs computed, textures read)
#define SPEC_EMITTER_FIRST 12      // 0 or the light count: BRDF rays go emitter first (render/emitter_first.h)
#define SPEC_INLINE_COUNT 13       // 0 or the inline slots in use: primitives inline, no BVH (render/inline_geometry.h)
#define SPEC_INLINE_FIRST 14       // first of INLINE_MAX_PRIMITIVES x INLINE_PRIMITIVE_WORDS inline words
#define INLINE_MAX_PRIMITIVES 48   // inline_geometry.glsl declares this many; the measured break-even
#define INLINE_CAPACITY_STEP 16    // inline kernels unroll a multiple of this many tests (render/inline_geometry.h)
#define INLINE_PRIMITIVE_WORDS 10  // slot word (below), p0, p1, p2 (float bits)
// An inline slot's first word: PRIM_* type | leaf-order primitive index << INLINE_SLOT_INDEX_SHIFT,
// or INLINE_SLOT_EMPTY for a slot that pads its group (render/inline_geometry.h).
#define INLINE_SLOT_INDEX_SHIFT 8
#define INLINE_SLOT_TYPE_MASK 0xffu
#define INLINE_SLOT_EMPTY 0xffu
// The slots come in groups of INLINE_GROUP_SIZE, each with a bounding box (lo.xyz, hi.xyz as
// float bits) and whether the kernel tests it before the group's slots (1) or not (0).
#define INLINE_GROUP_SIZE 8
#define INLINE_MAX_GROUPS (INLINE_MAX_PRIMITIVES / INLINE_GROUP_SIZE)
#define INLINE_GROUP_WORDS 7
#define SPEC_INLINE_GROUP_FIRST (SPEC_INLINE_FIRST + INLINE_MAX_PRIMITIVES * INLINE_PRIMITIVE_WORDS)
#define SPEC_NODE_READS (SPEC_INLINE_GROUP_FIRST + INLINE_MAX_GROUPS * INLINE_GROUP_WORDS)  // NODE_READS_*
#define SPEC_LOOPS_MAY_BE_CUT (SPEC_NODE_READS + 1)  // 1: the driver may end loops early (render/loop_budget.h)
#define SPEC_AOVS (SPEC_LOOPS_MAY_BE_CUT + 1)        // AOV_* bits of the layers to accumulate (shared/aov.h); 0: none
#define SPEC_LIGHT_BVH (SPEC_AOVS + 1)            // 1: light_selection "bvh" (lights/light_bvh.glsl); 0 compiles it out
#define SPEC_RIS_CANDIDATES (SPEC_LIGHT_BVH + 1)  // strategy "ris": light candidates per draw (M)
// 0, or the leaves of a small light tree as constants (render/light_flat.h, shared/light_flat.h):
// LIGHT_FLAT_MAX_LEAVES x LIGHT_FLAT_WORDS words from SPEC_LIGHT_FLAT_FIRST.
#define SPEC_LIGHT_FLAT_COUNT (SPEC_RIS_CANDIDATES + 1)
#define LIGHT_FLAT_MAX_LEAVES 8
#define LIGHT_FLAT_WORDS 15
// 1 with SPEC_LIGHT_FLAT_COUNT where no light is at infinity: the table beside the tree holds
// the tree alone, and the kernel skips drawing from it.
#define SPEC_LIGHT_FLAT_ALONE (SPEC_LIGHT_FLAT_COUNT + 1)
#define SPEC_LIGHT_FLAT_FIRST (SPEC_LIGHT_FLAT_ALONE + 1)
#define SPEC_COUNT (SPEC_LIGHT_FLAT_FIRST + LIGHT_FLAT_MAX_LEAVES * LIGHT_FLAT_WORDS)
// SPEC_TEXTURES bits: TEXTURES_ON, some material is textured; TEXTURES_TRANSFORMED, and
// some texture reference has a uv transform (the references then carry TextureTransforms).
#define TEXTURES_ON 1u
#define TEXTURES_TRANSFORMED 2u
// And TEXTURES_EMISSION: some emitting primitive's material has an emission texture.
#define TEXTURES_EMISSION 4u
// And TEXTURES_ALPHA_MASK: some material is cut out by an alpha test (TEXTURE_SLOT_ALPHA).
#define TEXTURES_ALPHA_MASK 8u
// And TEXTURES_NORMAL_MAP: some material has a normal map (TEXTURE_SLOT_NORMAL); the
// tangents at BINDING_TANGENTS are then filled.
#define TEXTURES_NORMAL_MAP 16u
// Where the traversal reads a BVH node from (SPEC_NODE_READS): the texel buffer at
// BINDING_NODES or the storage buffer at BINDING_NODE_WORDS, the same bytes. Which is faster
// depends on the driver (host/render/node_reads.h says which each gets, and why).
// NODE_READS_STORAGE_32 reads the storage buffer 32 bytes at a time (u64vec4, two loads per
// node instead of four): only the kernels compiled with PENUMBRA_INT64_LOADS (the "_int64"
// variants, cmake/EmbedShaders.cmake) do, for devices with shaderInt64; every other kernel
// reads it as NODE_READS_STORAGE. NODE_READS_ADDRESS makes the same 32-byte loads through
// the node buffer's device address (PassConstants.nodeAddress*) instead of the binding: only
// the "_address" variants (PENUMBRA_NODE_ADDRESS) do, for devices with shaderInt64 and
// bufferDeviceAddress.
#define NODE_READS_TEXELS 0u
#define NODE_READS_STORAGE 1u
#define NODE_READS_STORAGE_32 2u
#define NODE_READS_ADDRESS 3u

// Scene feature bits: bit FEATURE_PRIMITIVE + PRIM_*, FEATURE_LIGHT + LIGHT_*,
// FEATURE_MATERIAL + MATERIAL_* is set when the scene has such a primitive, light or
// material. Code for a kind the scene lacks is compiled out. Each group starts where the
// one before ends (its *_KIND_COUNT), so a new kind that raises its count moves the groups
// after it instead of sharing their bits; the static_asserts below and the host's check of
// every kind against its count (render/kernel_options.cpp) catch a kind added without
// raising the count, and groups that no longer fit in 32 bits.
#define FEATURE_PRIMITIVE 0u
#define FEATURE_LIGHT (FEATURE_PRIMITIVE + PRIM_KIND_COUNT)
#define FEATURE_MATERIAL (FEATURE_LIGHT + LIGHT_KIND_COUNT)
// One more bit after the groups: the scene's environment has a map (LIGHT_ENVIRONMENT_MAP);
// without it the map lookup and sampling are compiled out and the constant sky stays as it was.
#define FEATURE_ENVIRONMENT_MAP (FEATURE_MATERIAL + MATERIAL_KIND_COUNT)
// And one more: a quad light that is no rectangle (LIGHT_RECTANGLE unset); without one, the
// two-triangle sampling of such quads is compiled out (llvmpipe runs both sides of a branch).
#define FEATURE_PARALLELOGRAM_LIGHT (FEATURE_ENVIRONMENT_MAP + 1u)
// And one more: the scene has exactly one light, so a BRDF-sampled ray can only find the
// light that the same shading point's light sample drew, and the direct integrator reuses
// what that sample computed (a quad's solid angle) instead of computing it again.
#define FEATURE_SINGLE_LIGHT (FEATURE_PARALLELOGRAM_LIGHT + 1u)
#define FEATURE_BIT_COUNT (FEATURE_SINGLE_LIGHT + 1u)
PENUMBRA_CONST uint FEATURES_ALL = 0xffffffffu;
#ifdef __cplusplus
static_assert(PRIM_TRIANGLE < PRIM_KIND_COUNT && PRIM_SPHERE < PRIM_KIND_COUNT && PRIM_QUAD < PRIM_KIND_COUNT &&
              PRIM_INSTANCE < PRIM_KIND_COUNT && PRIM_KIND_COUNT <= PRIM_TYPE_MASK + 1u);
static_assert(LIGHT_POINT < LIGHT_KIND_COUNT && LIGHT_DIRECTIONAL < LIGHT_KIND_COUNT &&
              LIGHT_ENVIRONMENT < LIGHT_KIND_COUNT && LIGHT_SPHERE < LIGHT_KIND_COUNT &&
              LIGHT_QUAD < LIGHT_KIND_COUNT && LIGHT_MESH < LIGHT_KIND_COUNT && LIGHT_SPOT < LIGHT_KIND_COUNT);
static_assert(MATERIAL_DIFFUSE < MATERIAL_KIND_COUNT && MATERIAL_PHONG < MATERIAL_KIND_COUNT &&
              MATERIAL_PBR < MATERIAL_KIND_COUNT);
static_assert(FEATURE_BIT_COUNT <= 32u, "scene feature bits no longer fit in SPEC_SCENE_FEATURES");
#endif

// Everything a render kernel needs besides the scene arrays and the specialization
// constants; set once per render.
struct RenderParams {
    vec3 eye;
    float tanHalfFovY;
    vec3 right;      // unit camera basis, right-handed: forward = -w
    float aspect;    // width / height
    vec3 up;
    uint width;
    vec3 forward;
    uint height;
    uint seed;
    uint sampleOffset;
    uint lightCount;
    float aoMaxDistance;
    // Light selection tables, all in lightTable[]: [0, lightCount) picks any light with
    // probability Light::selectionProb; the delta-only table (points, directionals) and the
    // continuous-only table (area lights, environment) follow, each with its own pmf. The
    // scales turn selectionProb into the probability within those sub-tables.
    uint deltaTableOffset;
    uint deltaCount;
    uint continuousTableOffset;
    uint continuousCount;
    float deltaScale;       // 1 / (sum of selectionProb over delta lights), 0 if none
    float continuousScale;  // 1 / (sum of selectionProb over continuous lights), 0 if none
    uint environmentLight;  // index of the (single, merged) environment light, or NO_LIGHT
    // primitives[besideFirst, besideFirst + besideCount): tested before the BVH by every
    // query, in no leaf of it (host/bvh/bvh.h, Bvh::besideCount).
    uint besideFirst;
    uint besideCount;
    // One of those that no camera ray can hit, whose test camera rays leave out, or NO_HIT
    // (host/render/out_of_view.h).
    uint cameraOutOfView;
    // light_selection "bvh" (lights/light_bvh.glsl): lightTable[lightBvhTableOffset, +
    // lightBvhTableCount) picks, uniformly, one of the lights at infinity or the tree
    // (item NO_LIGHT); in BINDING_LIGHT_BVH the items start at texel lightBvhItems and the
    // per-primitive trails at texel lightBvhTrails (the nodes at 0). All 0 otherwise.
    uint lightBvhTableOffset;
    uint lightBvhTableCount;
    uint lightBvhItems;
    uint lightBvhTrails;
    uint pad3, pad4;
};

// The render kernels work in tiles of TILE_SIZE x TILE_SIZE pixels, a workgroup's
// invocations (PassBands::kTile on the host).
#define TILE_SIZE 8
#define TILE_PIXELS (TILE_SIZE * TILE_SIZE)

// Per-dispatch constants: which sample indices it adds (sampleCount of them, from
// sampleIndex on, in order), to which rows of pixels (the preview renders a band of rows
// per frame to stay responsive), from which column on (render/pass_bands.h: a heavy row is
// split into runs of tiles; the band's tiles end the run), how the invocations share the
// band's pixels (queueTiles: render/tile_queue.h), and where the BVH's nodes
// are for the kernels that read them through their device address (NODE_READS_ADDRESS; 0
// for the others), and where those kernels keep their traversal stacks: stackDepth entries
// per stack, BVH_STACKS_PER_INVOCATION stacks per invocation, invocation i of the dispatch
// (x fastest, then y, then z) from entry i * BVH_STACKS_PER_INVOCATION * stackDepth on
// (render/traversal_stacks.h). The addresses are the same for every dispatch
// of a scene; they are push constants and not specialization constants because they change
// from run to run, and a kernel specialized on them would miss Mesa's shader cache on every
// start.
struct PassConstants {
    uint sampleIndex;  // relative to sampleOffset
    uint firstRow;
    uint rowCount;
    uint firstColumn;
    uint sampleCount;
    uint nodeAddressLow;   // VkDeviceAddress of the node buffer, low and high 32 bits (two
    uint nodeAddressHigh;  // words: a 64-bit member would be aligned differently in C++)
    uint stackAddressLow;  // VkDeviceAddress of the traversal stacks' buffer, likewise
    uint stackAddressHigh;
    uint stackDepth;  // entries per stack (at least 1)
    // 0: workgroup (x, y) renders tile (x, y) of the band. Otherwise the band's tiles, this
    // many, tileColumns to a row, which the invocations take pixel by pixel from the tile
    // queue's counter (render/tile_queue.h), whatever workgroup they are in.
    uint queueTiles;
    uint tileColumns;
    // LOOP_PROBE_TRIPS, the trips of the loop that tells whether the driver has cut this
    // invocation's loops short (integrators/kernel_common.glsl, loopsWereCut): a constant the
    // compiler cannot see, so that the loop stays a loop.
    uint loopProbeTrips;
};
#define LOOP_PROBE_TRIPS 2u

// ---- Preview tone map (shaders/preview/tonemap.comp) ------------------------------------
#define TONEMAP_BINDING_ACCUM 0   // the render kernels' accumulation buffer, read only
#define TONEMAP_BINDING_PIXELS 1  // uint per pixel: sRGB-encoded R | G << 8 | B << 16 | 255 << 24
#define TONEMAP_BINDING_COMPENSATION 2  // the render kernels' AccumCompensation buffer, read only
#define TONEMAP_BINDING_COUNT 3

struct ToneMapConstants {
    uint width;
    uint height;
    float scale;  // 2^exposure, applied to the linear mean before the curve
    uint curve;   // 0 clamp, 1 filmic (host/image/tone_map.h, ToneCurve)
};

#ifdef __cplusplus
}  // namespace penumbra::gpu
#endif
#endif
