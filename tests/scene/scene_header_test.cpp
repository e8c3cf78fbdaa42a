// Scene headers (LoadScene): a wrong-typed, out-of-range or malformed field is an error value
// "path:LINE: ..., expected ..." pointing at the field's own line; nothing throws (issue 10:
// `"LABEL": 5` used to escape as nlohmann type_error.302 and end `sdfvj live`).
#include <filesystem>
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

// Every field on a line of its own; the line numbers below are the file's lines (1-based).
// Input "a" has its LABEL on line 6, input "b" on line 12: an error about b must say 12.
const std::string kHeader =
    "// a test scene\n"                                                                             // 1
    "/*{\n"                                                                                         // 2
    "  \"NAME\": \"t\",\n"                                                                          // 3
    "  \"DESCRIPTION\": \"d\",\n"                                                                   // 4
    "  \"INPUTS\": [\n"                                                                             // 5
    "    {\"NAME\": \"a\", \"TYPE\": \"float\", \"DEFAULT\": 0.5, \"MIN\": 0, \"MAX\": 1, \"LABEL\": \"A\"},\n"  // 6
    "    {\"NAME\": \"b\",\n"                                                                       // 7
    "     \"TYPE\": \"float\",\n"                                                                   // 8
    "     \"DEFAULT\": 0.25,\n"                                                                     // 9
    "     \"MIN\": -2,\n"                                                                           // 10
    "     \"MAX\": 2,\n"                                                                            // 11
    "     \"LABEL\": \"B\"}\n"                                                                      // 12
    "  ],\n"                                                                                        // 13
    "  \"EFFECTS\": {\"SHADOWS\": \"soft\", \"AO\": true, \"REFLECTIONS\": 1},\n"                   // 14
    "  \"CAMERA\": {\n"                                                                             // 15
    "    \"POSITION\": [0, 1, -5],\n"                                                               // 16
    "    \"TARGET\": [0, 0, 0],\n"                                                                  // 17
    "    \"FOV\": 45},\n"                                                                           // 18
    "  \"LIGHT\": {\n"                                                                              // 19
    "    \"DIRECTION\": [0, 2, 0],\n"                                                               // 20
    "    \"COLOR\": [1, 0.5, 1]},\n"                                                                // 21
    "  \"MATERIAL\": {\n"                                                                           // 22
    "    \"ROUGHNESS\": 0.25,\n"                                                                    // 23
    "    \"METALNESS\": 0.75}\n"                                                                    // 24
    "}*/\n"                                                                                         // 25
    "vec4 render(vec2 uv) { return vec4(uv, 0.0, 1.0); }\n";

struct Case {
    const char* what;
    const char* from;
    const char* to;
    int line;
    const char* names;  // a piece of the message that names the field and what was expected
};

void ExpectRejected(const std::string& name, const std::string& text, int line, const std::string& names) {
    const std::string path = WriteTemp(name + ".glsl", text);
    SceneInfo scene;
    std::string error;
    bool ok = true;
    REQUIRE_NOTHROW(ok = LoadScene(path, &scene, &error));
    CHECK_FALSE(ok);
    CheckError(error, path, line, names);
}

void ExpectCases(const std::vector<Case>& cases) {
    int n = 0;
    for (const Case& c : cases) {
        SECTION(c.what) { ExpectRejected("case" + std::to_string(n), With(kHeader, c.from, c.to), c.line, c.names); }
        ++n;
    }
}

}  // namespace

TEST_CASE("scene header: the test header itself loads with every field read", "[scene]") {
    const std::string path = WriteTemp("good.glsl", With(kHeader, "\"NAME\": \"t\",", "\"NAME\": \"t\", \"ISFVSN\": \"2\","));
    SceneInfo s;
    std::string error;
    REQUIRE(LoadScene(path, &s, &error));
    CHECK(s.name == "t");
    CHECK(s.description == "d");
    REQUIRE(s.params.size() == 2);
    CHECK(s.params[1].label == "B");
    CHECK(s.params[1].minValue == -2.0f);
    CHECK(s.effects.reflections == 1);
    CHECK(s.effects.normals == 0);   // central unless the header says "NORMALS"
    CHECK(s.camPos == Vec3f{0, 1, -5});
    CHECK(s.fov == 45.0f);
    CHECK(s.lightDir == Vec3f{0, 1, 0});
    CHECK(s.lightColor == Vec3f{1, 0.5f, 1});
    CHECK(s.roughness == 0.25f);
    CHECK(s.metalness == 0.75f);
}

