// The integrator options, one row each (integrator_options.cpp): the scene file's key, its
// values (name <-> IntegratorSettings' enum <-> the kernels' constant), the integrator that
// reads it, its specialization constant, its preview key and when the EXR header lists it.
// The parser (integrator_parse.cpp), the header object (integrator_json.cpp, which batch resume
// compares), the kernel's specialization (render/kernel_options.cpp) and the preview's keys
// (preview/integrator_controls.cpp) read the rows; none of them names an option of its own.
// docs/design/layout.md "A new integrator option" says what adding one touches.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <type_traits>
#include <vector>

namespace penumbra {

// How a pixel's samples are placed (shaders/common/rng.glsl). Sobol' is the default, as
// low-discrepancy samplers are in pbrt-v4 and Cycles: unbiased like independent samples,
// with lower error on smooth integrands. Not an integrator option (sampler.type), but
// named and passed to the kernel the same way, so its values are a table of the same kind.
enum class SamplerType { Independent, Sobol };

enum class IntegratorType { AmbientOcclusion, Direct };
enum class AoSampling { Uniform, Cosine };
enum class Strategy { Light, Bsdf, Mis, Mixture, Ris };
enum class Heuristic { Balance, Power };
enum class SphereSampling { Area, Cap, SolidAngle };
enum class QuadSampling { Area, SolidAngle };
enum class TriangleSampling { Area, SolidAngle };
enum class LightSelection { Uniform, Power, Bvh };

// The member initializers are the options' defaults (SCENE_FORMAT.md); the registry test
// checks that each is one of its option's values.
struct IntegratorSettings {
    IntegratorType type = IntegratorType::Direct;
    // ao
    AoSampling aoSampling = AoSampling::Cosine;
    float aoMaxDistance = 1e30f;
    // direct
    Strategy strategy = Strategy::Mis;
    Heuristic heuristic = Heuristic::Power;
    uint32_t lightSamples = 1;
    uint32_t bsdfSamples = 1;
    // strategy "ris": light candidates per draw (SCENE_FORMAT.md `ris_candidates`, 1..64)
    uint32_t risCandidates = 8;
    SphereSampling sphereSampling = SphereSampling::SolidAngle;
    QuadSampling quadSampling = QuadSampling::SolidAngle;
    TriangleSampling triangleSampling = TriangleSampling::Area;
    LightSelection lightSelection = LightSelection::Power;
    // Whether the scene, --set or the preview set quad_sampling / triangle_sampling: the
    // header lists them only then (integrator_json.h).
    bool quadSamplingGiven = false;
    bool triangleSamplingGiven = false;
};

// One value of a choice option.
struct OptionValue {
    const char* name;  // as the scene file spells it
    uint32_t value;    // the enum's number in IntegratorSettings (uint32_t(Strategy::Mis))
    uint32_t kernel;   // the kernels' constant for it (STRATEGY_MIS), kNoKernelConstant if none
};
inline constexpr uint32_t kNoKernelConstant = UINT32_MAX;
inline constexpr int32_t kNoSpecialization = -1;

enum class OptionKind {
    Choice,    // a string, one of `values`
    Count,     // an integer in [min, max]
    Distance,  // a number > 0
};

// Where IntegratorSettings keeps an option. The value travels as a double: an enum's
// number, a count and a float distance are each exact in one.
struct OptionField {
    double (*get)(const IntegratorSettings&);
    void (*set)(IntegratorSettings&, double);
};

template <auto Member>
double getOption(const IntegratorSettings& s) {
    const auto value = s.*Member;
    if constexpr (std::is_enum_v<decltype(value)>) return double(uint32_t(value));
    else return double(value);
}

template <auto Member>
void setOption(IntegratorSettings& s, double value) {
    using T = std::remove_reference_t<decltype(s.*Member)>;
    if constexpr (std::is_enum_v<T>) s.*Member = T(uint32_t(value));
    else s.*Member = T(value);
}

template <auto Member>
constexpr OptionField optionField() {
    return {&getOption<Member>, &setOption<Member>};
}

// The preview's key for an option (preview/integrator_controls.cpp): one key that steps
// through the values, or one key per value that sets it.
struct PreviewKeys {
    const char* keys = nullptr;  // nullptr: none; one character: it cycles; one per value: each sets its value
    const char* label = "";      // the help line before the values: "MIS heuristic", "strategy"
    const char* note = "";       // after the first key's help line
};

struct IntegratorOption {
    const char* json;  // the key in the scene's integrator object and in the header's
    IntegratorType integrator;
    OptionKind kind;
    std::span<const OptionValue> values = {};  // Choice
    uint32_t min = 0, max = 0;                 // Count
    int32_t specId = kNoSpecialization;        // SPEC_* (shaders/shared/types.h)
    OptionField field = {};
    // When not null, the scene, --set or the preview set it; the header lists the option
    // only then, so headers of scenes that do not use it stay as before it existed.
    bool IntegratorSettings::*given = nullptr;
    // When not null, the option matters only where this holds: elsewhere the kernel gets
    // the default (no split pipeline cache) and the header leaves it out.
    bool (*appliesTo)(const IntegratorSettings&) = nullptr;
    PreviewKeys preview = {};
    // The scene's GPU arrays are built for the option's value (light_selection: the light
    // tables), so a change of it needs a new upload, not only new render parameters.
    bool shapesUpload = false;
};

// Every option, in the order the parser reads them (so the first of several bad values is
// the one reported) and the order the preview lists its keys in (integrator_options.cpp).
std::span<const IntegratorOption> integratorOptions();

// The option of `integrator` named `json`; nullptr when it has none.
const IntegratorOption* findIntegratorOption(IntegratorType integrator, std::string_view json);

// The option's value in `settings`, and the value the kernel gets for it (its OptionValue's
// kernel constant for a choice, the number for a count).
double optionValue(const IntegratorOption& option, const IntegratorSettings& settings);
uint32_t kernelValue(const IntegratorOption& option, const IntegratorSettings& settings);

// Whether `a` and `b` differ in an option that shapes the upload (shapesUpload): a renderer
// of one cannot render the other by new render parameters or a new kernel alone.
bool needsNewUpload(const IntegratorSettings& a, const IntegratorSettings& b);

// Whether the option is in effect for `settings`: of its integrator type and, where the
// option says so, of the settings it applies to.
bool optionInEffect(const IntegratorOption& option, const IntegratorSettings& settings);

// The entry of `values` numbered `value` / named `name`; nullptr when there is none.
const OptionValue* valueNumbered(std::span<const OptionValue> values, uint32_t value);
const OptionValue* valueNamed(std::span<const OptionValue> values, std::string_view name);

// ---- The same tables, typed by enum -------------------------------------------------

// The values of an enum type's option, found by overload on a value of it; table order is
// the order error messages list the choices in and the preview steps through them.
std::span<const OptionValue> enumNames(SamplerType);
std::span<const OptionValue> enumNames(IntegratorType);
std::span<const OptionValue> enumNames(AoSampling);
std::span<const OptionValue> enumNames(Strategy);
std::span<const OptionValue> enumNames(Heuristic);
std::span<const OptionValue> enumNames(SphereSampling);
std::span<const OptionValue> enumNames(QuadSampling);
std::span<const OptionValue> enumNames(TriangleSampling);
std::span<const OptionValue> enumNames(LightSelection);

// The scene-file name of `value` ("?" only for a value outside its enum).
template <class E>
const char* toName(E value) {
    for (const OptionValue& entry : enumNames(E{}))
        if (entry.value == uint32_t(value)) return entry.name;
    return "?";
}

// The value named `name`, or nothing when no value of E has that name.
template <class E>
std::optional<E> fromName(std::string_view name) {
    for (const OptionValue& entry : enumNames(E{}))
        if (name == entry.name) return E(entry.value);
    return std::nullopt;
}

// The kernels' constant for `value` (kNoKernelConstant where there is none).
template <class E>
uint32_t kernelConstant(E value) {
    for (const OptionValue& entry : enumNames(E{}))
        if (entry.value == uint32_t(value)) return entry.kernel;
    return kNoKernelConstant;
}

// The value after `value` in table order, the first after the last: the order in which the
// preview's keys step through an option's values.
template <class E>
E nextValue(E value) {
    auto table = enumNames(E{});
    for (size_t i = 0; i < table.size(); ++i)
        if (table[i].value == uint32_t(value)) return E(table[(i + 1) % table.size()].value);
    return E(table[0].value);
}

// Every name of a table, in table order.
std::vector<const char*> allNames(std::span<const OptionValue> values);
template <class E>
std::vector<const char*> allNames() {
    return allNames(enumNames(E{}));
}

}  // namespace penumbra
