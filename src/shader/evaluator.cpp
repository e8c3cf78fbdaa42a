// The evaluator's front end: the unit a scene is translated from, glslang, and the code buffer's
// layout. The SPIR-V translation is evaluator_translate.cpp, the CPU machine evaluator_machine.cpp.
#include "shader/evaluator.h"

#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>
#include <glslang/SPIRV/GlslangToSpv.h>

#include <charconv>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <regex>
#include <sstream>

#include "shader/evaluator_internal.h"

namespace fs = std::filesystem;

namespace sdfvj::eval {

namespace {

// ExpandIncludes folds a file's index into its line numbers (shader.cpp kLinesPerFile): the line
// glslang reports is index * 100000 + line.
constexpr uint32_t kLinesPerFile = 100000;
const char* kFilesTag = "// sdfvj-evaluator-files: ";

// What each hook returns and takes, as the renderer calls it (render.glsl, march.glsl).
struct HookSig {
    const char* name;
    const char* type;
    const char* call;   // the call main() makes
};
const HookSig kHooks[] = {
    {"map", "vec4", "map(q)"},
    {"mapGround", "vec4", "mapGround(q)"},
    {"mapObjects", "vec4", "mapObjects(q)"},
    {"sceneBound", "vec4", "sceneBound()"},
    {"sceneLipschitz", "float", "vec4(sceneLipschitz())"},
    {"sceneGroundBlend", "float", "vec4(sceneGroundBlend())"},
    {"sceneBoxMin", "vec3", "vec4(sceneBoxMin(), 0.0)"},
    {"sceneBoxMax", "vec3", "vec4(sceneBoxMax(), 0.0)"},
    {"sceneSetup", "void", ""},
};

}  // namespace

const std::vector<std::string>& HookNames() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> n;
        for (const HookSig& h : kHooks) n.push_back(h.name);
        return n;
    }();
    return names;
}

const Entry* Program::Find(const std::string& name) const {
    for (const Entry& e : entries)
        if (e.name == name) return &e;
    return nullptr;
}

std::vector<std::array<uint32_t, 4>> PackCode(const Program& program) {
    std::vector<std::array<uint32_t, 4>> out;
    for (const std::string& name : HookNames()) {
        const Entry* e = program.Find(name);
        if (!e) {
            out.push_back({0, kNone, kNone, 0});
            continue;
        }
        out.push_back({e->pc, e->args.empty() ? kNone : e->args[0], e->result, 1});
    }
    for (const Instr& i : program.code) out.push_back(i.Packed());
    return out;
}

std::string UnitFiles::Where(uint32_t line) const {
    if (line == 0) return name;
    const uint32_t index = line / kLinesPerFile;
    if (index == 0 || index >= files.size()) return name + ":" + std::to_string(line);
    return DisplayPath(files[index]) + ":" + std::to_string(line % kLinesPerFile);
}

std::vector<std::string> UniformSlots(const SceneInfo& scene) {
    std::vector<std::string> slots;
    std::ifstream in(fs::path(DataRoot()) / "shaders" / "render" / "uniforms.glsl");
    static const std::regex kUniform(R"(^\s*uniform\s+\w+\s+(\w+)\s*;)");
    std::string line;
    while (std::getline(in, line)) {
        std::smatch m;
        if (std::regex_search(line, m, kUniform)) slots.push_back(m[1]);
    }
    for (const ParamDecl& p : scene.params) slots.push_back("u_" + p.name);
    return slots;
}

bool AssembleEvaluatorUnit(const SceneInfo& scene, const VariantKey& key, std::string* unit,
                           std::vector<std::string>* uniformSlots, std::string* error) {
    ShaderSource s;
    s.files.push_back("<generated>");
    s.text = "#version 450 core\n";
    for (const auto& d : VariantDefines(key.effects, key.path)) s.text += "#define " + d + "\n";
    s.text += "#define SCENE_SETUP_FRAME 0\n#define SCENE_TABLES 0\n";
    const fs::path root = fs::path(DataRoot()) / "shaders";
    if (!ExpandIncludes((root / "render" / "uniforms.glsl").string(), &s, error)) return false;
    s.text += "#line 1 0\n" + SceneInputUniforms(scene);
    const size_t sceneAt = s.text.size();
    if (!ExpandIncludes(scene.path, &s, error)) return false;
    // Which hooks the scene defines: a definition starts a line with its return type and name.
    // (A scan by hand: std::regex over the expanded scene took milliseconds.)
    const std::string sceneText = s.text.substr(sceneAt);
    auto defines = [&](const HookSig& h) {
        const std::string type = h.type, name = h.name;
        for (size_t at = 0; at < sceneText.size();) {
            size_t end = sceneText.find('\n', at);
            if (end == std::string::npos) end = sceneText.size();
            size_t i = sceneText.find_first_not_of(" \t", at);
            auto word = [&](const std::string& w) {
                if (i >= end || sceneText.compare(i, w.size(), w) != 0) return false;
                i += w.size();
                return true;
            };
            auto spaces = [&] {
                const size_t from = i;
                while (i < end && (sceneText[i] == ' ' || sceneText[i] == '\t')) ++i;
                return i > from;
            };
            if (word(type) && spaces() && word(name)) {
                spaces();
                if (i < end && sceneText[i] == '(') return true;
            }
            at = end + 1;
        }
        return false;
    };
    std::string calls;
    bool setup = false;
    for (const HookSig& h : kHooks) {
        if (!defines(h)) continue;
        if (std::string(h.name) == "sceneSetup")
            setup = true;
        else
            calls += "    r += " + std::string(h.call) + ";\n";
    }
    s.text += "#line 1 0\nlayout(local_size_x = 1) in;\n"
              "layout(std430, binding = 0) buffer SdfvjEvaluatorOut { vec4 sdfvjEvaluatorOut; };\n"
              "void main() {\n    vec3 q = vec3(u_time);\n    vec4 r = vec4(0.0);\n";
    if (setup) s.text += "    sceneSetup();\n";
    s.text += calls + "    sdfvjEvaluatorOut = r;\n}\n";
    s.text += kFilesTag;
    for (size_t i = 0; i < s.files.size(); ++i) s.text += (i ? "|" : "") + s.files[i];
    s.text += "\n";
    *unit = std::move(s.text);
    *uniformSlots = UniformSlots(scene);
    return true;
}

