// ISF headers parsed strictly into values: every input type, passes, imports; each error names
// the line it is on and what was expected. No GL here.
#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>

#include "isf/isf.h"
#include "isf_test_util.h"

using namespace sdfvj;

namespace {

IsfFile ParseOk(const std::string& text) {
    IsfFile f;
    std::string error;
    INFO(error);
    if (!ParseIsfText(text, "t.fs", &f, &error)) FAIL(error);
    return f;
}

std::string ParseError(const std::string& text) {
    IsfFile f;
    std::string error;
    CHECK_FALSE(ParseIsfText(text, "t.fs", &f, &error));
    return error;
}

}  // namespace

TEST_CASE("isf parse: every INPUTS type with its values", "[isf][parse]") {
    IsfFile f;
    std::string error;
    REQUIRE(LoadIsfFile(isftest::TestFile("all_inputs.fs"), &f, &error));
    REQUIRE(f.inputs.size() == 9);
    CHECK(f.kind == IsfKind::Filter);
    CHECK(f.isfVersion == "2.0");
    const IsfInput& fl = f.inputs[1];
    CHECK((fl.name == "amount" && fl.type == IsfInputType::Float && fl.defaultValue[0] == 0.25f && fl.maxValue[0] == 2.0f));
    CHECK((f.inputs[2].type == IsfInputType::Bool && f.inputs[2].defaultValue[0] == 1.0f));
    const IsfInput& lg = f.inputs[3];
    CHECK(lg.type == IsfInputType::Long);
    CHECK(lg.values == std::vector<int>{0, 5, 10});
    CHECK(lg.labels == std::vector<std::string>{"none", "half", "all"});
    CHECK((lg.minValue[0] == 0 && lg.maxValue[0] == 10 && lg.defaultValue[0] == 5));
    CHECK((f.inputs[4].type == IsfInputType::Point2D && f.inputs[4].defaultValue[1] == 20.0f));
    CHECK((f.inputs[5].type == IsfInputType::Color && f.inputs[5].defaultValue[2] == 0.75f));
    CHECK(f.inputs[6].type == IsfInputType::Event);
    CHECK(f.inputs[7].type == IsfInputType::Audio);
    CHECK((f.inputs[8].type == IsfInputType::AudioFFT && f.inputs[8].maxSamples == 16));
    // audio is not wired: one line each, naming its line in the file
    REQUIRE(f.notices.size() == 2);
    CHECK(f.notices[0].find("all_inputs.fs:20: input 'wave' is audio") != std::string::npos);

    // As parameters: a color is four, a point two, images and audio none.
    const auto params = IsfParams(f);
    std::vector<std::string> names;
    for (const ParamDecl& d : params) names.push_back(d.name);
    CHECK(names == std::vector<std::string>{"amount", "flag", "choice", "where_x", "where_y", "tint_r", "tint_g", "tint_b",
                                            "tint_a", "bang"});
    CHECK(params[2].type == ParamType::Int);
    std::vector<std::pair<std::string, float>> values;
    REQUIRE(ApplyIsfParamOverrides(params, {"amount=9", "choice=4.6"}, &values, &error));
    CHECK(values == std::vector<std::pair<std::string, float>>{{"amount", 2.0f}, {"choice", 5.0f}});   // clamped, rounded
    CHECK_FALSE(ApplyIsfParamOverrides(params, {"nope=1"}, &values, &error));
    CHECK(error.find("no ISF input 'nope', expected one of: amount") != std::string::npos);
}

TEST_CASE("isf parse: PASSES with TARGET, PERSISTENT, FLOAT, WIDTH/HEIGHT", "[isf][parse]") {
    IsfFile f = ParseOk(R"(/*{ "ISFVSN": "2", "INPUTS": [{"NAME": "scale", "TYPE": "float", "DEFAULT": 2, "MAX": 8}],
  "PASSES": [ {"TARGET": "a", "PERSISTENT": true, "FLOAT": 1, "WIDTH": "$WIDTH / $scale", "HEIGHT": 16},
              {"TARGET": "b", "PERSISTENT": false, "FLOAT": false}, {} ] }*/
void main() { gl_FragColor = vec4(1.0); }
)");
    REQUIRE(f.passes.size() == 3);
    CHECK((f.passes[0].target == "a" && f.passes[0].persistent && f.passes[0].floatTarget));
    CHECK((f.passes[0].widthExpr == "$WIDTH / $scale" && f.passes[0].heightExpr == "16"));
    CHECK((!f.passes[1].persistent && !f.passes[1].floatTarget && f.passes[2].target.empty()));
    CHECK(f.kind == IsfKind::Generator);
    CHECK(f.bodyLine == 3);
    // A header without PASSES is one pass to the output.
    CHECK(ParseOk("/*{}*/ void main(){}").passes.size() == 1);
}

