// The enum name tables (scene/enum_names.h) and the header's integrator object rebuilt from
// the typed settings (scene/integrator_json.h): the text a scene file gives comes back.
#include <gtest/gtest.h>

#include "scene/enum_names.h"
#include "scene/integrator_json.h"
#include "scene/load.h"
#include "scene_test_util.h"

using namespace penumbra;
using namespace penumbra::test;

namespace {

// Every name of E reads back as its value, and the names are distinct.
template <class E>
void expectRoundTrip() {
    for (const EnumName<E>& entry : enumNames(E{})) {
        EXPECT_EQ(fromName<E>(entry.name), entry.value) << entry.name;
        EXPECT_STREQ(toName(entry.value), entry.name);
    }
    EXPECT_FALSE(fromName<E>("no_such_name").has_value());
}

// The header text of a scene whose integrator object is `integrator`.
std::string headerOf(const std::string& integrator) {
    auto file = writeFile(freshTempDir() / "scene.json", R"({"integrator": )" + integrator + "}");
    return integratorJson(loadScene(file).integrator).dump();
}

}  // namespace

TEST(EnumNames, EveryTableRoundTrips) {
    expectRoundTrip<SamplerType>();
    expectRoundTrip<IntegratorType>();
    expectRoundTrip<AoSampling>();
    expectRoundTrip<Strategy>();
    expectRoundTrip<Heuristic>();
    expectRoundTrip<SphereSampling>();
    expectRoundTrip<QuadSampling>();
    expectRoundTrip<TriangleSampling>();
    expectRoundTrip<LightSelection>();
}

TEST(EnumNames, ParserMessageListsTheTableInOrder) {
    auto file = writeFile(freshTempDir() / "bad.json", R"({"integrator": {"strategy": "path"}})");
    EXPECT_NE(loadError(file).find(R"("path" is not one of "light", "bsdf", "mis", "mixture")"), std::string::npos)
        << loadError(file);
}

// The header keeps the numbers as a scene file writes them.
TEST(IntegratorJson, NumbersAsWritten) {
    EXPECT_EQ(headerOf(R"({"type": "ao"})"), R"({"max_distance":1e+30,"sampling":"cosine","type":"ao"})");
    EXPECT_EQ(headerOf(R"({"type": "ao", "max_distance": 5})"),
              R"({"max_distance":5,"sampling":"cosine","type":"ao"})");
    EXPECT_EQ(headerOf(R"({"type": "ao", "max_distance": 0.1})"),
              R"({"max_distance":0.1,"sampling":"cosine","type":"ao"})");
    EXPECT_EQ(headerOf(R"({"type": "direct", "light_samples": 3, "quad_sampling": "area"})"),
              R"({"bsdf_samples":1,"heuristic":"power","light_samples":3,"light_selection":"power",)"
              R"("quad_sampling":"area","sphere_sampling":"solid_angle","strategy":"mis","type":"direct"})");
}
