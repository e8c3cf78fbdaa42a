// Presets (LoadPreset): every field type- and range-checked, unknown keys reported with their
// line, nothing throws; every shipped preset still loads.
#include <random>
#include <string>

#include <catch2/catch.hpp>

#include "scene/scene.h"
#include "test_util.h"

using namespace sdfvj;
using scene_test::CheckError;
using scene_test::With;
using scene_test::WriteTemp;

namespace {

const std::string kPreset =
    "{\n"                                             // 1
    "  \"scene\": \"midi\",\n"                        // 2
    "  \"params\": {\n"                               // 3
    "    \"scale\": 1.0,\n"                           // 4
    "    \"twist\": 0.5},\n"                          // 5
    "  \"effects\": \"soft_shadows,ao\",\n"           // 6
    "  \"normals\": \"tetrahedron\",\n"               // 7
    "  \"mapping\": \"mappings/akai_lpd8.toml\",\n"   // 8
    "  \"take\": \"presets/demo_take.mid\"\n"         // 9
    "}\n";                                            // 10

void ExpectRejected(const std::string& name, const std::string& text, int line, const std::string& names) {
    const std::string path = WriteTemp(name + ".json", text);
    Preset p;
    std::string error;
    bool ok = true;
    REQUIRE_NOTHROW(ok = LoadPreset(path, &p, &error));
    CHECK_FALSE(ok);
    CheckError(error, path, line, names);
}

struct Case {
    const char* what;
    const char* from;
    std::string to;
    int line;
    const char* names;
};

}  // namespace

TEST_CASE("preset: the test preset loads with every field read", "[scene]") {
    const std::string path = WriteTemp("good.json", kPreset);
    Preset p;
    std::string error;
    REQUIRE(LoadPreset(path, &p, &error));
    CHECK(p.scene == "midi");
    CHECK(p.params.at("twist") == 0.5f);
    CHECK(p.effects == "soft_shadows,ao");
    CHECK(p.normals == "tetrahedron");
    CHECK(p.mapping == "mappings/akai_lpd8.toml");
    CHECK(p.take == "presets/demo_take.mid");
}