TEST_CASE("scene header: NORMALS picks the scene's normal estimator", "[scene]") {
    const std::string path = WriteTemp("normals.glsl", With(kHeader, "\"REFLECTIONS\": 1", "\"REFLECTIONS\": 1, \"NORMALS\": \"tetrahedron\""));
    SceneInfo s;
    std::string error;
    REQUIRE(LoadScene(path, &s, &error));
    CHECK(s.effects.normals == 2);
}

TEST_CASE("scene header: LABEL 5 is an error on its line, not type_error.302", "[scene]") {
    ExpectRejected("label5", With(kHeader, "\"LABEL\": \"B\"", "\"LABEL\": 5"), 12, "input 'b' LABEL is number, expected a string");
}

TEST_CASE("scene header: every wrong-typed field is an error on its line", "[scene]") {
    ExpectCases({
        {"NAME number", "\"NAME\": \"t\"", "\"NAME\": 5", 3, "NAME is number, expected a string"},
        {"NAME empty", "\"NAME\": \"t\"", "\"NAME\": \"\"", 3, "NAME is empty, expected the scene's name"},
        {"DESCRIPTION array", "\"DESCRIPTION\": \"d\"", "\"DESCRIPTION\": []", 4, "DESCRIPTION is array, expected a string"},
        {"INPUTS object", "\"INPUTS\": [", "\"INPUTS\": {\"x\": 1}, \"OTHER\": [", 5, "INPUTS is object, expected a list"},
        {"input not an object", "{\"NAME\": \"a\", \"TYPE\": \"float\", \"DEFAULT\": 0.5, \"MIN\": 0, \"MAX\": 1, \"LABEL\": \"A\"}",
         "7", 6, "an input is number, expected {"},
        {"input NAME number", "\"NAME\": \"b\"", "\"NAME\": 5", 7, "input NAME is number, expected a string"},
        {"input NAME not an identifier", "\"NAME\": \"b\"", "\"NAME\": \"b c\"", 7, "is not an identifier, expected"},
        {"input without NAME", "\"NAME\": \"b\"", "\"NOM\": \"b\"", 7, "an input has no NAME, expected"},
        {"TYPE number", "\"TYPE\": \"float\",\n", "\"TYPE\": 1,\n", 8, "input 'b' TYPE is number, expected a string"},
        {"TYPE unknown", "     \"TYPE\": \"float\"", "     \"TYPE\": \"vec9\"", 8, "input 'b' has TYPE 'vec9', expected float, int or bool"},
        {"DEFAULT string", "\"DEFAULT\": 0.25", "\"DEFAULT\": \"x\"", 9, "non-numeric DEFAULT (string), expected a number"},
        {"MIN null", "\"MIN\": -2", "\"MIN\": null", 10, "non-numeric MIN (null), expected a number"},
        {"MAX object", "\"MAX\": 2", "\"MAX\": {}", 11, "non-numeric MAX (object), expected a number"},
        {"MIN > MAX", "\"MIN\": -2", "\"MIN\": 3", 10, "MIN > MAX, expected MIN <= MAX"},
        {"DEFAULT out of range", "\"DEFAULT\": 0.25", "\"DEFAULT\": 7", 9, "DEFAULT outside [MIN, MAX], expected"},
        {"duplicate input", "\"NAME\": \"b\"", "\"NAME\": \"a\"", 7, "input 'a' is declared twice, expected unique names"},
        {"EFFECTS array", "\"EFFECTS\": {\"SHADOWS\": \"soft\", \"AO\": true, \"REFLECTIONS\": 1}", "\"EFFECTS\": []", 14,
         "EFFECTS is array, expected an object"},
        {"AO string", "\"AO\": true", "\"AO\": \"yes\"", 14, "AO is string, expected true or false"},
        {"SHADOWS number", "\"SHADOWS\": \"soft\"", "\"SHADOWS\": 3", 14, "SHADOWS is number, expected none, hard, soft or improved"},
        {"SHADOWS unknown", "\"SHADOWS\": \"soft\"", "\"SHADOWS\": \"fuzzy\"", 14, "SHADOWS is 'fuzzy', expected none, hard"},
        {"REFLECTIONS fraction", "\"REFLECTIONS\": 1", "\"REFLECTIONS\": 1.5", 14, "REFLECTIONS must be a bounce count 0..8, expected"},
        {"REFLECTIONS huge", "\"REFLECTIONS\": 1", "\"REFLECTIONS\": 18446744073709551615", 14, "REFLECTIONS must be a bounce count"},
        {"REFLECTIONS negative", "\"REFLECTIONS\": 1", "\"REFLECTIONS\": -1", 14, "REFLECTIONS must be a bounce count"},
        {"NORMALS unknown", "\"REFLECTIONS\": 1", "\"REFLECTIONS\": 1, \"NORMALS\": \"sideways\"", 14,
         "NORMALS is 'sideways', expected central, forward or tetrahedron"},
        {"NORMALS number", "\"REFLECTIONS\": 1", "\"REFLECTIONS\": 1, \"NORMALS\": 2", 14,
         "NORMALS is number, expected central, forward or tetrahedron"},
        {"CAMERA number", "\"CAMERA\": {", "\"CAMERA\": 5, \"X\": {", 15, "CAMERA is number, expected an object"},
        {"POSITION string", "\"POSITION\": [0, 1, -5]", "\"POSITION\": \"up\"", 16, "CAMERA POSITION is string, expected [x, y, z]"},
        {"POSITION two", "\"POSITION\": [0, 1, -5]", "\"POSITION\": [0, 1]", 16, "CAMERA POSITION is an array of 2, expected [x, y, z]"},
        {"TARGET string element", "\"TARGET\": [0, 0, 0]", "\"TARGET\": [0, \"a\", 0]", 17, "CAMERA TARGET[1] is string, expected a number"},
        {"POSITION equals TARGET", "\"POSITION\": [0, 1, -5]", "\"POSITION\": [0, 0, 0]", 15, "POSITION equals TARGET, expected"},
        {"unknown CAMERA key", "\"POSITION\": [0, 1, -5]", "\"POSITON\": [0, 1, -5]", 16, "unknown key 'POSITON' in CAMERA, expected POSITION"},
        {"FOV string", "\"FOV\": 45", "\"FOV\": \"wide\"", 18, "CAMERA FOV is string, expected a number in [0, 180]"},
        {"FOV zero", "\"FOV\": 45", "\"FOV\": 0", 18, "CAMERA FOV is 0, expected degrees in (0, 180)"},
        {"FOV 180", "\"FOV\": 45", "\"FOV\": 180", 18, "expected degrees in (0, 180)"},
        {"FOV negative", "\"FOV\": 45", "\"FOV\": -5", 18, "CAMERA FOV is -5, expected a number in [0, 180]"},
        {"LIGHT bool", "\"LIGHT\": {", "\"LIGHT\": true, \"X\": {", 19, "LIGHT is boolean, expected an object"},
        {"DIRECTION zero", "\"DIRECTION\": [0, 2, 0]", "\"DIRECTION\": [0, 0, 0]", 20, "LIGHT DIRECTION is zero, expected a direction"},
        {"DIRECTION null", "\"DIRECTION\": [0, 2, 0]", "\"DIRECTION\": null", 20, "LIGHT DIRECTION is null, expected [x, y, z]"},
        {"COLOR negative", "\"COLOR\": [1, 0.5, 1]", "\"COLOR\": [1, -0.5, 1]", 21, "LIGHT COLOR[1] is -0.5, expected a number in [0, 1000]"},
        {"MATERIAL array", "\"MATERIAL\": {", "\"MATERIAL\": [], \"X\": {", 22, "MATERIAL is array, expected an object"},
        {"ROUGHNESS 2", "\"ROUGHNESS\": 0.25", "\"ROUGHNESS\": 2", 23, "MATERIAL ROUGHNESS is 2, expected a number in [0, 1]"},
        {"METALNESS string", "\"METALNESS\": 0.75", "\"METALNESS\": \"x\"", 24, "MATERIAL METALNESS is string, expected a number in [0, 1]"},
        {"METALNESS negative", "\"METALNESS\": 0.75", "\"METALNESS\": -0.1", 24, "MATERIAL METALNESS is -0.1, expected a number in [0, 1]"},
        {"unknown MATERIAL key", "\"METALNESS\": 0.75", "\"METALNESS\": 0.75, \"SHINE\": 1", 24, "unknown key 'SHINE' in MATERIAL, expected"},
        {"known key in wrong case", "\"INPUTS\": [", "\"Inputs\": [", 5, "unknown key 'Inputs', expected INPUTS (upper case)"},
    });
}

