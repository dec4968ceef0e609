// Small scenes without a BVH: every primitive's shape is compiled into the kernel as
// specialization constants, and a ray is tested against each primitive in turn, with no
// memory read, in groups of eight slots, each behind its bounding box where the box is small
// against the scene (render/inline_geometry.h). bvh.glsl calls this instead of its traversal
// when the host filled the constants (render/inline_geometry.h says when that pays), in the
// kernels built with PENUMBRA_INLINE_GEOMETRY (the "_inline<N>" variants) alone.
//
// Why it pays on llvmpipe: a BVH step reads its node through a texel fetch (a call to a
// generated sampling function) and keeps a per-lane stack, and eight rays in SIMD lanes
// run every loop until the slowest has finished; here the shapes are constants, so an
// axis-aligned wall's zero edge components fold away and a primitive test is a few dozen
// SIMD instructions for all eight rays (docs/performance-history/round-08.md).
#ifndef PENUMBRA_INLINE_GEOMETRY_GLSL
#define PENUMBRA_INLINE_GEOMETRY_GLSL

#include "shared/types.h"
#include "geometry/intersect.glsl"

// How many tests this module unrolls: a multiple of INLINE_CAPACITY_STEP up to
// INLINE_MAX_PRIMITIVES, set where cmake/EmbedShaders.cmake compiles the "<kernel>_inline<N>"
// variants (the host picks the smallest that holds the scene: render/inline_geometry.h).
// llvmpipe's front end inlines every trace site's tests before the constants remove the
// unused ones, and pays for that on every start (docs/performance-history/round-08.md).
#if !defined(PENUMBRA_INLINE_CAPACITY) || PENUMBRA_INLINE_CAPACITY % INLINE_CAPACITY_STEP != 0 || \
    PENUMBRA_INLINE_CAPACITY > INLINE_MAX_PRIMITIVES || INLINE_CAPACITY_STEP != 16
#error "PENUMBRA_INLINE_CAPACITY: a multiple of 16 (the groups below) up to INLINE_MAX_PRIMITIVES"
#endif

// How many of the slots are in use (0: none, the kernel traverses the BVH).
layout(constant_id = SPEC_INLINE_COUNT) const uint kInlineCount = 0u;

// Slot i's INLINE_PRIMITIVE_WORDS constants (shared/types.h): its slot word (the PRIM_* type
// and the primitive's leaf-order index, or INLINE_SLOT_EMPTY), then p0, p1, p2 as in
// Primitive (float bits), for i below INLINE_MAX_PRIMITIVES.
#define INLINE_FLOAT(i, k) \
    layout(constant_id = SPEC_INLINE_FIRST + INLINE_PRIMITIVE_WORDS * (i) + (k)) const float kInline##i##_##k = 0.0;
#define INLINE_PRIMITIVE(i)                                                                          \
    layout(constant_id = SPEC_INLINE_FIRST + INLINE_PRIMITIVE_WORDS * (i)) const uint kInlineType##i = 0u; \
    INLINE_FLOAT(i, 1) INLINE_FLOAT(i, 2) INLINE_FLOAT(i, 3)                                         \
    INLINE_FLOAT(i, 4) INLINE_FLOAT(i, 5) INLINE_FLOAT(i, 6)                                         \
    INLINE_FLOAT(i, 7) INLINE_FLOAT(i, 8) INLINE_FLOAT(i, 9)

