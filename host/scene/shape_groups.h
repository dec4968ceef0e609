// Groups and instances (SCENE_FORMAT.md "Mesh files, transforms and instances"): a group is
// a named list of shapes that is not rendered by itself; an instance places a copy of it
// with its own to_world and, optionally, its own material. load_json.cpp reads a group's
// shapes once, into the group's frame, and an instance's copy from them; the rules of
// names and references live here.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "scene/json_reader.h"
#include "scene/scene.h"

namespace penumbra {

// A group as read: its shapes with their own to_world applied, the lights of its glTF
// shapes, and whether an instance names it.
struct ShapeGroup {
    std::string path;  // its JSON path, for notes
    std::vector<Shape> shapes;
    std::vector<Light> lights;
    bool used = false;
    // Its traced shapes' Scene::instancedGroups entries, once an instance needs them: for
    // instances without a material of their own, and for those with one; -1: none yet.
    int32_t tracedOwn = -1, tracedWithMaterial = -1;
};

// The world primitives that instances may copy into a scene (their emitters, and the
// shapes they cannot trace: copiedByInstances in load_json.cpp), spheres, quads and
// triangles (host memory for each, and the BVH's limit of BVH_MAX_PRIMITIVES): beyond it
// the scene is refused with the instance that crossed it, not left to run out of memory.
inline constexpr uint64_t kMaxInstancedPrimitives = uint64_t(1) << 24;

// Whether `r` is an object of "type": `type` ("group": read before the other shapes;
// "instance": counted before any is copied).
bool isShapeOfType(const JsonReader& r, const char* type);

// The group that `of` names; fails on `of` when there is none, listing the names.
ShapeGroup& groupNamed(const JsonReader& of, std::map<std::string, ShapeGroup>& groups);

// One note per group that no instance names (declared but never rendered: likely a typo
// in an instance's `of`, but harmless).
void noteUnusedGroups(const std::map<std::string, ShapeGroup>& groups, const std::string& label,
                      std::vector<std::string>& notes);

// Fails on the first instance of `shapes` (the scene's) whose copy would take the
// primitives that instances copy past kMaxInstancedPrimitives; before any copy is made.
// `copied(shape, instance)`: whether the instance copies the group's shape (only copies count).
void checkInstancedPrimitives(const JsonReader& shapes, std::map<std::string, ShapeGroup>& groups,
                              const std::function<bool(const Shape&, const JsonReader&)>& copied);

// Primitives of a shape on the GPU: one for a sphere or quad, one per triangle of a mesh.
uint64_t primitiveCount(const Shape& s);

}  // namespace penumbra
