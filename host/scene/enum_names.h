// The scene-file name of every value of the integrator and sampler enums (SCENE_FORMAT.md),
// one table per enum, and toName/fromName over them. The parser, the EXR header, the preview
// and batch all spell the options through these tables.
#pragma once

#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "scene/scene.h"

namespace penumbra {

template <class E>
struct EnumName {
    E value;
    const char* name;
};

// Table order is the order error messages list the choices in.
inline constexpr EnumName<SamplerType> kSamplerTypeNames[] = {{SamplerType::Sobol, "sobol"},
                                                              {SamplerType::Independent, "independent"}};
inline constexpr EnumName<IntegratorType> kIntegratorTypeNames[] = {{IntegratorType::AmbientOcclusion, "ao"},
                                                                    {IntegratorType::Direct, "direct"}};
inline constexpr EnumName<AoSampling> kAoSamplingNames[] = {{AoSampling::Cosine, "cosine"},
                                                            {AoSampling::Uniform, "uniform"}};
inline constexpr EnumName<Strategy> kStrategyNames[] = {{Strategy::Light, "light"},
                                                        {Strategy::Bsdf, "bsdf"},
                                                        {Strategy::Mis, "mis"},
                                                        {Strategy::Mixture, "mixture"},
                                                        {Strategy::Ris, "ris"}};
inline constexpr EnumName<Heuristic> kHeuristicNames[] = {{Heuristic::Balance, "balance"}, {Heuristic::Power, "power"}};
inline constexpr EnumName<SphereSampling> kSphereSamplingNames[] = {
    {SphereSampling::Area, "area"}, {SphereSampling::Cap, "cap"}, {SphereSampling::SolidAngle, "solid_angle"}};
inline constexpr EnumName<QuadSampling> kQuadSamplingNames[] = {{QuadSampling::Area, "area"},
                                                                {QuadSampling::SolidAngle, "solid_angle"}};
inline constexpr EnumName<TriangleSampling> kTriangleSamplingNames[] = {{TriangleSampling::Area, "area"},
                                                                        {TriangleSampling::SolidAngle, "solid_angle"}};
inline constexpr EnumName<LightSelection> kLightSelectionNames[] = {
    {LightSelection::Uniform, "uniform"}, {LightSelection::Power, "power"}, {LightSelection::Bvh, "bvh"}};

// The table of an enum type, found by overload on a value of it.
constexpr std::span<const EnumName<SamplerType>> enumNames(SamplerType) { return kSamplerTypeNames; }
constexpr std::span<const EnumName<IntegratorType>> enumNames(IntegratorType) { return kIntegratorTypeNames; }
constexpr std::span<const EnumName<AoSampling>> enumNames(AoSampling) { return kAoSamplingNames; }
constexpr std::span<const EnumName<Strategy>> enumNames(Strategy) { return kStrategyNames; }
constexpr std::span<const EnumName<Heuristic>> enumNames(Heuristic) { return kHeuristicNames; }
constexpr std::span<const EnumName<SphereSampling>> enumNames(SphereSampling) { return kSphereSamplingNames; }
constexpr std::span<const EnumName<QuadSampling>> enumNames(QuadSampling) { return kQuadSamplingNames; }
constexpr std::span<const EnumName<TriangleSampling>> enumNames(TriangleSampling) { return kTriangleSamplingNames; }
constexpr std::span<const EnumName<LightSelection>> enumNames(LightSelection) { return kLightSelectionNames; }

// The scene-file name of `value` ("?" only for a value outside its enum).
template <class E>
constexpr const char* toName(E value) {
    for (const EnumName<E>& entry : enumNames(E{}))
        if (entry.value == value) return entry.name;
    return "?";
}

// The value named `name`, or nothing when no value of E has that name.
template <class E>
constexpr std::optional<E> fromName(std::string_view name) {
    for (const EnumName<E>& entry : enumNames(E{}))
        if (name == entry.name) return entry.value;
    return std::nullopt;
}

// The value after `value` in table order, the first after the last: the order in which the
// preview's keys step through an option's values.
template <class E>
constexpr E nextValue(E value) {
    auto table = enumNames(E{});
    for (size_t i = 0; i < table.size(); ++i)
        if (table[i].value == value) return table[(i + 1) % table.size()].value;
    return table[0].value;
}

// Every name of E, in table order.
template <class E>
std::vector<const char*> allNames() {
    std::vector<const char*> names;
    for (const EnumName<E>& entry : enumNames(E{})) names.push_back(entry.name);
    return names;
}

}  // namespace penumbra