INLINE_PRIMITIVE(0) INLINE_PRIMITIVE(1) INLINE_PRIMITIVE(2) INLINE_PRIMITIVE(3)
INLINE_PRIMITIVE(4) INLINE_PRIMITIVE(5) INLINE_PRIMITIVE(6) INLINE_PRIMITIVE(7)
INLINE_PRIMITIVE(8) INLINE_PRIMITIVE(9) INLINE_PRIMITIVE(10) INLINE_PRIMITIVE(11)
INLINE_PRIMITIVE(12) INLINE_PRIMITIVE(13) INLINE_PRIMITIVE(14) INLINE_PRIMITIVE(15)
INLINE_PRIMITIVE(16) INLINE_PRIMITIVE(17) INLINE_PRIMITIVE(18) INLINE_PRIMITIVE(19)
INLINE_PRIMITIVE(20) INLINE_PRIMITIVE(21) INLINE_PRIMITIVE(22) INLINE_PRIMITIVE(23)
INLINE_PRIMITIVE(24) INLINE_PRIMITIVE(25) INLINE_PRIMITIVE(26) INLINE_PRIMITIVE(27)
INLINE_PRIMITIVE(28) INLINE_PRIMITIVE(29) INLINE_PRIMITIVE(30) INLINE_PRIMITIVE(31)
INLINE_PRIMITIVE(32) INLINE_PRIMITIVE(33) INLINE_PRIMITIVE(34) INLINE_PRIMITIVE(35)
INLINE_PRIMITIVE(36) INLINE_PRIMITIVE(37) INLINE_PRIMITIVE(38) INLINE_PRIMITIVE(39)
INLINE_PRIMITIVE(40) INLINE_PRIMITIVE(41) INLINE_PRIMITIVE(42) INLINE_PRIMITIVE(43)
INLINE_PRIMITIVE(44) INLINE_PRIMITIVE(45) INLINE_PRIMITIVE(46) INLINE_PRIMITIVE(47)

// Group g of INLINE_GROUP_SIZE slots (shared/types.h): its box lo.xyz, hi.xyz, and whether
// the box is tested before the slots.
#define INLINE_GROUP_FLOAT(g, k) \
    layout(constant_id = SPEC_INLINE_GROUP_FIRST + INLINE_GROUP_WORDS * (g) + (k)) const float kInlineGroup##g##_##k = 0.0;
#define INLINE_GROUP_BOX(g)                                                                                   \
    INLINE_GROUP_FLOAT(g, 0) INLINE_GROUP_FLOAT(g, 1) INLINE_GROUP_FLOAT(g, 2)                              \
    INLINE_GROUP_FLOAT(g, 3) INLINE_GROUP_FLOAT(g, 4) INLINE_GROUP_FLOAT(g, 5)                              \
    layout(constant_id = SPEC_INLINE_GROUP_FIRST + INLINE_GROUP_WORDS * (g) + 6) const uint kInlineGroupTested##g = 0u;
INLINE_GROUP_BOX(0) INLINE_GROUP_BOX(1) INLINE_GROUP_BOX(2)
INLINE_GROUP_BOX(3) INLINE_GROUP_BOX(4) INLINE_GROUP_BOX(5)
#if INLINE_MAX_GROUPS != 6 || INLINE_CAPACITY_STEP % INLINE_GROUP_SIZE != 0 || INLINE_GROUP_WORDS != 7
#error "inline_geometry.glsl declares six groups of eight slots, seven words each"
#endif

// Records a test's hit of primitive `index` (leaf order) where it is nearer than hit.t
// (selects, not branches: every lane runs every test anyway).
void inlineRecord(bool found, uint index, float t, vec2 uv, inout Hit hit) {
    hit.t = found ? t : hit.t;
    hit.primitive = found ? index : hit.primitive;
    hit.uv = found ? uv : hit.uv;
}

// Slot i's PRIM_* type and leaf-order index, and its points (Primitive's p0, p1, p2).
#define INLINE_TYPE(i) (kInlineType##i & INLINE_SLOT_TYPE_MASK)
#define INLINE_INDEX(i) (kInlineType##i >> INLINE_SLOT_INDEX_SHIFT)
#define INLINE_P0(i) vec3(kInline##i##_1, kInline##i##_2, kInline##i##_3)
#define INLINE_P1(i) vec3(kInline##i##_4, kInline##i##_5, kInline##i##_6)
#define INLINE_P2(i) vec3(kInline##i##_7, kInline##i##_8, kInline##i##_9)

