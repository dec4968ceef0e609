// The option names (scene/integrator_options.h) in the parser's messages and the header's
// integrator object rebuilt from the typed settings (scene/integrator_json.h): the text a
// scene file gives comes back. tests/test_integrator_options.cpp checks the tables themselves.
#include <gtest/gtest.h>

#include "scene/integrator_json.h"
#include "scene/integrator_options.h"
#include "scene/load.h"
#include "scene_test_util.h"

using namespace penumbra;
using namespace penumbra::test;

namespace {

// The header text of a scene whose integrator object is `integrator`.
std::string headerOf(const std::string& integrator) {
    auto file = writeFile(freshTempDir() / "scene.json", R"({"integrator": )" + integrator + "}");
    return integratorJson(loadScene(file).integrator).dump();
}

}  // namespace

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

// Every option of the registry reads from the scene file: a bad value fails naming the file,
// the option's JSON path and (for a choice) every value in table order or (for a count) its
// range; each value, and each end of the range, reads back; the header lists it as written.
TEST(IntegratorJson, EveryRegistryOptionParsesFailsAndIsRecorded) {
    const auto dir = freshTempDir();
    for (const IntegratorOption& option : integratorOptions()) {
        const std::string type = toName(option.integrator);
        const std::string path = std::string("integrator.") + option.json;
        // ris_candidates is read, and recorded, only under strategy "ris".
        const std::string extra = option.appliesTo ? R"(, "strategy": "ris")" : "";
        auto scene = [&](const std::string& value) {
            return writeFile(
                dir / (std::string(option.json) + ".json"),
                R"({"integrator": {"type": ")" + type + R"(", ")" + option.json + R"(": )" + value + extra + "}}");
        };
        std::string bad = option.kind == OptionKind::Choice ? R"("no_such_value")" : "-1";
        const std::string message = loadError(scene(bad));
        EXPECT_NE(message.find(std::string(option.json) + ".json: " + path + ": "), std::string::npos) << message;
        if (option.kind == OptionKind::Choice) {
            std::string list;
            for (const OptionValue& v : option.values)
                list += (list.empty() ? "\"" : ", \"") + std::string(v.name) + "\"";
            EXPECT_NE(message.find("is not one of " + list), std::string::npos) << message;
            for (const OptionValue& v : option.values) {
                const IntegratorSettings s = loadScene(scene(std::string("\"") + v.name + "\"")).integrator;
                EXPECT_EQ(optionValue(option, s), double(v.value)) << path << " " << v.name;
                EXPECT_EQ(integratorJson(s)[option.json], v.name) << path;
            }
        } else if (option.kind == OptionKind::Count) {
            EXPECT_NE(message.find("[" + std::to_string(option.min) + ", " + std::to_string(option.max) + "]"),
                      std::string::npos)
                << message;
            // A count's ends: "light_samples": 0 with the default bsdf sample is valid.
            for (uint32_t n : {option.min, option.max}) {
                const IntegratorSettings s = loadScene(scene(std::to_string(n))).integrator;
                EXPECT_EQ(optionValue(option, s), double(n)) << path;
                EXPECT_EQ(integratorJson(s)[option.json], n) << path;
            }
        } else {
            EXPECT_NE(message.find("must be > 0"), std::string::npos) << message;
            const IntegratorSettings s = loadScene(scene("2.5")).integrator;
            EXPECT_EQ(optionValue(option, s), 2.5) << path;
            EXPECT_EQ(integratorJson(s)[option.json], 2.5) << path;
        }
    }
}