TEST_CASE("scene header: huge numbers are errors, not inf", "[scene]") {
    ExpectCases({
        {"DEFAULT 1e300", "\"DEFAULT\": 0.25", "\"DEFAULT\": 1e300", 9, "input 'b' DEFAULT is 1e+300, expected a number in [-3.40282e+38, 3.40282e+38]"},
        {"MAX overflows float", "\"MAX\": 2", "\"MAX\": 1e39", 11, "input 'b' MAX is 1e+39, expected a number in"},
        {"MIN -1e300", "\"MIN\": -2", "\"MIN\": -1e300", 10, "input 'b' MIN is -1e+300, expected a number in"},
        {"MAX big integer", "\"MAX\": 2", "\"MAX\": 9999999999999999999999999999999999999999", 11, "input 'b' MAX is 1e+40, expected a number in"},
        {"range overflows float", "\"MIN\": -2,\n     \"MAX\": 2", "\"MIN\": -3e38,\n     \"MAX\": 3e38", 10, "range MAX - MIN that overflows a float, expected a narrower range"},
        {"DEFAULT overflows double", "\"DEFAULT\": 0.25", "\"DEFAULT\": 1e400", 9, "number overflow parsing '1e400'), expected numbers that fit a float"},
        {"POSITION 1e300", "\"POSITION\": [0, 1, -5]", "\"POSITION\": [1e300, 1, -5]", 16, "CAMERA POSITION[0] is 1e+300, expected a number in"},
        {"DIRECTION 3e38", "\"DIRECTION\": [0, 2, 0]", "\"DIRECTION\": [0, 3e38, 0]", 20, "LIGHT DIRECTION[1] is 3e+38, expected a number in"},
        {"FOV 1e300", "\"FOV\": 45", "\"FOV\": 1e300", 18, "CAMERA FOV is 1e+300, expected a number in [0, 180]"},
        {"ROUGHNESS -1e300", "\"ROUGHNESS\": 0.25", "\"ROUGHNESS\": -1e300", 23, "MATERIAL ROUGHNESS is -1e+300, expected"},
    });
}

