// Small scenes without a BVH: every primitive's shape is compiled into the kernel as
// specialization constants, and a ray is tested against each primitive in turn, in leaf
// order, with no branch and no memory read. bvh.glsl calls this instead of its traversal
// when the host filled the constants (render/inline_geometry.h says when that pays), in the
// kernels built with PENUMBRA_INLINE_GEOMETRY (the "_inline<N>" variants) alone.
//
// Why it pays on llvmpipe: a BVH step reads its node through a texel fetch (a call to a
// generated sampling function) and keeps a per-lane stack, and eight rays in SIMD lanes
// run every loop until the slowest has finished; here the shapes are constants, so an
// axis-aligned wall's zero edge components fold away and a primitive test is a few dozen
// SIMD instructions for all eight rays (docs/PERFORMANCE.md, "Round 8").
#ifndef PENUMBRA_INLINE_GEOMETRY_GLSL
#define PENUMBRA_INLINE_GEOMETRY_GLSL

#include "shared/types.h"
#include "geometry/intersect.glsl"

// How many tests this module unrolls: a multiple of INLINE_CAPACITY_STEP up to
// INLINE_MAX_PRIMITIVES, set where cmake/EmbedShaders.cmake compiles the "<kernel>_inline<N>"
// variants (the host picks the smallest that holds the scene: render/inline_geometry.h).
// llvmpipe's front end inlines every trace site's tests before the constants remove the
// unused ones, and pays for that on every start (docs/PERFORMANCE.md, "Round 8").
#if !defined(PENUMBRA_INLINE_CAPACITY) || PENUMBRA_INLINE_CAPACITY % INLINE_CAPACITY_STEP != 0 || \
    PENUMBRA_INLINE_CAPACITY > INLINE_MAX_PRIMITIVES || INLINE_CAPACITY_STEP != 16
#error "PENUMBRA_INLINE_CAPACITY: a multiple of 16 (the groups below) up to INLINE_MAX_PRIMITIVES"
#endif

// How many of the first primitives are inline (0: none, the kernel traverses the BVH).
layout(constant_id = SPEC_INLINE_COUNT) const uint kInlineCount = 0u;

// Primitive i's INLINE_PRIMITIVE_WORDS constants (shared/types.h): its PRIM_* type, then
// p0, p1, p2 as in Primitive (float bits), for i below INLINE_MAX_PRIMITIVES.
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

// Primitive `index` of type `type` tested against the ray; a hit nearer than hit.t
// replaces hit (selects, not branches: every lane runs every test anyway).
void inlineTest(uint index, uint type, vec3 p0, vec3 p1, vec3 p2, vec3 origin, vec3 dir, inout Hit hit) {
    float t;
    vec2 uv;
    bool found = intersectShape(type, p0, p1, p2, origin, dir, hit.t, t, uv);
    hit.t = found ? t : hit.t;
    hit.primitive = found ? index : hit.primitive;
    hit.uv = found ? uv : hit.uv;
}

// Primitive i's test, compiled out past kInlineCount (the condition is a constant).
#define INLINE_TEST(i)                                                                                        \
    if ((i) < kInlineCount)                                                                                   \
        inlineTest((i), kInlineType##i, vec3(kInline##i##_1, kInline##i##_2, kInline##i##_3),                \
                   vec3(kInline##i##_4, kInline##i##_5, kInline##i##_6),                                      \
                   vec3(kInline##i##_7, kInline##i##_8, kInline##i##_9), origin, dir, hit);

// The nearest of the inline primitives hit with t in (0, hit.t): hit must come in with
// t = tMax and primitive = NO_HIT. Ties go to the lower index, as the test runs in order.
void inlineClosest(vec3 origin, vec3 dir, inout Hit hit) {
    INLINE_TEST(0) INLINE_TEST(1) INLINE_TEST(2) INLINE_TEST(3)
    INLINE_TEST(4) INLINE_TEST(5) INLINE_TEST(6) INLINE_TEST(7)
    INLINE_TEST(8) INLINE_TEST(9) INLINE_TEST(10) INLINE_TEST(11)
    INLINE_TEST(12) INLINE_TEST(13) INLINE_TEST(14) INLINE_TEST(15)
#if PENUMBRA_INLINE_CAPACITY > 16
    INLINE_TEST(16) INLINE_TEST(17) INLINE_TEST(18) INLINE_TEST(19)
    INLINE_TEST(20) INLINE_TEST(21) INLINE_TEST(22) INLINE_TEST(23)
    INLINE_TEST(24) INLINE_TEST(25) INLINE_TEST(26) INLINE_TEST(27)
    INLINE_TEST(28) INLINE_TEST(29) INLINE_TEST(30) INLINE_TEST(31)
#endif
#if PENUMBRA_INLINE_CAPACITY > 32
    INLINE_TEST(32) INLINE_TEST(33) INLINE_TEST(34) INLINE_TEST(35)
    INLINE_TEST(36) INLINE_TEST(37) INLINE_TEST(38) INLINE_TEST(39)
    INLINE_TEST(40) INLINE_TEST(41) INLINE_TEST(42) INLINE_TEST(43)
    INLINE_TEST(44) INLINE_TEST(45) INLINE_TEST(46) INLINE_TEST(47)
#endif
}

#endif
