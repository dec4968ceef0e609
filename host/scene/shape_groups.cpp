// Groups and instances: names, references and the copy limit (see shape_groups.h).
#include "scene/shape_groups.h"

namespace penumbra {

bool isShapeOfType(const JsonReader& r, const char* type) {
    const nlohmann::json& j = r.json();
    if (!j.is_object()) return false;
    auto it = j.find("type");
    return it != j.end() && it->is_string() && it->get<std::string>() == type;
}

ShapeGroup& groupNamed(const JsonReader& of, std::map<std::string, ShapeGroup>& groups) {
    std::string name = of.string();
    auto it = groups.find(name);
    if (it != groups.end()) return it->second;
    std::string known;
    for (const auto& [n, g] : groups) known += (known.empty() ? "" : ", ") + ("\"" + n + "\"");
    of.fail("no group named \"" + name + "\" (" +
            (known.empty() ? "the scene declares no groups" : "groups: " + known) + ")");
}

void noteUnusedGroups(const std::map<std::string, ShapeGroup>& groups, const std::string& label,
                      std::vector<std::string>& notes) {
    for (const auto& [name, group] : groups)
        if (!group.used)
            notes.push_back(label + ": " + group.path + ": group \"" + name +
                            "\" is placed by no instance and is not rendered");
}

uint64_t primitiveCount(const Shape& s) { return s.type == ShapeType::Mesh ? s.indices.size() / 3 : 1; }

void checkInstancedPrimitives(const JsonReader& shapes, std::map<std::string, ShapeGroup>& groups,
                              const std::function<bool(const Shape&, const JsonReader&)>& copied) {
    uint64_t count = 0;
    for (size_t i = 0; i < shapes.size(); ++i) {
        const JsonReader r = shapes[i];
        if (!isShapeOfType(r, "instance")) continue;
        for (const Shape& s : groupNamed(r.at("of"), groups).shapes)
            if (copied(s, r)) count += primitiveCount(s);
        if (count > kMaxInstancedPrimitives)
            r.fail("the instances copy more than " + std::to_string(kMaxInstancedPrimitives) +
                   " primitives into the scene (README: ranges)");
    }
}

}  // namespace penumbra
