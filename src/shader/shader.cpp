#include "shader/shader.h"

#include "shader/literals.h"

#include <charconv>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

namespace fs = std::filesystem;

namespace sdfvj {

const char* RenderPathName(RenderPath p) { return p == RenderPath::Compute ? "compute" : "fragment"; }

uint64_t HashBytes(const std::string& bytes) {
    uint64_t h = 1469598103934665603ull;
    for (unsigned char c : bytes) h = (h ^ c) * 1099511628211ull;
    return h;
}

std::string DisplayPath(const std::string& path) {
    std::error_code ec;
    fs::path rel = fs::relative(path, DataRoot(), ec);
    if (ec || rel.empty() || rel.string().rfind("..", 0) == 0) return path;
    return rel.string();
}

namespace {

// Mesa reports some errors with source-string number 0 whatever #line said, so the file index is
// also folded into the line number: line = index * kLinesPerFile + line-in-file.
constexpr int kLinesPerFile = 100000;

std::string LineDirective(int line, int fileIndex) {
    return "#line " + std::to_string(fileIndex * kLinesPerFile + line) + " " + std::to_string(fileIndex) + "\n";
}

struct Expander {
    ShaderSource* out;
    std::set<std::string> included;   // each file once (files also carry guards)
    std::vector<std::string> stack;   // for cycle messages
    std::string error;
    std::string liftPath;             // this file's float literals become u_lit[i] (LiftLiterals)

    int FileIndex(const std::string& path) {
        for (size_t i = 0; i < out->files.size(); ++i)
            if (out->files[i] == path) return (int)i;
        out->files.push_back(path);
        return (int)out->files.size() - 1;
    }

