// The integrator option registry (scene/integrator_options.h) is consistent: every value
// round-trips name -> enum -> kernel constant -> name, every default is one of its
// option's values, and no two options share a key, a specialization constant or a preview key.
#include <algorithm>
#include <cstring>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "scene/integrator_options.h"
#include "shared/types.h"

using namespace penumbra;

namespace {

// Every name of E reads back as its value, and the names are distinct.
template <class E>
void expectTypedRoundTrip() {
    std::set<std::string> names;
    for (const OptionValue& entry : enumNames(E{})) {
        EXPECT_EQ(fromName<E>(entry.name), E(entry.value)) << entry.name;
        EXPECT_STREQ(toName(E(entry.value)), entry.name);
        EXPECT_EQ(kernelConstant(E(entry.value)), entry.kernel) << entry.name;
        EXPECT_TRUE(names.insert(entry.name).second) << entry.name << " twice";
    }
    EXPECT_FALSE(fromName<E>("no_such_name").has_value());
}

// The specialization constants the host fills from other things than an option.
const std::set<int32_t> kOtherSpecIds = {
    SPEC_COUNT_RAYS,   SPEC_SCENE_FEATURES, SPEC_SAMPLER,          SPEC_TEXTURES, SPEC_EMITTER_FIRST,
    SPEC_INLINE_COUNT, SPEC_NODE_READS,     SPEC_LOOPS_MAY_BE_CUT, SPEC_AOVS,     SPEC_LIGHT_BVH};

}  // namespace

TEST(IntegratorOptions, EveryTypedTableRoundTrips) {
    expectTypedRoundTrip<SamplerType>();
    expectTypedRoundTrip<IntegratorType>();
    expectTypedRoundTrip<AoSampling>();
    expectTypedRoundTrip<Strategy>();
    expectTypedRoundTrip<Heuristic>();
    expectTypedRoundTrip<SphereSampling>();
    expectTypedRoundTrip<QuadSampling>();
    expectTypedRoundTrip<TriangleSampling>();
    expectTypedRoundTrip<LightSelection>();
}

// name -> the enum's number, stored in and read back from IntegratorSettings -> the kernel's
// constant -> the one value with that constant -> the same name.
TEST(IntegratorOptions, EveryChoiceRoundTripsThroughSettingsAndKernel) {
    for (const IntegratorOption& option : integratorOptions()) {
        if (option.kind != OptionKind::Choice) continue;
        ASSERT_FALSE(option.values.empty()) << option.json;
        const bool hasKernelConstants = option.values[0].kernel != kNoKernelConstant;
        EXPECT_EQ(hasKernelConstants, option.specId != kNoSpecialization)
            << option.json << ": a specialization constant needs a kernel constant for every value";
        for (const OptionValue& entry : option.values) {
            const OptionValue* named = valueNamed(option.values, entry.name);
            ASSERT_NE(named, nullptr) << option.json << " " << entry.name;
            IntegratorSettings settings;
            settings.type = option.integrator;
            option.field.set(settings, named->value);
            EXPECT_EQ(optionValue(option, settings), double(entry.value)) << option.json << " " << entry.name;
            const uint32_t kernel = kernelValue(option, settings);
            EXPECT_EQ(kernel != kNoKernelConstant, hasKernelConstants) << option.json << " " << entry.name;
            if (!hasKernelConstants) continue;
            auto sameKernel = [&](const OptionValue& v) { return v.kernel == kernel; };
            EXPECT_EQ(std::count_if(option.values.begin(), option.values.end(), sameKernel), 1)
                << option.json << ": kernel constant " << kernel << " not unique";
            auto back = std::find_if(option.values.begin(), option.values.end(), sameKernel);
            ASSERT_NE(back, option.values.end());
            EXPECT_STREQ(back->name, entry.name) << option.json;
        }
    }
}

TEST(IntegratorOptions, DefaultsAreValidValues) {
    const IntegratorSettings defaults;
    for (const IntegratorOption& option : integratorOptions()) {
        const double value = optionValue(option, defaults);
        switch (option.kind) {
            case OptionKind::Choice:
                EXPECT_NE(valueNumbered(option.values, uint32_t(value)), nullptr) << option.json;
                break;
            case OptionKind::Count:
                EXPECT_LE(option.min, option.max) << option.json;
                EXPECT_GE(value, double(option.min)) << option.json;
                EXPECT_LE(value, double(option.max)) << option.json;
                break;
            case OptionKind::Distance: EXPECT_GT(value, 0.0) << option.json; break;
        }
        // A count or distance stored and read back unchanged (the field is the option's own).
        if (option.kind != OptionKind::Choice) {
            IntegratorSettings settings;
            const double other = option.kind == OptionKind::Count ? double(option.max) : 2.5;
            option.field.set(settings, other);
            EXPECT_EQ(optionValue(option, settings), other) << option.json;
        }
    }
}

TEST(IntegratorOptions, NoTwoOptionsShareAKeySpecializationOrPreviewKey) {
    std::set<std::pair<IntegratorType, std::string>> keys;
    std::set<int32_t> specIds;
    std::set<char> previewKeys;
    for (const IntegratorOption& option : integratorOptions()) {
        EXPECT_STRNE(option.json, "type") << "\"type\" picks the integrator";
        EXPECT_TRUE(keys.insert({option.integrator, option.json}).second) << option.json << " twice";
        EXPECT_EQ(findIntegratorOption(option.integrator, option.json), &option) << option.json;
        if (option.specId != kNoSpecialization) {
            EXPECT_GE(option.specId, 0) << option.json;
            EXPECT_LT(option.specId, SPEC_COUNT) << option.json;
            EXPECT_TRUE(specIds.insert(option.specId).second) << option.json << ": SPEC " << option.specId << " twice";
            EXPECT_FALSE(kOtherSpecIds.count(option.specId)) << option.json << ": SPEC " << option.specId;
        }
        if (!option.preview.keys) continue;
        const size_t count = std::strlen(option.preview.keys);
        EXPECT_TRUE(count == 1 || (option.kind == OptionKind::Choice && count == option.values.size()))
            << option.json << ": one key to cycle or one key per value";
        EXPECT_EQ(option.kind, OptionKind::Choice) << option.json << ": only choices have keys";
        for (size_t i = 0; i < count; ++i)
            EXPECT_TRUE(previewKeys.insert(option.preview.keys[i]).second)
                << option.json << ": key " << option.preview.keys[i] << " twice";
    }
}

// The light tables are built for the scene's light selection: changing it needs a new upload
// (the renderer, a batch's reused session and the preview all ask needsNewUpload); every
// other option is render parameters or a kernel away.
TEST(IntegratorOptions, OnlyLightSelectionNeedsANewUpload) {
    for (const IntegratorOption& option : integratorOptions()) {
        const IntegratorSettings a;
        IntegratorSettings b = a;
        const double now = optionValue(option, a);
        double other = now;
        if (option.kind == OptionKind::Choice) {
            for (const OptionValue& v : option.values)
                if (double(v.value) != now) other = v.value;
        } else if (option.kind == OptionKind::Count) {
            other = now == option.min ? option.max : option.min;
        } else {
            other = now * 0.5;
        }
        ASSERT_NE(other, now) << option.json;
        option.field.set(b, other);
        EXPECT_EQ(needsNewUpload(a, b), std::string(option.json) == "light_selection") << option.json;
        EXPECT_FALSE(needsNewUpload(a, a)) << option.json;
    }
}
