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
        {"param array", "\"twist\": 0.5", "\"twist\": [1]", 5, "parameter 'twist' is array, expected a number in its range or an expression"},
        {"param empty expression", "\"twist\": 0.5", "\"twist\": \"\"", 5, "expression for 'twist' is empty"},
        {"param null", "\"twist\": 0.5", "\"twist\": null", 5, "parameter 'twist' is null, expected a number"},
        {"param 1e300", "\"twist\": 0.5", "\"twist\": 1e300", 5, "parameter 'twist' is 1e+300, expected a number that fits a float"},
        {"param 1e39", "\"twist\": 0.5", "\"twist\": 1e39", 5, "parameter 'twist' is 1e+39, expected a number that fits a float"},
        {"param big integer", "\"twist\": 0.5", "\"twist\": 9999999999999999999999999999999999999999", 5, "parameter 'twist' is 1e+40, expected"},
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
         "unknown key 'colour', expected scene, params, effects, normals, mapping, take, post, bpm, morph, envelopes, cues or loop_bars"},
        {"bpm string", "\"take\": \"presets/demo_take.mid\"", "\"take\": \"presets/demo_take.mid\",\n  \"bpm\": \"fast\"", 10,
         "bpm is not a tempo, expected a number of beats per minute in [20, 400]"},
        {"bpm huge", "\"take\": \"presets/demo_take.mid\"", "\"take\": \"presets/demo_take.mid\",\n  \"bpm\": 1e30", 10,
         "bpm is not a tempo"},
        {"morph easing", "\"take\": \"presets/demo_take.mid\"", "\"take\": \"presets/demo_take.mid\",\n  \"morph\": {\"seconds\": 2,\n \"easing\": \"wobbly\"}", 11,
         "morph easing is not known, expected linear, smooth, ease_in, ease_out or cut"},
        {"envelope sustain", "\"take\": \"presets/demo_take.mid\"", "\"take\": \"presets/demo_take.mid\",\n  \"envelopes\": {\"flash\":\n {\"note\": 36, \"sustain\": 2}}", 11,
         "envelope sustain is not a level, expected a number in [0, 1]"},
        {"envelope note", "\"take\": \"presets/demo_take.mid\"", "\"take\": \"presets/demo_take.mid\",\n  \"envelopes\": {\"flash\": {\"note\": 300}}", 10,
         "envelope note is not a whole number in [0, 127]"},
        {"cue without bar", "\"take\": \"presets/demo_take.mid\"", "\"take\": \"presets/demo_take.mid\",\n  \"cues\": [\n {\"preset\": \"walker\"}]", 11,
         "cue 0 has no bar, expected \"bar\": N"},
        {"cue set string", "\"take\": \"presets/demo_take.mid\"", "\"take\": \"presets/demo_take.mid\",\n  \"cues\": [{\"bar\": 4,\n \"set\": {\"twist\": \"x\"}}]", 11,
         "cue value for 'twist' is not a number"},
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

TEST_CASE("preset: a scripted preset's expressions, envelopes, cues, tempo and morph are read with their lines", "[scene]") {
    const std::string text =
        "{\n"                                                           // 1
        "  \"scene\": \"midi\",\n"                                      // 2
        "  \"bpm\": 128,\n"                                              // 3
        "  \"morph\": {\"seconds\": 1.5, \"easing\": \"ease_out\"},\n"    // 4
        "  \"params\": {\n"                                              // 5
        "    \"scale\": 1.0,\n"                                          // 6
        "    \"twist\": \"0.4 + 0.3 * lfo_sine(beat / 4)\"\n"            // 7
        "  },\n"                                                        // 8
        "  \"envelopes\": {\"flash\": {\"note\": 36, \"attack\": 0.01, \"release\": 0.5}},\n"  // 9
        "  \"cues\": [{\"bar\": 8, \"preset\": \"walker\", \"over\": 2},\n"   // 10
        "           {\"bar\": 4, \"set\": {\"twist\": 1.0}}],\n"           // 11
        "  \"loop_bars\": 16\n"                                          // 12
        "}\n";
    const std::string path = WriteTemp("scripted.json", text);
    Preset p;
    std::string error;
    REQUIRE(LoadPreset(path, &p, &error));
    const AutomationDesc& a = p.automation;
    CHECK(a.file == path);
    CHECK(a.bpm == 128.0);
    CHECK(a.morph.seconds == 1.5);
    CHECK(a.morph.easing == Easing::EaseOut);
    REQUIRE(a.expressions.size() == 1);
    CHECK(a.expressions[0].param == "twist");
    CHECK(a.expressions[0].text == "0.4 + 0.3 * lfo_sine(beat / 4)");
    CHECK(a.expressions[0].line == 7);
    CHECK(p.params.count("twist") == 0);
    CHECK(p.params.at("scale") == 1.0f);
    REQUIRE(a.envelopes.size() == 1);
    CHECK(a.envelopes[0].note == 36);
    CHECK(a.envelopes[0].release == 0.5);
    REQUIRE(a.cues.size() == 2);
    CHECK(a.cues[0].preset == "walker");
    CHECK(a.cues[0].overBeats == 2.0);
    CHECK(a.cues[1].values.at("twist") == 1.0f);
    CHECK(a.cues[1].line == 11);
    CHECK(a.loopBars == 16.0);
}