TEST_CASE("isf parse: ISF 1.0 PERSISTENT_BUFFERS mark their passes persistent", "[isf][parse]") {
    IsfFile f = ParseOk(R"(/*{ "PERSISTENT_BUFFERS": ["acc"], "PASSES": [{"TARGET": "acc"}, {}] }*/ void main(){})");
    CHECK(f.passes[0].persistent);
    CHECK(f.isfVersion.empty());
}

TEST_CASE("isf parse: errors name the line and say what was expected", "[isf][parse]") {
    CHECK(ParseError("/*{\n \"INPUTS\": [\n  {\"NAME\": \"a\", \"TYPE\": \"float\"},\n  {\"NAME\": \"b\", \"TYPE\": \"vec3\"}\n ]\n}*/ void main(){}") ==
          "t.fs:4: input 'b' has TYPE 'vec3', expected one of event, bool, long, float, point2D, color, image, audio, audioFFT");
    CHECK(ParseError("/*{\n \"INPUTS\": [\n  {\"NAME\": \"x\", \"TYPE\": \"float\",\n   \"DEFAULT\": \"big\"}]}*/") ==
          "t.fs:4: input 'x' DEFAULT is string, expected a number");
    CHECK(ParseError("/*{\"INPUTS\": [{\"NAME\": \"x\", \"TYPE\": \"float\", \"MIN\": 0, \"MAX\": 1, \"DEFAULT\": 3}]}*/")
              .find("t.fs:1: input 'x' has DEFAULT outside [MIN, MAX]") == 0);
    CHECK(ParseError("/*{\n\"INPUTS\": [{\"NAME\": \"m\", \"TYPE\": \"long\", \"VALUES\": [0, 1],\n \"LABELS\": [\"a\"]}]}*/") ==
          "t.fs:3: input 'm' has 1 LABELS and 2 VALUES, expected one label per value");
    CHECK(ParseError("/*{\n\"INPUTS\": [{\"NAME\": \"my var\", \"TYPE\": \"float\"}]}*/").find("t.fs:2: input name 'my var' is not a GLSL identifier") == 0);
    CHECK(ParseError("/*{\"INPUTS\": [{\"NAME\": \"TIME\", \"TYPE\": \"float\"}]}*/").find("is an ISF built-in") != std::string::npos);
    CHECK(ParseError("/*{\n\"INPUTS\": [{\"NAME\": \"p\", \"TYPE\": \"point2D\", \"DEFAULT\": [1]}]}*/") ==
          "t.fs:2: input 'p' DEFAULT is an array of 1, expected an array of 2 numbers");
    CHECK(ParseError("/*{\n\"PASSES\": [\n {\"TARGET\": \"a\",\n  \"WIDTH\": \"$WIDTH / $blur\"}]}*/") ==
          "t.fs:4: pass WIDTH '$WIDTH / $blur': unknown variable '$blur', expected $WIDTH, $HEIGHT or an input's name at character 10");
    CHECK(ParseError("/*{\n\"PASSES\": [{\"TARGET\": \"a\", \"PERSISTENT\": [1]}]}*/") ==
          "t.fs:2: pass PERSISTENT is array, expected true or false");
    CHECK(ParseError("/*{\n \"INPUTS\": [\n   {\"NAME\": \"a\",},\n ]\n}*/").find("t.fs:3: the ISF header is not valid JSON") == 0);
    CHECK(ParseError("\n\nvoid main() {}").find("t.fs:3: no ISF header, expected the file to open with a JSON comment") == 0);
    CHECK(ParseError("/*{ \"INPUTS\": [] ").find("the ISF header comment is not closed") != std::string::npos);
    CHECK(ParseError("/*{\n\"IMPORTED\": {\"tex\": {\"PATH\": \"missing.png\"}}}*/") ==
          "t.fs:2: IMPORTED 'tex' PATH 'missing.png' is not a file, expected an image beside the .fs");
    CHECK(ParseError("/*{\"INPUTS\": [{\"NAME\": \"a\", \"TYPE\": \"image\"}], \"PASSES\": [{\"TARGET\": \"a\"}]}*/")
              .find("pass TARGET 'a' is also an input's name") != std::string::npos);
    IsfFile f;
    std::string error;
    CHECK_FALSE(LoadIsfFile("/nonexistent/x.fs", &f, &error));
    CHECK(error == "/nonexistent/x.fs:1: cannot read the file, expected an ISF .fs file");
}