TEST_CASE("scene header: NaN and Infinity are bad JSON on their line", "[scene]") {
    ExpectCases({
        {"DEFAULT NaN", "\"DEFAULT\": 0.25", "\"DEFAULT\": NaN", 9, "bad JSON in scene header"},
        {"MAX Infinity", "\"MAX\": 2", "\"MAX\": Infinity", 11, "bad JSON in scene header"},
        {"MIN -inf", "\"MIN\": -2", "\"MIN\": -inf", 10, "bad JSON in scene header"},
        {"FOV \"inf\"", "\"FOV\": 45", "\"FOV\": \"inf\"", 18, "CAMERA FOV is string, expected a number"},
    });
}

TEST_CASE("scene header: deep nesting is refused before parsing", "[scene]") {
    const std::string deep(100000, '[');
    SECTION("100000 open brackets in an unknown key") {
        ExpectRejected("deep1", With(kHeader, "  \"MATERIAL\": {", "  \"X\": " + deep + "\n  \"MATERIAL\": {"), 22,
                       "nests deeper than 64 levels, expected at most 64");
    }
    SECTION("balanced 100000 levels") {
        ExpectRejected("deep2", With(kHeader, "  \"MATERIAL\": {", "  \"X\": " + deep + std::string(100000, ']') + ",\n  \"MATERIAL\": {"),
                       22, "nests deeper than 64 levels");
    }
    SECTION("deep objects inside an input") {
        std::string objs;
        for (int i = 0; i < 1000; ++i) objs += "{\"k\": ";
        ExpectRejected("deep3", With(kHeader, "\"LABEL\": \"B\"", "\"LABEL\": \"B\",\n \"IDENTITY\": " + objs), 13,
                       "nests deeper than 64 levels");
    }
    SECTION("64 levels are fine") {
        std::string ok = std::string(62, '[') + std::string(62, ']');
        const std::string path = WriteTemp("deep_ok.glsl", With(kHeader, "\"NAME\": \"t\",", "\"NAME\": \"t\", \"X\": " + ok + ","));
        SceneInfo s;
        std::string error;
        CHECK(LoadScene(path, &s, &error));
    }
}