namespace {

std::mutex gGlslangMutex;   // glslang's process state and its pools are not for two threads at once

// glslang's "ERROR: 0:100042: what" -> "shaders/scenes/x.glsl:42: what".
std::string MapGlslangLog(const std::string& log, const UnitFiles& files) {
    static const std::regex kLine(R"(^(ERROR|WARNING): \d+:(\d+): (.*)$)");
    std::stringstream in(log);
    std::string line, out;
    while (std::getline(in, line)) {
        std::smatch m;
        if (std::regex_match(line, m, kLine)) {
            if (m[1] != "ERROR") continue;
            const std::string at = m[2];
            uint32_t where = 0;
            if (std::from_chars(at.data(), at.data() + at.size(), where).ec == std::errc()) out += files.Where(where) + ": " + m[3].str() + "\n";
            else out += line + "\n";
        } else if (!line.empty() && line.find("compilation errors") == std::string::npos) {
            out += line + "\n";
        }
    }
    while (!out.empty() && out.back() == '\n') out.pop_back();
    return out;
}

// The files a unit was assembled from, read back from its last comment line (AssembleEvaluatorUnit).
UnitFiles UnitFilesOf(const std::string& unit) {
    UnitFiles f;
    f.name = "unit";
    const size_t at = unit.rfind(kFilesTag);
    if (at == std::string::npos) return f;
    const size_t begin = at + std::string(kFilesTag).size();
    std::stringstream list(unit.substr(begin, unit.find('\n', begin) - begin));
    std::string one;
    while (std::getline(list, one, '|')) f.files.push_back(one);
    if (f.files.size() > 1) {
        // The scene is the first file after uniforms.glsl that is under scenes/ (else the last).
        f.name = DisplayPath(f.files.back());
        for (const std::string& file : f.files)
            if (file.find("/scenes/") != std::string::npos) {
                f.name = DisplayPath(file);
                break;
            }
    }
    return f;
}

}  // namespace

bool CompileSpirv(const std::string& unit, std::vector<uint32_t>* words, std::string* error) {
    std::lock_guard<std::mutex> lock(gGlslangMutex);
    static const bool initialized = glslang::InitializeProcess();
    if (!initialized) {
        *error = "evaluator: glslang did not initialize";
        return false;
    }
    const UnitFiles files = UnitFilesOf(unit);
    glslang::TShader shader(EShLangCompute);
    const char* text = unit.c_str();
    const int length = (int)unit.size();
    const char* name = "unit";
    shader.setStringsWithLengthsAndNames(&text, &length, &name, 1);
    shader.setEnvInput(glslang::EShSourceGlsl, EShLangCompute, glslang::EShClientOpenGL, 450);
    shader.setEnvClient(glslang::EShClientOpenGL, glslang::EShTargetOpenGL_450);
    shader.setEnvTarget(glslang::EShTargetSpv, glslang::EShTargetSpv_1_0);
    shader.setAutoMapLocations(true);
    shader.setAutoMapBindings(true);
    const EShMessages messages = (EShMessages)(EShMsgSpvRules);
    if (!shader.parse(GetDefaultResources(), 450, false, messages)) {
        *error = "evaluator: " + files.name + ": glslang: " + MapGlslangLog(shader.getInfoLog(), files);
        return false;
    }
    glslang::TProgram program;
    program.addShader(&shader);
    if (!program.link(messages) || !program.mapIO()) {
        *error = "evaluator: " + files.name + ": glslang link: " + MapGlslangLog(program.getInfoLog(), files);
        return false;
    }
    glslang::SpvOptions options;
    options.disableOptimizer = true;
    options.generateDebugInfo = true;   // OpLine: a rejected construct names its line
    spv::SpvBuildLogger logger;
    std::vector<unsigned int> spirv;
    glslang::GlslangToSpv(*program.getIntermediate(EShLangCompute), spirv, &logger, &options);
    words->assign(spirv.begin(), spirv.end());
    return true;
}

void PrepareTranslator() {
    std::vector<uint32_t> words;
    std::string error;
    CompileSpirv("#version 450 core\nlayout(local_size_x = 1) in;\nvoid main() {}\n", &words, &error);
}

bool Translate(const std::string& unit, const std::vector<std::string>& uniformSlots, Program* out,
               std::string* error) {
    try {
        std::vector<uint32_t> words;
        if (!CompileSpirv(unit, &words, error)) return false;
        return TranslateSpirv(words, uniformSlots, UnitFilesOf(unit), out, error);
    } catch (const std::exception& e) {
        *error = std::string("evaluator: ") + e.what();
    } catch (...) {
        *error = "evaluator: the translation failed";
    }
    return false;
}

}  // namespace sdfvj::eval