TEST_CASE("preset: every wrong-typed or out-of-range field is an error on its line", "[scene]") {
    const std::vector<Case> cases = {
        {"scene number", "\"scene\": \"midi\"", "\"scene\": 5", 2, "scene is number, expected a string"},
        {"scene empty", "\"scene\": \"midi\"", "\"scene\": \"\"", 2, "scene is empty, expected a scene name"},
        {"scene missing", "\"scene\": \"midi\",", "", 1, "preset names no scene, expected"},
        {"params array", "\"params\": {\n    \"scale\": 1.0,\n    \"twist\": 0.5}", "\"params\": [1.0,\n 0.5]", 3, "params is array, expected an object"},
        {"param string", "\"twist\": 0.5", "\"twist\": \"x\"", 5, "parameter 'twist' is string, expected a number"},
        {"param null", "\"twist\": 0.5", "\"twist\": null", 5, "parameter 'twist' is null, expected a number"},
        {"param 1e300", "\"twist\": 0.5", "\"twist\": 1e300", 5, "parameter 'twist' is 1e+300, expected a number in [-1e+09, 1e+09]"},
        {"param 1e39", "\"twist\": 0.5", "\"twist\": 1e39", 5, "parameter 'twist' is 1e+39, expected a number in"},
        {"param big integer", "\"twist\": 0.5", "\"twist\": 99999999999999999999999", 5, "parameter 'twist' is 1e+23, expected"},
        {"param 1e400", "\"twist\": 0.5", "\"twist\": 1e400", 5, "number overflow parsing '1e400'), expected numbers that fit a float"},
        {"param NaN", "\"twist\": 0.5", "\"twist\": NaN", 5, "bad JSON"},
        {"param -Infinity", "\"twist\": 0.5", "\"twist\": -Infinity", 5, "bad JSON"},
        {"effects number", "\"effects\": \"soft_shadows,ao\"", "\"effects\": 5", 6, "effects is number, expected a string"},
        {"effects unknown", "\"effects\": \"soft_shadows,ao\"", "\"effects\": \"sparkles\"", 6, "unknown effect 'sparkles', expected"},
        {"effects huge reflections", "\"effects\": \"soft_shadows,ao\"", "\"effects\": \"reflections=99999999999999999999\"", 6,
         "is not 0..8, expected reflections=N"},
        {"normals number", "\"normals\": \"tetrahedron\"", "\"normals\": 1", 7, "normals is number, expected a string"},
        {"normals unknown", "\"normals\": \"tetrahedron\"", "\"normals\": \"sideways\"", 7, "unknown normal method 'sideways', expected"},
        {"mapping null", "\"mapping\": \"mappings/akai_lpd8.toml\"", "\"mapping\": null", 8, "mapping is null, expected a string"},
        {"take object", "\"take\": \"presets/demo_take.mid\"", "\"take\": {}", 9, "take is object, expected a string"},
        {"unknown key", "\"take\": \"presets/demo_take.mid\"", "\"take\": \"presets/demo_take.mid\",\n  \"colour\": 1", 10,
         "unknown key 'colour', expected scene, params, effects, normals, mapping or take"},
        {"not an object", "{\n  \"scene\"", "[\n  \"scene\"", 2, "bad JSON"},
        {"deep nesting", "\"mapping\": \"mappings/akai_lpd8.toml\"", "\"mapping\": " + std::string(100000, '['), 8,
         "preset nests deeper than 64 levels, expected at most 64"},
    };
    int n = 0;
    for (const Case& c : cases) {
        SECTION(c.what) { ExpectRejected("p" + std::to_string(n), With(kPreset, c.from, c.to), c.line, c.names); }
        ++n;
    }
}

TEST_CASE("preset: a top-level array or number is not a preset", "[scene]") {
    ExpectRejected("array", "\n[1, 2]\n", 2, "preset is not a JSON object, expected");
    ExpectRejected("number", "5", 1, "preset is not a JSON object, expected");
}

TEST_CASE("preset: empty, truncated and binary files are errors", "[scene]") {
    SECTION("empty") { ExpectRejected("empty", "", 1, "bad JSON"); }
    SECTION("truncated after a key") { ExpectRejected("trunc", kPreset.substr(0, kPreset.find(" 0.5")), 5, "bad JSON"); }
    SECTION("every truncation") {
        for (size_t n = 0; n + 2 < kPreset.size(); n += 3) {
            const std::string path = WriteTemp("trunc.json", kPreset.substr(0, n));
            Preset p;
            std::string error;
            bool ok = true;
            REQUIRE_NOTHROW(ok = LoadPreset(path, &p, &error));
            CHECK_FALSE(ok);
            CHECK(error.rfind(path + ":", 0) == 0);
        }
    }
    SECTION("binary garbage") {
        std::mt19937 rng(99);
        for (int round = 0; round < 200; ++round) {
            std::string junk = "{";
            for (int i = 0, n = 1 + int(rng() % 200); i < n; ++i) junk += char(rng() & 0xFF);
            const std::string path = WriteTemp("junk.json", junk);
            Preset p;
            std::string error;
            bool ok = true;
            REQUIRE_NOTHROW(ok = LoadPreset(path, &p, &error));
            CHECK_FALSE(ok);
            CHECK(error.rfind(path + ":", 0) == 0);
        }
    }
}

TEST_CASE("preset: every shipped preset loads", "[scene]") {
    const auto names = ListPresets();
    REQUIRE(names.size() >= 4);
    for (const std::string& name : names) {
        Preset p;
        std::string error;
        const std::string path = DataRoot() + "/presets/" + name;
        INFO(path << ": " << error);
        CHECK(LoadPreset(path, &p, &error));
        CHECK_FALSE(p.scene.empty());
    }
}
