// ISF -> GLSL 4.5 core: the preamble with the ISF built-ins, the GLSL 1.x words translated, and
// #line directives so a driver error names the .fs (or .vs) and its line.
#include <cctype>
#include <regex>
#include <set>

#include "isf/isf.h"

namespace sdfvj {

namespace {

// Same folding as the shader module: line = fileIndex * 100000 + line, so MapCompileLog maps
// Mesa's messages that report source string 0 whatever #line said.
std::string LineDirective(int line, int fileIndex) {
    return "#line " + std::to_string(fileIndex * 100000 + line) + " " + std::to_string(fileIndex) + "\n";
}

// Replaces whole identifiers (never inside a longer name): texture2D -> texture, not
// texture2DLod -> textureLod. `#version` lines become empty lines (the count of lines stays).
std::string Rewrite(const std::string& text, const std::map<std::string, std::string>& words) {
    std::string out;
    out.reserve(text.size() + 64);
    size_t i = 0;
    bool lineStart = true;
    while (i < text.size()) {
        const char c = text[i];
        if (lineStart) {
            size_t j = i;
            while (j < text.size() && (text[j] == ' ' || text[j] == '\t')) ++j;
            if (text.compare(j, 8, "#version") == 0) {
                while (i < text.size() && text[i] != '\n') ++i;
                continue;
            }
        }
        lineStart = c == '\n';
        if (std::isalpha((unsigned char)c) || c == '_') {
            size_t j = i;
            while (j < text.size() && (std::isalnum((unsigned char)text[j]) || text[j] == '_')) ++j;
            const std::string word = text.substr(i, j - i);
            auto it = words.find(word);
            out += it == words.end() ? word : it->second;
            i = j;
        } else {
            out += c;
            ++i;
        }
    }
    return out;
}

const char* kBuiltins =
    "uniform int PASSINDEX;\n"
    "uniform vec2 RENDERSIZE;\n"
    "uniform float TIME;\n"
    "uniform float TIMEDELTA;\n"
    "uniform vec4 DATE;\n"
    "uniform int FRAMEINDEX;\n"
    "uniform float u_beat;\n"   // sdfvj: the show's beat phase 0..1 and tempo, as scenes get them
    "uniform float u_bpm;\n"
    "#define vv_FragNormCoord isf_FragNormCoord\n"
    "#define IMG_PIXEL(img, coord) texture(img, (coord) / vec2(textureSize(img, 0)))\n"
    "#define IMG_NORM_PIXEL(img, coord) texture(img, coord)\n"
    "#define IMG_THIS_PIXEL(img) texture(img, isf_FragNormCoord)\n"
    "#define IMG_THIS_NORM_PIXEL(img) texture(img, isf_FragNormCoord)\n"
    "#define IMG_SIZE(img) vec2(textureSize(img, 0))\n"
    "vec4 isf_texture2DRect(sampler2D s, vec2 c) { return texture(s, c / vec2(textureSize(s, 0))); }\n";

// Uniform declarations for the inputs, pass targets and imported images.
std::string Declarations(const IsfFile& f) {
    std::string d;
    std::set<std::string> samplers;
    for (const IsfInput& in : f.inputs) {
        switch (in.type) {
            case IsfInputType::Float: d += "uniform float " + in.name + ";\n"; break;
            case IsfInputType::Bool: case IsfInputType::Event: d += "uniform bool " + in.name + ";\n"; break;
            case IsfInputType::Long: d += "uniform int " + in.name + ";\n"; break;
            case IsfInputType::Point2D: d += "uniform vec2 " + in.name + ";\n"; break;
            case IsfInputType::Color: d += "uniform vec4 " + in.name + ";\n"; break;
            default: samplers.insert(in.name); d += "uniform sampler2D " + in.name + ";\n"; break;
        }
    }
    for (const IsfPass& p : f.passes)
        if (!p.target.empty() && samplers.insert(p.target).second) d += "uniform sampler2D " + p.target + ";\n";
    for (const IsfImport& im : f.imports)
        if (samplers.insert(im.name).second) d += "uniform sampler2D " + im.name + ";\n";
    return d;
}

void Finish(ShaderSource* s) { s->hash = HashBytes(s->text); }

}  // namespace

bool TranslateIsf(const IsfFile& f, IsfSources* out, std::string* error) {
    IsfSources r;
    const std::map<std::string, std::string> fragWords = {
        {"gl_FragColor", "isf_FragColor"}, {"texture2D", "texture"}, {"texture2DRect", "isf_texture2DRect"},
        {"texture2DProj", "textureProj"}, {"texture2DLod", "textureLod"}, {"varying", "in"}};
    const std::string body = Rewrite(f.body, fragWords);
    static const std::regex kOwnOutput(R"((^|\n)[ \t]*(layout\s*\([^)]*\)\s*)?out\s+(\w+\s+)?vec4\s+\w+)");
    const bool ownOutput = std::regex_search(body, kOwnOutput);

    // Vertex stage: the full-screen triangle from gl_VertexID, or the file's own .vs around it.
    ShaderSource& vs = r.vertex;
    vs.files = {"<generated>", f.vertexPath.empty() ? f.path : f.vertexPath};
    vs.text = "#version 450 core\nout vec2 isf_FragNormCoord;\n";
    if (f.kind != IsfKind::Shadertoy) vs.text += std::string(kBuiltins) + Declarations(f);
    vs.text +=
        "void isf_vertShaderInit() {\n"
        "    vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));\n"
        "    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);\n"
        "    isf_FragNormCoord = p;\n"
        "}\n"
        "#define vv_vertShaderInit isf_vertShaderInit\n";
    if (f.vertexBody.empty()) {
        vs.text += "void main() { isf_vertShaderInit(); }\n";
    } else {
        const std::map<std::string, std::string> vertWords = {
            {"varying", "out"}, {"attribute", "in"}, {"texture2D", "texture"}, {"texture2DRect", "isf_texture2DRect"}};
        vs.text += LineDirective(1, 1) + Rewrite(f.vertexBody, vertWords);
    }
    Finish(&vs);

    ShaderSource& fs = r.fragment;
    fs.files = {"<generated>", f.path};
    fs.text = "#version 450 core\nin vec2 isf_FragNormCoord;\n";
    if (f.kind == IsfKind::Shadertoy) {
        fs.text +=
            "layout(location = 0) out vec4 isf_FragColor;\n"
            "uniform vec3 iResolution;\nuniform float iTime;\nuniform float iTimeDelta;\nuniform float iFrameRate;\n"
            "uniform int iFrame;\nuniform vec4 iMouse;\nuniform vec4 iDate;\nuniform vec3 iChannelResolution[4];\n"
            "uniform sampler2D iChannel0;\nuniform sampler2D iChannel1;\nuniform sampler2D iChannel2;\nuniform sampler2D iChannel3;\n"
            "uniform float u_beat;\nuniform float u_bpm;\n" +
            LineDirective(f.bodyLine, 1) + body + "\n" + LineDirective(1, 0) +
            "void main() {\n"
            "    vec4 c = vec4(0.0, 0.0, 0.0, 1.0);\n"
            "    mainImage(c, gl_FragCoord.xy);\n"
            "    isf_FragColor = vec4(c.rgb, 1.0);   // Shadertoy shows no alpha\n"
            "}\n";
    } else {
        if (!ownOutput) fs.text += "layout(location = 0) out vec4 isf_FragColor;\n";
        fs.text += std::string(kBuiltins) + Declarations(f) + LineDirective(f.bodyLine, 1) + body;
        if (body.find("main") == std::string::npos) {
            *error = f.path + ":" + std::to_string(f.bodyLine) + ": no main() after the ISF header, expected void main() { gl_FragColor = ...; }";
            return false;
        }
    }
    Finish(&fs);
    *out = std::move(r);
    return true;
}

}  // namespace sdfvj