    bool Expand(const std::string& path, const std::string& from, int fromLine) {
        std::string canon = fs::weakly_canonical(path).string();
        if (included.count(canon)) return true;
        std::ifstream in(canon);
        if (!in) {
            error = from.empty() ? DisplayPath(path) + ":1: cannot read the file"
                                 : DisplayPath(from) + ":" + std::to_string(fromLine) + ": cannot open include '" +
                                       DisplayPath(path) + "', expected a file under shaders/";
            return false;
        }
        included.insert(canon);
        const int index = FileIndex(canon);
        out->text += LineDirective(1, index);
        std::stringstream body;
        body << in.rdbuf();
        if (!liftPath.empty() && canon == liftPath) {
            LiftedText lifted = LiftLiterals(body.str());
            out->literals = std::move(lifted.values);
            body.str(lifted.text);
        }
        std::string line;
        int lineNo = 0;
        static const std::regex kInclude(R"(^\s*#\s*include\s*"([^"]+)\"\s*$)");
        while (std::getline(body, line)) {
            ++lineNo;
            std::smatch m;
            if (line.find("#") != std::string::npos && std::regex_match(line, m, kInclude)) {
                const std::string name = m[1];
                fs::path fromRoot = fs::path(DataRoot()) / "shaders" / name;
                fs::path fromHere = fs::path(canon).parent_path() / name;
                fs::path target = fs::exists(fromRoot) ? fromRoot : fromHere;
                if (!Expand(target.string(), canon, lineNo)) return false;
                out->text += LineDirective(lineNo + 1, index);
                continue;
            }
            out->text += line;
            out->text += '\n';
        }
        return true;
    }
};

const char* kVertexShader = R"(#version 450 core
void main() {
    vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
)";

}  // namespace

bool ExpandIncludes(const std::string& path, ShaderSource* out, std::string* error, bool liftLiterals) {
    Expander e{out, {}, {}, {}, liftLiterals ? fs::weakly_canonical(path).string() : std::string()};
    if (out->files.empty()) out->files.push_back("<generated>");
    if (!e.Expand(path, "", 0)) {
        *error = e.error;
        return false;
    }
    return true;
}

std::vector<std::string> VariantDefines(const EffectSet& e, RenderPath path) {
    std::vector<std::string> d = {
        "SHADOWS " + std::to_string(e.shadows),
        "AO " + std::to_string(e.ao ? 1 : 0),
        "SPECULAR " + std::to_string(e.specular ? 1 : 0),
        "PBR " + std::to_string(e.pbr ? 1 : 0),
        "REFLECTIONS " + std::to_string(e.reflections),
        "FOG " + std::to_string(e.fog ? 1 : 0),
        "DEBUG_VIEW " + std::to_string(e.debugView),
        "NORMALS " + std::to_string(e.normals),
        "MARCH_FIXED " + std::to_string(e.marchFixed ? 1 : 0),
        "SUPERSAMPLE " + std::to_string(e.supersample),
        // direct_reflections: the reflected surface lit without its shadow ray or AO, in at most 48 steps
        "BOUNCE_LIGHT " + std::to_string(e.directReflections ? 2 : 0),
        "BOUNCE_STEPS " + std::to_string(e.directReflections ? kDirectReflectionSteps : 0),
        "QUAD_REFLECTIONS " + std::to_string(e.quadReflections ? 1 : 0),
    };
    d.push_back(path == RenderPath::Compute ? "SDFVJ_COMPUTE 1" : "SDFVJ_FRAGMENT 1");
    return d;
}

// The scene's SCENE_STATE globals (lib/common.glsl), found in its text: "SCENE_STATE <type> <name>[N],
// <name>...;" at the start of a line. Each becomes a member of the blocks the compute path's frame
// setup writes and reads (main_comp.glsl SCENE_STATE_FRAME): sceneSetup() runs once per frame, not
// once per pixel. A declaration this cannot read for certain (inside an #if, or with an initialiser
// or anything else past plain names) leaves the program as it was: its setup per invocation.
static std::string SceneStateBlocks(const std::string& text) {
    static const std::regex kDecl(R"(^[ \t]*SCENE_STATE\b(.*)$)");
    static const std::regex kTyped(R"(^[ \t]+([A-Za-z_]\w*)[ \t]+([^;]*);[ \t]*(//.*)?$)");
    static const std::regex kName(R"(^[ \t]*([A-Za-z_]\w*)[ \t]*(\[[ \t]*\d+[ \t]*\])?[ \t]*$)");
    static const std::regex kOpen(R"(^[ \t]*#[ \t]*if)"), kClose(R"(^[ \t]*#[ \t]*endif)");
    std::string in, out, load, store;
    std::stringstream lines(text);
    std::string line;
    int depth = 0;
    bool comment = false;
    while (std::getline(lines, line)) {
        if (comment) {   // inside a /* */ comment: only its end matters
            comment = line.find("*/") == std::string::npos;
            continue;
        }
        const size_t open = line.find("/*");
        if (open != std::string::npos && line.find("*/", open + 2) == std::string::npos) comment = true;
        if (std::regex_search(line, kOpen)) ++depth;
        if (std::regex_search(line, kClose)) --depth;
        std::smatch m;
        if (!std::regex_search(line, m, kDecl)) continue;
        std::smatch typed;
        const std::string rest = m[1];
        if (depth > 0 || !std::regex_match(rest, typed, kTyped)) return "";
        const std::string type = typed[1];
        std::stringstream names(typed[2].str());
        std::string one;
        while (std::getline(names, one, ',')) {
            std::smatch n;
            if (!std::regex_match(one, n, kName)) return "";
            const std::string name = n[1], array = n[2];
            in += "    " + type + " sceneIn_" + name + array + ";\n";
            out += "    " + type + " sceneOut_" + name + array + ";\n";
            load += "    " + name + " = sceneIn_" + name + ";\n";
            store += "    sceneOut_" + name + " = " + name + ";\n";
        }
    }
    if (in.empty()) return "";
    // Both blocks std140 over one buffer: the same offsets whatever the members.
    return "#if SCENE_SETUP && SCENE_SETUP_FRAME\n#define SCENE_STATE_FRAME 1\n"
           "layout(std140, binding = " + std::to_string(kSceneStateBinding) + ") uniform SceneStateIn {\n" + in + "};\n"
           "layout(std140, binding = " + std::to_string(kSceneStateBinding) + ") buffer SceneStateOut {\n" + out + "};\n"
           "void sceneStateLoad() {\n" + load + "}\nvoid sceneStateStore() {\n" + store + "}\n#endif\n";
}

// After the scene: its frame state's blocks, the raymarcher, the pixel entry (supersampling) and the
// path's main().
static bool ExpandRenderer(const fs::path& root, RenderPath path, ShaderSource* s, std::string* error) {
    const std::string blocks = path == RenderPath::Compute ? SceneStateBlocks(s->text) : std::string();
    if (!blocks.empty()) s->text += LineDirective(1, 0) + blocks;
    const char* mainFile = path == RenderPath::Compute ? "main_comp.glsl" : "main_frag.glsl";
    for (const char* file : {"render.glsl", "supersample.glsl", mainFile})
        if (!ExpandIncludes((root / "render" / file).string(), s, error)) return false;
    return true;
}

std::string SceneInputUniforms(const SceneInfo& scene) {
    std::string text;
    for (const ParamDecl& p : scene.params) text += "uniform float u_" + p.name + ";\n";  // bool and int params are floats too
    return text;
}

bool AssembleProgram(const SceneInfo& scene, const VariantKey& key, ShaderSource* out, std::string* error,
                     bool liftLiterals) {
    ShaderSource s;
    s.files.push_back("<generated>");
    s.text = "#version 450 core\n";
    for (const auto& d : VariantDefines(key.effects, key.path)) s.text += "#define " + d + "\n";
    const fs::path root = fs::path(DataRoot()) / "shaders";
    if (!ExpandIncludes((root / "render" / "uniforms.glsl").string(), &s, error)) return false;
    // Scene parameters: declared once, in the scene header.
    s.text += LineDirective(1, 0);
    s.text += SceneInputUniforms(scene);
    const size_t literalsAt = s.text.size();
    if (!ExpandIncludes(scene.path, &s, error, liftLiterals)) return false;
    if (liftLiterals) {
        if (s.literals.empty()) s.literals.push_back(0.0f);   // declared either way: one skeleton, one program
        s.text.insert(literalsAt, "uniform float u_lit[" + std::to_string(s.literals.size()) + "];\n");
    }
    if (!ExpandRenderer(root, key.path, &s, error)) return false;
    s.hash = HashBytes(s.text);   // with lifted literals: the skeleton's hash, whatever their values
    *out = std::move(s);
    return true;
}

bool AssembleMorphProgram(const SceneInfo& from, const SceneInfo& to, const VariantKey& key, ShaderSource* out,
                          std::string* error) {
    ShaderSource s;
    s.files.push_back("<generated>");
    s.text = "#version 450 core\n";
    for (const auto& d : VariantDefines(key.effects, key.path)) s.text += "#define " + d + "\n";
    const fs::path root = fs::path(DataRoot()) / "shaders";
    if (!ExpandIncludes((root / "render" / "uniforms.glsl").string(), &s, error)) return false;
    s.text += LineDirective(1, 0) + "uniform float u_morph;\n";
    // The scene's own names, renamed while its text is read; its bound and ground macros saved.
    // A scene's box (SCENE_BOX) is dropped: it holds that scene's shapes, not the mix; the sphere
    // around both spheres below bounds the morph. Its objects (SCENE_OBJECTS) are dropped too: the
    // morph's map() is no union of one floor and one set of objects.
    static const char* kRenamed[] = {"map",         "sceneLipschitz", "sceneBound", "mapGround",       "sceneSetup",
                                     "sceneBoxMin", "sceneBoxMax",    "mapObjects", "sceneGroundBlend"};
    auto include = [&](const SceneInfo& scene, const std::string& prefix) {
        s.text += LineDirective(1, 0);
        for (const ParamDecl& p : scene.params) s.text += "uniform float u_" + prefix + "_" + p.name + ";\n";
        for (const char* name : kRenamed) s.text += "#define " + std::string(name) + " " + prefix + "_" + name + "\n";
        for (const ParamDecl& p : scene.params) s.text += "#define u_" + p.name + " u_" + prefix + "_" + p.name + "\n";
        if (!ExpandIncludes(scene.path, &s, error)) return false;
        s.text += LineDirective(1, 0);
        for (const char* name : kRenamed) s.text += "#undef " + std::string(name) + "\n";
        for (const ParamDecl& p : scene.params) s.text += "#undef u_" + p.name + "\n";
        for (const char* macro : {"BOUND", "GROUND", "SETUP", "BOX", "OBJECTS"}) {
            const std::string m = std::string("SCENE_") + macro, saved = "MORPH_" + prefix + "_" + macro;
            s.text += "#if defined(" + m + ") && " + m + "\n#define " + saved + " 1\n#else\n#define " + saved +
                      " 0\n#endif\n#undef " + m + "\n";
        }
        return true;
    };
    if (!include(from, "m0") || !include(to, "m1")) return false;
    s.text += LineDirective(1, 0);
    s.text +=
        "#define SCENE_SETUP 1\n"   // each scene's per-invocation state (render.glsl SCENE_SETUP), if it has any
        "void sceneSetup() {\n"
        "#if MORPH_m0_SETUP\n    m0_sceneSetup();\n#endif\n"
        "#if MORPH_m1_SETUP\n    m1_sceneSetup();\n#endif\n"
        "}\n"
        "vec4 map(vec3 p) { return mix(m0_map(p), m1_map(p), u_morph); }\n"
        "float sceneLipschitz() { return mix(m0_sceneLipschitz(), m1_sceneLipschitz(), u_morph); }\n"
        // Off the union of the two spheres each field is its own ground (or empty), so the mix is
        // the mix of the grounds there: one sphere around both is a bound of the morph.
        "#if MORPH_m0_BOUND && MORPH_m1_BOUND && MORPH_m0_GROUND == MORPH_m1_GROUND\n"
        "#define SCENE_BOUND 1\n"
        "vec4 sceneBound() {\n"
        "    vec4 a = m0_sceneBound(), b = m1_sceneBound();\n"
        "    vec3 ca = vec3(a.x, a.y, a.z), cb = vec3(b.x, b.y, b.z);\n"
        "    float d = length(cb - ca);\n"
        "    if (d + b.w <= a.w) return a;\n"
        "    if (d + a.w <= b.w) return b;\n"
        "    float r = 0.5f * (d + a.w + b.w);\n"
        "    vec3 c = ca + (cb - ca) * ((r - a.w) / d);\n"
        "    return vec4(c.x, c.y, c.z, r + 1e-3f);\n"
        "}\n"
        "#if MORPH_m0_GROUND\n"
        "#define SCENE_GROUND 1\n"
        "vec4 mapGround(vec3 p) { return mix(m0_mapGround(p), m1_mapGround(p), u_morph); }\n"
        "#endif\n"
        "#endif\n";
    if (!ExpandRenderer(root, key.path, &s, error)) return false;
    s.hash = HashBytes(s.text);
    *out = std::move(s);
    return true;
}

std::string MapCompileLog(const std::string& log, const ShaderSource& src) {
    static const std::regex kMesa(R"(^(\d+):(\d+)\(\d+\):\s*(.*)$)");
    static const std::regex kNvidia(R"(^(\d+)\((\d+)\)\s*:\s*(.*)$)");
    std::stringstream in(log), out;
    std::string line;
    while (std::getline(in, line)) {
        std::smatch m;
        if (std::regex_match(line, m, kMesa) || std::regex_match(line, m, kNvidia)) {
            // The driver's log is outside input too: numbers parsed with a range check.
            size_t file = 0;
            long lineNo = 0;
            const std::string fileText = m[1].str(), lineText = m[2].str();
            if (std::from_chars(fileText.data(), fileText.data() + fileText.size(), file).ec != std::errc() ||
                std::from_chars(lineText.data(), lineText.data() + lineText.size(), lineNo).ec != std::errc()) {
                out << line << "\n";
                continue;
            }
            if (lineNo >= kLinesPerFile) {
                file = (size_t)(lineNo / kLinesPerFile);
                lineNo %= kLinesPerFile;
            }
            std::string name = file < src.files.size() ? DisplayPath(src.files[file]) : "<source " + m[1].str() + ">";
            out << name << ":" << lineNo << ": " << m[3] << "\n";
        } else if (!line.empty()) {
            out << line << "\n";
        }
    }
    return out.str();
}

const char* FullscreenVertexShader() { return kVertexShader; }

}  // namespace sdfvj