TEST_CASE("scene header: empty, unclosed, truncated and binary files are errors", "[scene]") {
    SECTION("empty file") { ExpectRejected("empty", "", 1, "no scene header, expected"); }
    SECTION("header never closed") {
        ExpectRejected("unclosed", With(kHeader, "}*/", "}"), 2, "scene header is never closed, expected }*/");
    }
    SECTION("missing file") {
        SceneInfo s;
        std::string error;
        CHECK_FALSE(LoadScene("/nonexistent/x.glsl", &s, &error));
        CheckError(error, "/nonexistent/x.glsl", 1, "cannot read the file");
    }
    SECTION("truncated inside the JSON, then closed") {
        // Cut inside input b, right after `"MIN": -`: the JSON ends on line 10.
        const std::string cut = kHeader.substr(0, kHeader.find("-2")) + "-}*/\n";
        ExpectRejected("truncated", cut, 10, "bad JSON in scene header");
    }
    SECTION("every truncation is an error value, never an exception") {
        for (size_t n = 0; n < kHeader.find("}*/") + 2; n += 7) {
            const std::string path = WriteTemp("trunc.glsl", kHeader.substr(0, n));
            SceneInfo s;
            std::string error;
            bool ok = true;
            REQUIRE_NOTHROW(ok = LoadScene(path, &s, &error));
            CHECK_FALSE(ok);
            CHECK(error.rfind(path + ":", 0) == 0);
        }
    }
    SECTION("invalid UTF-8 in a string") {
        ExpectRejected("utf8", With(kHeader, "\"LABEL\": \"B\"", "\"LABEL\": \"\xff\xfe\""), 12, "bad JSON in scene header");
    }
    SECTION("binary garbage in a header") {
        std::mt19937 rng(1234);
        for (int round = 0; round < 200; ++round) {
            std::string junk = "/*{";
            const int n = 1 + int(rng() % 300);
            for (int i = 0; i < n; ++i) junk += char(rng() & 0xFF);
            junk += "}*/";
            const std::string path = WriteTemp("junk.glsl", junk);
            SceneInfo s;
            std::string error;
            bool ok = true;
            REQUIRE_NOTHROW(ok = LoadScene(path, &s, &error));
            CHECK_FALSE(ok);
            CHECK(error.rfind(path + ":", 0) == 0);
        }
    }
}

TEST_CASE("scene header: ParseSceneText reads the same as LoadScene", "[scene]") {
    SceneInfo s;
    std::string error;
    CHECK_FALSE(ParseSceneText(With(kHeader, "\"LABEL\": \"B\"", "\"LABEL\": 5"), "mem.glsl", &s, &error));
    CheckError(error, "mem.glsl", 12, "LABEL is number");
    REQUIRE(ParseSceneText(kHeader, "mem.glsl", &s, &error));
    CHECK(s.name == "t");
}

TEST_CASE("scene header: the test suites' scenes load (stability_hard declares MAX 1e30 on purpose)", "[scene]") {
    int n = 0;
    for (const auto& e : std::filesystem::directory_iterator(std::filesystem::path(DataRoot()) / "tests" / "stability" / "scenes")) {
        if (e.path().extension() != ".glsl") continue;
        SceneInfo s;
        std::string error;
        INFO(e.path().string());
        CHECK(LoadScene(e.path().string(), &s, &error));
        CHECK(error.empty());
        ++n;
    }
    CHECK(n >= 2);
}

TEST_CASE("scene header: every shipped scene loads", "[scene]") {
    const auto names = ListScenes();
    REQUIRE(names.size() >= 4);
    for (const std::string& name : names) {
        SceneInfo s;
        std::string error;
        INFO(name << ": " << error);
        CHECK(FindScene(name, &s, &error));
        CHECK(error.empty());
        CHECK_FALSE(s.params.empty());
    }
}
