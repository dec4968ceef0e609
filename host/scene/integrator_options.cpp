// The integrator option registry: the value tables and one row per option (see
// integrator_options.h), and the lookups over them.
#include "scene/integrator_options.h"

#include "shared/types.h"

namespace penumbra {
namespace {

// Table order is the order error messages list the choices in and the preview steps through.
constexpr OptionValue kSamplerTypeValues[] = {
    {"sobol", uint32_t(SamplerType::Sobol), gpu::SAMPLER_SOBOL},
    {"independent", uint32_t(SamplerType::Independent), gpu::SAMPLER_INDEPENDENT}};
// The integrator type picks the kernel (render/renderer.cpp), not a constant in it.
constexpr OptionValue kIntegratorTypeValues[] = {{"ao", uint32_t(IntegratorType::AmbientOcclusion), kNoKernelConstant},
                                                 {"direct", uint32_t(IntegratorType::Direct), kNoKernelConstant}};
constexpr OptionValue kAoSamplingValues[] = {{"cosine", uint32_t(AoSampling::Cosine), gpu::AO_COSINE},
                                             {"uniform", uint32_t(AoSampling::Uniform), gpu::AO_UNIFORM}};
constexpr OptionValue kStrategyValues[] = {{"light", uint32_t(Strategy::Light), gpu::STRATEGY_LIGHT},
                                           {"bsdf", uint32_t(Strategy::Bsdf), gpu::STRATEGY_BSDF},
                                           {"mis", uint32_t(Strategy::Mis), gpu::STRATEGY_MIS},
                                           {"mixture", uint32_t(Strategy::Mixture), gpu::STRATEGY_MIXTURE},
                                           {"ris", uint32_t(Strategy::Ris), gpu::STRATEGY_RIS}};
constexpr OptionValue kHeuristicValues[] = {{"balance", uint32_t(Heuristic::Balance), gpu::HEURISTIC_BALANCE},
                                            {"power", uint32_t(Heuristic::Power), gpu::HEURISTIC_POWER}};
constexpr OptionValue kSphereSamplingValues[] = {
    {"area", uint32_t(SphereSampling::Area), gpu::SPHERE_AREA},
    {"cap", uint32_t(SphereSampling::Cap), gpu::SPHERE_CAP},
    {"solid_angle", uint32_t(SphereSampling::SolidAngle), gpu::SPHERE_SOLID_ANGLE}};
constexpr OptionValue kQuadSamplingValues[] = {
    {"area", uint32_t(QuadSampling::Area), gpu::QUAD_AREA},
    {"solid_angle", uint32_t(QuadSampling::SolidAngle), gpu::QUAD_SOLID_ANGLE}};
constexpr OptionValue kTriangleSamplingValues[] = {
    {"area", uint32_t(TriangleSampling::Area), gpu::TRIANGLE_AREA},
    {"solid_angle", uint32_t(TriangleSampling::SolidAngle), gpu::TRIANGLE_SOLID_ANGLE}};
// The selection is in the light tables the host builds (render/scene_arrays.cpp), not a
// kernel constant; "bvh" also sets SPEC_LIGHT_BVH (render/kernel_options.cpp).
constexpr OptionValue kLightSelectionValues[] = {{"uniform", uint32_t(LightSelection::Uniform), kNoKernelConstant},
                                                 {"power", uint32_t(LightSelection::Power), kNoKernelConstant},
                                                 {"bvh", uint32_t(LightSelection::Bvh), kNoKernelConstant}};

bool strategyIsRis(const IntegratorSettings& s) { return s.strategy == Strategy::Ris; }

// Every option, in the order the parser reads them (so the first of several bad values is
// the one reported) and the order the preview lists its keys in.
constexpr IntegratorOption kIntegratorOptions[] = {
    {.json = "sampling",
     .integrator = IntegratorType::AmbientOcclusion,
     .kind = OptionKind::Choice,
     .values = kAoSamplingValues,
     .specId = SPEC_AO_SAMPLING,
     .field = optionField<&IntegratorSettings::aoSampling>()},
    {.json = "max_distance",
     .integrator = IntegratorType::AmbientOcclusion,
     .kind = OptionKind::Distance,
     .field = optionField<&IntegratorSettings::aoMaxDistance>()},  // a RenderParams field, not a constant
    {.json = "strategy",
     .integrator = IntegratorType::Direct,
     .kind = OptionKind::Choice,
     .values = kStrategyValues,
     .specId = SPEC_STRATEGY,
     .field = optionField<&IntegratorSettings::strategy>(),
     .preview = {"12345", "strategy", " (direct integrator)"}},
    {.json = "heuristic",
     .integrator = IntegratorType::Direct,
     .kind = OptionKind::Choice,
     .values = kHeuristicValues,
     .specId = SPEC_HEURISTIC,
     .field = optionField<&IntegratorSettings::heuristic>(),
     .preview = {"h", "MIS heuristic"}},
    {.json = "light_samples",
     .integrator = IntegratorType::Direct,
     .kind = OptionKind::Count,
     .min = 0,
     .max = 1 << 16,
     .specId = SPEC_LIGHT_SAMPLES,
     .field = optionField<&IntegratorSettings::lightSamples>()},
    {.json = "bsdf_samples",
     .integrator = IntegratorType::Direct,
     .kind = OptionKind::Count,
     .min = 0,
     .max = 1 << 16,
     .specId = SPEC_BSDF_SAMPLES,
     .field = optionField<&IntegratorSettings::bsdfSamples>()},
    {.json = "sphere_sampling",
     .integrator = IntegratorType::Direct,
     .kind = OptionKind::Choice,
     .values = kSphereSamplingValues,
     .specId = SPEC_SPHERE_SAMPLING,
     .field = optionField<&IntegratorSettings::sphereSampling>(),
     .preview = {"s", "sphere sampling"}},
    {.json = "quad_sampling",
     .integrator = IntegratorType::Direct,
     .kind = OptionKind::Choice,
     .values = kQuadSamplingValues,
     .specId = SPEC_QUAD_SAMPLING,
     .field = optionField<&IntegratorSettings::quadSampling>(),
     .given = &IntegratorSettings::quadSamplingGiven,
     .preview = {"t", "quad sampling"}},
    {.json = "triangle_sampling",
     .integrator = IntegratorType::Direct,
     .kind = OptionKind::Choice,
     .values = kTriangleSamplingValues,
     .specId = SPEC_TRIANGLE_SAMPLING,
     .field = optionField<&IntegratorSettings::triangleSampling>(),
     .given = &IntegratorSettings::triangleSamplingGiven,
     .preview = {"m", "mesh-light triangle sampling"}},
    {.json = "light_selection",
     .integrator = IntegratorType::Direct,
     .kind = OptionKind::Choice,
     .values = kLightSelectionValues,
     .field = optionField<&IntegratorSettings::lightSelection>(),
     .preview = {"l", "light selection", " (rebuilds the light tables)"},
     .shapesUpload = true},
    {.json = "ris_candidates",
     .integrator = IntegratorType::Direct,
     .kind = OptionKind::Count,
     .min = 1,
     .max = 64,
     .specId = SPEC_RIS_CANDIDATES,
     .field = optionField<&IntegratorSettings::risCandidates>(),
     .appliesTo = &strategyIsRis},
};

}  // namespace

std::span<const IntegratorOption> integratorOptions() { return kIntegratorOptions; }

std::span<const OptionValue> enumNames(SamplerType) { return kSamplerTypeValues; }
std::span<const OptionValue> enumNames(IntegratorType) { return kIntegratorTypeValues; }
std::span<const OptionValue> enumNames(AoSampling) { return kAoSamplingValues; }
std::span<const OptionValue> enumNames(Strategy) { return kStrategyValues; }
std::span<const OptionValue> enumNames(Heuristic) { return kHeuristicValues; }
std::span<const OptionValue> enumNames(SphereSampling) { return kSphereSamplingValues; }
std::span<const OptionValue> enumNames(QuadSampling) { return kQuadSamplingValues; }
std::span<const OptionValue> enumNames(TriangleSampling) { return kTriangleSamplingValues; }
std::span<const OptionValue> enumNames(LightSelection) { return kLightSelectionValues; }

const IntegratorOption* findIntegratorOption(IntegratorType integrator, std::string_view json) {
    for (const IntegratorOption& option : integratorOptions())
        if (option.integrator == integrator && json == option.json) return &option;
    return nullptr;
}

double optionValue(const IntegratorOption& option, const IntegratorSettings& settings) {
    return option.field.get(settings);
}

uint32_t kernelValue(const IntegratorOption& option, const IntegratorSettings& settings) {
    const double value = optionValue(option, settings);
    if (option.kind != OptionKind::Choice) return uint32_t(value);
    const OptionValue* entry = valueNumbered(option.values, uint32_t(value));
    return entry ? entry->kernel : kNoKernelConstant;
}

bool needsNewUpload(const IntegratorSettings& a, const IntegratorSettings& b) {
    for (const IntegratorOption& option : integratorOptions())
        if (option.shapesUpload && optionValue(option, a) != optionValue(option, b)) return true;
    return false;
}

bool optionInEffect(const IntegratorOption& option, const IntegratorSettings& settings) {
    return option.integrator == settings.type && (!option.appliesTo || option.appliesTo(settings));
}

const OptionValue* valueNumbered(std::span<const OptionValue> values, uint32_t value) {
    for (const OptionValue& entry : values)
        if (entry.value == value) return &entry;
    return nullptr;
}

const OptionValue* valueNamed(std::span<const OptionValue> values, std::string_view name) {
    for (const OptionValue& entry : values)
        if (name == entry.name) return &entry;
    return nullptr;
}

std::vector<const char*> allNames(std::span<const OptionValue> values) {
    std::vector<const char*> names;
    for (const OptionValue& entry : values) names.push_back(entry.name);
    return names;
}

}  // namespace penumbra