TEST_CASE("isf parse: unknown keys and extra image inputs are one notice each, not errors", "[isf][parse]") {
    IsfFile f = ParseOk("/*{\n\"FOO\": 1,\n\"INPUTS\": [{\"NAME\": \"inputImage\", \"TYPE\": \"image\"},\n"
                        "{\"NAME\": \"mask\", \"TYPE\": \"image\"}]}*/ void main(){}");
    REQUIRE(f.notices.size() == 2);
    CHECK(f.notices[0] == "t.fs:2: key 'FOO' is not ISF 2.0, ignored");
    CHECK(f.notices[1] == "t.fs:4: image input 'mask' also reads the previous stage's frame (sdfvj has one image source per stage)");
}

TEST_CASE("isf parse: a Shadertoy mainImage without a header is a generator", "[isf][parse]") {
    IsfFile f = ParseOk("void mainImage(out vec4 c, in vec2 p) { c = texture(iChannel1, p); }");
    CHECK(f.kind == IsfKind::Shadertoy);
    REQUIRE(f.notices.size() == 1);
    CHECK(f.notices[0].find("iChannel1 is not supported") != std::string::npos);
}

TEST_CASE("isf expressions: arithmetic, functions, variables and errors", "[isf][expr]") {
    const std::map<std::string, double> vars{{"WIDTH", 640}, {"HEIGHT", 360}, {"blur", 4}};
    auto eval = [&](const std::string& e) {
        double v = NAN;
        std::string error;
        INFO(e << ": " << error);
        REQUIRE(EvalIsfExpression(e, vars, &v, &error));
        return v;
    };
    CHECK(eval("$WIDTH/2") == 320);
    CHECK(eval("floor($HEIGHT / $blur) + 1") == 91);
    CHECK(eval("-2^2") == -4);   // -(2^2), as in mathematics
    CHECK(eval("2^-1") == 0.5);
    CHECK(eval("2^3^2") == 512);
    CHECK(eval("max($WIDTH, $HEIGHT) * 0.5") == 320);
    CHECK(eval("(1 + 2) * 3 % 4") == 1);
    CHECK(eval("round(pi * 100)") == 314);
    std::string error;
    double v = 0;
    CHECK_FALSE(EvalIsfExpression("$WIDTH / 0", vars, &v, &error));
    CHECK(error.find("not a finite number") != std::string::npos);
    CHECK_FALSE(EvalIsfExpression("$WIDTH +", vars, &v, &error));
    CHECK(error.find("ends early") != std::string::npos);
    CHECK_FALSE(EvalIsfExpression("foo(1)", vars, &v, &error));
    CHECK(error.find("unknown function 'foo'") != std::string::npos);
    CHECK_FALSE(EvalIsfExpression("1 2", vars, &v, &error));
    CHECK(error.find("expected the end of the expression") != std::string::npos);
    CHECK_FALSE(EvalIsfExpression(std::string(2000, '('), vars, &v, &error));
}

TEST_CASE("isf translate: GLSL 1.x words become 4.5 core and #line points into the .fs", "[isf][translate]") {
    IsfFile f = ParseOk("/*{\"INPUTS\": [{\"NAME\": \"inputImage\", \"TYPE\": \"image\"}]}*/\n#version 120\nvarying vec2 uv;\n"
                        "void main() { gl_FragColor = texture2D(inputImage, uv) + texture2DLodX; }\n");
    IsfSources s;
    std::string error;
    REQUIRE(TranslateIsf(f, &s, &error));
    CHECK(s.fragment.text.rfind("#version 450 core\n", 0) == 0);
    CHECK(s.fragment.text.find("#version 120") == std::string::npos);
    CHECK(s.fragment.text.find("in vec2 uv;") != std::string::npos);
    CHECK(s.fragment.text.find("isf_FragColor = texture(inputImage, uv) + texture2DLodX;") != std::string::npos);
    CHECK(s.fragment.text.find("#line 100001 1\n") != std::string::npos);   // body starts on line 1 of t.fs
    CHECK(s.fragment.text.find("uniform sampler2D inputImage;") != std::string::npos);
    CHECK(s.fragment.files == std::vector<std::string>{"<generated>", "t.fs"});
}
