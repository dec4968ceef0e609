// Instances of groups (SCENE_FORMAT.md "instance"), the second level of a two-level BVH: a
// PRIM_INSTANCE primitive in the scene's tree stands for one placement of a group, whose
// shapes sit once in a tree of their own, in the group's frame (host/render/
// instance_arrays.h builds both). A ray that reaches one is moved into that frame and
// traverses the group's tree there; the hit keeps the instance (Hit.instance), so that
// surface.glsl, instanceSurfaceAt, moves the surface point back into the world.
// Included by bvh.glsl, between the node test and the primitive tests, in every kernel but
// the "_address" ones: scenes with instances trace with the local-array stack
// (render/instance_arrays.h, traversalWithInstances), and scenes without compile none of
// it (hasPrimitive(PRIM_INSTANCE) is false).
#ifndef PENUMBRA_INSTANCES_GLSL
#define PENUMBRA_INSTANCES_GLSL

layout(std430, binding = BINDING_INSTANCES) readonly restrict buffer Instances { Instance instances[]; };

// The ray origin + t dir in the instance's frame: both through worldToObject, the direction
// as a vector and not normalized, so that the same t names the same point on both rays and
// every distance a traversal compares stays the world's (pbrt-v4 section 6.1.4, instances:
// the same unnormalized transformed ray).
void rayToObject(Instance instance, vec3 origin, vec3 dir, out vec3 objectOrigin, out vec3 objectDir) {
    vec4 o = vec4(origin, 1.0);
    objectOrigin = vec3(dot(instance.worldToObject0, o), dot(instance.worldToObject1, o), dot(instance.worldToObject2, o));
    objectDir = vec3(dot(instance.worldToObject0.xyz, dir), dot(instance.worldToObject1.xyz, dir),
                     dot(instance.worldToObject2.xyz, dir));
}

// Instance `index` tested against the ray up to hit.t, as testPrimitive tests a primitive:
// the closest hit in the group's tree, where there is one closer than hit.t, becomes `hit`
// (its primitive, uv and t, with hit.instance = index) and the result is true. The
// group's tree is walked as traverse walks the scene's (while-while, a local-array stack of
// nodes with their children still to visit) and closest-first also for shadow rays: within
// one instance the nearest blocker is found, then the query ends. The walk is a copy of
// traverse's loop, not a call of it: traverse calls this function, and GLSL has no recursion.
bool testInstance(uint index, vec3 origin, vec3 dir, inout Hit hit) {
    Instance instance = instances[index];
    vec3 o, d;
    rayToObject(instance, origin, dir, o, d);
    if (!isFiniteVec(o) || !isFiniteVec(d)) return false;
    vec3 invDir = rayInverseDirection(d);
    bool found = false;
    uint stack[BVH_MAX_DEPTH];
    int sp = 0;
    uint node = instance.root, allowed = WIDE_ALL_CHILDREN;
    while (true) {
        bool atLeaf = false;
        uint leaf = 0u;
        while (true) {
            vec4 tEntry;
            uvec4 ref;
            uint hits = intersectWideNode(node, o, invDir, hit.t, tEntry, ref) & allowed;
            if (hits == 0u) break;
            uint c = nearestChild(hits, tEntry);
            uint rest = hits & ~(1u << c);
            if (rest != 0u) {
                stack[sp] = node | (rest << WIDE_STACK_MASK_SHIFT);
                ++sp;
            }
            uint next = c == 0u ? ref.x : (c == 1u ? ref.y : (c == 2u ? ref.z : ref.w));
            if ((next >> BVH_COUNT_SHIFT) != 0u) {
                atLeaf = true;
                leaf = next;
                break;
            }
            node = next;
            allowed = WIDE_ALL_CHILDREN;
        }
        if (atLeaf) {
            uint first = leaf & BVH_OFFSET_MASK, end = first + (leaf >> BVH_COUNT_SHIFT);
            for (uint i = first; i < end; ++i) {
                float t;
                vec2 uv;
                if (intersectPrimitive(loadPrimitive(i), o, d, hit.t, t, uv)) {
                    hit.t = t;
                    hit.primitive = i;
                    hit.uv = uv;
                    hit.instance = index;
                    found = true;
                }
            }
        }
        if (sp == 0) break;
        --sp;
        uint entry = stack[sp];
        node = entry & WIDE_STACK_NODE_MASK;
        allowed = entry >> WIDE_STACK_MASK_SHIFT;
    }
    return found;
}

#endif
