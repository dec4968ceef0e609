// --set PATH=VALUE: parsing, applying to a document (created paths, indices, appends,
// JSON values with a plain-string fallback) and the errors of malformed or impossible paths.
#include <gtest/gtest.h>

#include "scene/integrator_json.h"
#include "scene/load.h"
#include "scene_test_util.h"

using namespace penumbra;
using nlohmann::json;

namespace {

json applied(json doc, const std::string& text) {
    applyOverride(doc, parseOverride(text));
    return doc;
}

std::string overrideError(json doc, const std::string& text) {
    try {
        applyOverride(doc, parseOverride(text));
    } catch (const InputError& e) {
        return e.what();
    }
    ADD_FAILURE() << "expected InputError for --set " << text;
    return "";
}

}  // namespace

TEST(Overrides, ParseSplitsAtFirstEquals) {
    Override o = parseOverride("integrator.strategy=a=b");
    EXPECT_EQ(o.path, "integrator.strategy");
    EXPECT_EQ(o.value, "a=b");
    EXPECT_EQ(parseOverride("x=").value, "");
}

TEST(Overrides, MalformedPathsAreRejected) {
    for (const char* text : {"spp", "=3", "a..b=1", "a.=1", ".a=1", "a[x]=1", "a[1=1", "a[]=1", "a]b=1", "a[1]b=1", "[0]=1"}) {
        try {
            parseOverride(text);
            ADD_FAILURE() << "accepted " << text;
        } catch (const InputError& e) {
            std::string message = e.what();
            EXPECT_EQ(message.rfind("--set ", 0), 0u) << message;
            EXPECT_NE(message.find("--set PATH=VALUE"), std::string::npos) << message;
            EXPECT_EQ(message.find('\n'), std::string::npos);
        }
    }
}

TEST(Overrides, CreatesMissingObjects) {
    json doc = applied({{"integrator", {{"type", "direct"}}}}, "integrator.strategy=bsdf");
    EXPECT_EQ(doc, (json{{"integrator", {{"type", "direct"}, {"strategy", "bsdf"}}}}));
    EXPECT_EQ(applied(json::object(), "a.b.c=1"), (json{{"a", {{"b", {{"c", 1}}}}}}));
}

TEST(Overrides, ValuesParseAsJsonElseString) {
    json doc = json::object();
    EXPECT_EQ(applied(doc, "sampler.spp=16")["sampler"]["spp"], json(16));
    EXPECT_TRUE(applied(doc, "sampler.spp=16")["sampler"]["spp"].is_number_integer());
    EXPECT_EQ(applied(doc, "x=[10,10,10]")["x"], json({10, 10, 10}));
    EXPECT_EQ(applied(doc, "x=true")["x"], json(true));
    EXPECT_EQ(applied(doc, "x=\"16\"")["x"], json("16"));  // quoted: a JSON string
    EXPECT_EQ(applied(doc, "x=bsdf")["x"], json("bsdf"));  // not JSON: a plain string
    EXPECT_EQ(applied(doc, "x=[1,2")["x"], json("[1,2"));
    EXPECT_EQ(applied(doc, "x={\"a\":1}")["x"], (json{{"a", 1}}));
}

TEST(Overrides, ArrayIndicesReplaceAndAppend) {
    json doc = {{"lights", json::array({{{"type", "point"}, {"power", 1}}})}};
    EXPECT_EQ(applied(doc, "lights[0].power=[10,10,10]")["lights"][0]["power"], json({10, 10, 10}));
    json appended = applied(doc, "lights[1].type=environment");
    ASSERT_EQ(appended["lights"].size(), 2u);
    EXPECT_EQ(appended["lights"][1], (json{{"type", "environment"}}));
    EXPECT_EQ(applied(json::object(), "shapes[0].radius=2"), (json{{"shapes", {{{"radius", 2}}}}}));
    EXPECT_EQ(applied(json::object(), "m[0][0]=1"), (json{{"m", {{1}}}}));
}

TEST(Overrides, ImpossiblePathsAreErrors) {
    json doc = {{"lights", json::array({json::object()})}, {"film", {{"width", 5}}}};
    std::string past = overrideError(doc, "lights[2].power=1");
    EXPECT_EQ(past.rfind("--set lights[2].power=1: index 2 out of range", 0), 0u) << past;
    EXPECT_NE(overrideError(doc, "film[0]=1").find("film is not an array"), std::string::npos);
    EXPECT_NE(overrideError(doc, "film.width.x=1").find("film.width is not an object"), std::string::npos);
    EXPECT_NE(overrideError(doc, "lights.power=1").find("lights is not an object"), std::string::npos);
}

TEST(Overrides, AppliedBeforeValidation) {
    auto file = test::writeFile(test::freshTempDir() / "s.json", R"({"integrator": {"type": "direct"}, "film": {"width": 8}})");
    Scene s = loadScene(file, {parseOverride("integrator.strategy=bsdf"), parseOverride("sampler.spp=3"),
                               parseOverride("lights[0]={\"type\":\"point\",\"position\":[0,1,0],\"intensity\":2}")});
    EXPECT_EQ(s.integrator.strategy, Strategy::Bsdf);
    EXPECT_EQ(integratorJson(s.integrator)["strategy"], "bsdf");
    EXPECT_EQ(s.sampler.spp, 3u);
    ASSERT_EQ(s.lights.size(), 1u);
    EXPECT_FLOAT_EQ(s.lights[0].intensity.y, 2.0f);

    // An overridden value is validated like one in the file.
    std::string message = test::loadError(file, {parseOverride("film.width=0")});
    EXPECT_EQ(message, file.string() + ": film.width: must be an integer in [1, 16384], got 0");
    message = test::loadError(file, {parseOverride("sampler.spp=many")});
    EXPECT_EQ(message, file.string() + ": sampler.spp: expected an integer, got a string");
    message = test::loadError(file, {parseOverride("sampler.type=halton")});
    EXPECT_EQ(message, file.string() + ": sampler.type: \"halton\" is not one of \"sobol\", \"independent\"");
    EXPECT_EQ(loadScene(file, {parseOverride("sampler.type=independent")}).sampler.type, SamplerType::Independent);
    message = test::loadError(file, {parseOverride("camera.fov_y=1e999")});
    EXPECT_NE(message.find("camera.fov_y: number is not finite"), std::string::npos) << message;
}
