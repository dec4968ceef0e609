#version 460
// Cost of the traversal stack: each invocation runs a depth-first traversal of an implicit
// complete binary tree of depth STEPS (node i has children 2i+1 and 2i+2, leaves at depth
// STEPS), where whether a lane visits a child depends on a hash of the node it loaded and of
// the lane, like box tests; both children visited -> the far one is deferred. Compiled once
// per stack kind by tools/bench/microbenchmarks/CMakeLists.txt (-DSTACK_*). Nodes come from a
// storage buffer in every variant, so the stack is the only difference.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

layout(std430, binding = 1) readonly restrict buffer Nodes { vec4 nodes[]; };

// Full stacks hold one deferred node per level at most: 64 entries as in shaders/geometry.
#define STACK_SIZE 64

#if defined(STACK_SHARED)
// Each invocation's slice, interleaved so that one level of all lanes is contiguous.
shared uint sharedStack[STACK_SIZE * 64];
#define STACK(sp) sharedStack[(sp) * 64u + gl_LocalInvocationIndex]
#elif defined(STACK_SHORT)
// A ring of SHORT_STACK entries: a push onto a full ring overwrites the oldest entry, whose
// subtree is then found again by a restart from the root along the trail (Laine 2010,
// "Restart Trail for Stackless BVH Traversal", with a short stack as in its section 4).
#define SHORT_STACK 4u
#elif defined(STACK_TRAIL)
// No stack at all: every pop restarts from the root along the trail (Laine 2010).
#elif !defined(STACK_LOCAL)
#error "no STACK_* defined"
#endif

// Which children of `node` this lane visits (bit 0: left, bit 1: right).
uint visit(vec4 a, uint salt) {
    uint h = hash(floatBitsToUint(a.w) ^ salt);
    return uint((h & 0xffffu) < pc.threshold) | (uint((h >> 16) < pc.threshold) << 1);
}

void main() {
    uint id = gl_GlobalInvocationID.x;
    uint salt = hash(id);
    float acc = 0.0;
    uint fetches = 0u;
    uint node = 0u;
#if defined(STACK_LOCAL)
    uint stack[STACK_SIZE];
#endif
#if defined(STACK_LOCAL) || defined(STACK_SHARED)
    uint sp = 0u;
    while (true) {
        vec4 a = nodes[2u * node], b = nodes[2u * node + 1u];
        ++fetches;
        bool descend = false;
        if (findMSB(node + 1u) < int(STEPS)) {
            uint v = visit(a, salt);
            acc += a.x * b.y;
            if (v == 3u) {
    #if defined(STACK_LOCAL)
                stack[sp] = 2u * node + 2u;
    #else
                STACK(sp) = 2u * node + 2u;
    #endif
                ++sp;
            }
            descend = v != 0u;
            node = v == 2u ? 2u * node + 2u : 2u * node + 1u;
        } else {
            acc += a.z;
        }
        if (!descend) {
            if (sp == 0u) break;
            --sp;
    #if defined(STACK_LOCAL)
            node = stack[sp];
    #else
            node = STACK(sp);
    #endif
        }
    }
#else
    // trail bit l set: at depth l, the near child's subtree is finished (or there is only
    // one child), so a walk from the root takes the far one.
    uint trail = 0u;
    // After a restart, the nodes down to depth replayUntil are walked again: their work is
    // counted once only, so that every variant computes the same sum.
    int replayUntil = -1;
    #if defined(STACK_SHORT)
    uint ring[SHORT_STACK];
    uint head = 0u, count = 0u;
    #endif
    while (true) {
        vec4 a = nodes[2u * node], b = nodes[2u * node + 1u];
        ++fetches;
        uint level = uint(findMSB(node + 1u));
        bool replay = int(level) <= replayUntil;
        if (int(level) == replayUntil) replayUntil = -1;
        bool descend = false;
        if (level < STEPS) {
            uint v = visit(a, salt);
            if (!replay) acc += a.x * b.y;
            bool farSide = ((trail >> level) & 1u) != 0u;
            if (v == 3u) {
    #if defined(STACK_SHORT)
                if (!farSide) {
                    ring[head] = 2u * node + 2u;
                    head = (head + 1u) & (SHORT_STACK - 1u);
                    count = min(count + 1u, SHORT_STACK);
                }
    #endif
                node = farSide ? 2u * node + 2u : 2u * node + 1u;
                descend = true;
            } else if (v != 0u) {
                trail |= 1u << level;
                node = v == 2u ? 2u * node + 2u : 2u * node + 1u;
                descend = true;
            }
        } else {
            acc += a.z;
        }
        if (!descend) {
            uint pending = ~trail & ((1u << level) - 1u);
            if (pending == 0u) break;
            uint l = uint(findMSB(pending));
            trail = (trail | (1u << l)) & ((2u << l) - 1u);
    #if defined(STACK_SHORT)
            if (count > 0u) {
                head = (head - 1u) & (SHORT_STACK - 1u);
                --count;
                node = ring[head];
            } else {
                node = 0u;
                replayUntil = int(l);
            }
    #else
            node = 0u;
            replayUntil = int(l);
    #endif
        }
    }
#endif
    results[id] = vec2(acc, float(fetches));
}