// Slot i's test, compiled out past kInlineCount and for an empty slot (constant conditions).
// The shape's own test is chosen here, by the slot's constant type, rather than through
// intersectShape's dispatch on a parameter: the host folds these constants before the driver
// sees the kernel (host/gpu/spirv_specialization.h), so each slot hands the driver one test
// instead of all three to inline and prune. The same tests, in the same operations, as
// intersectShape runs for that type.
#define INLINE_TEST(i)                                                                                        \
    if ((i) < kInlineCount && INLINE_TYPE(i) != INLINE_SLOT_EMPTY) {                                          \
        float t = 0.0;                                                                                        \
        vec2 uv = vec2(0.0);                                                                                  \
        bool found;                                                                                           \
        if (INLINE_TYPE(i) == PRIM_SPHERE)                                                                    \
            found = intersectSphere(INLINE_P0(i), kInline##i##_4, origin, dir, hit.t, t);                     \
        else if (INLINE_TYPE(i) == PRIM_QUAD)                                                                 \
            found = intersectFlat(INLINE_P0(i), INLINE_P1(i), INLINE_P2(i), true, origin, dir, hit.t, t, uv); \
        else                                                                                                  \
            found = intersectFlat(INLINE_P0(i), INLINE_P1(i) - INLINE_P0(i), INLINE_P2(i) - INLINE_P0(i), false, \
                                  origin, dir, hit.t, t, uv);                                                 \
        inlineRecord(found && INLINE_INDEX(i) != ignore, INLINE_INDEX(i), t, uv, hit);                        \
    }

// Group g's slots, compiled out past kInlineCount, behind its box where the host asks for
// the box test (constant conditions). The box is tested as the BVH tests its nodes
// (intersectBox, up to the nearest hit so far). Where no lane's ray hits it, a driver that
// skips the branches no lane takes (Mesa >= 24.3) skips the group's tests; Mesa 22.3 runs
// them anyway, masked, and pays for the box test too (docs/performance-history/round-09.md).
#define INLINE_GROUP(g, a, b, c, d, e, f, h, i)                                                                  \
    if (INLINE_GROUP_SIZE * (g) < kInlineCount) {                                                                \
        float tEntry;                                                                                            \
        if (kInlineGroupTested##g == 0u ||                                                                       \
            intersectBox(vec3(kInlineGroup##g##_0, kInlineGroup##g##_1, kInlineGroup##g##_2),                   \
                         vec3(kInlineGroup##g##_3, kInlineGroup##g##_4, kInlineGroup##g##_5), origin, invDir, hit.t, \
                         tEntry)) {                                                                              \
            INLINE_TEST(a) INLINE_TEST(b) INLINE_TEST(c) INLINE_TEST(d)                                          \
            INLINE_TEST(e) INLINE_TEST(f) INLINE_TEST(h) INLINE_TEST(i)                                          \
        }                                                                                                        \
    }

// The nearest of the inline primitives hit with t in (0, hit.t): hit must come in with
// t = tMax and primitive = NO_HIT. Ties go to the earlier slot, as the tests run in order.
// Primitive `ignore` (NO_HIT: none) is never hit (bvh.glsl, traceAnyIgnoring).
void inlineClosest(vec3 origin, vec3 dir, uint ignore, inout Hit hit) {
    vec3 invDir = rayInverseDirection(dir);
    INLINE_GROUP(0, 0, 1, 2, 3, 4, 5, 6, 7)
    INLINE_GROUP(1, 8, 9, 10, 11, 12, 13, 14, 15)
#if PENUMBRA_INLINE_CAPACITY > 16
    INLINE_GROUP(2, 16, 17, 18, 19, 20, 21, 22, 23)
    INLINE_GROUP(3, 24, 25, 26, 27, 28, 29, 30, 31)
#endif
#if PENUMBRA_INLINE_CAPACITY > 32
    INLINE_GROUP(4, 32, 33, 34, 35, 36, 37, 38, 39)
    INLINE_GROUP(5, 40, 41, 42, 43, 44, 45, 46, 47)
#endif
}

#endif
