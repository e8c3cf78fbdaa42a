// The evaluator's GPU program (eval_program.h): the scene's stub, the machine's constants and the
// uniform slot table generated in front of render/eval.glsl.
#include "shader/eval_program.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "shader/evaluator.h"

namespace fs = std::filesystem;

namespace sdfvj {

namespace {

// "LoadUniform" -> "LOAD_UNIFORM", "mapGround" -> "MAP_GROUND": the GLSL spelling of a C++ name.
std::string UpperSnake(const std::string& name) {
    std::string s;
    for (size_t i = 0; i < name.size(); ++i) {
        const char c = name[i];
        if (i > 0 && std::isupper((unsigned char)c) && !std::isupper((unsigned char)name[i - 1])) s += '_';
        s += (char)std::toupper((unsigned char)c);
    }
    return s;
}

// Every op of evaluator.h, its name and its value from one token: a name cannot be paired with
// another op's value, and the count is checked against kOpCount at compile time.
#define SDFVJ_EV_OP(name) {#name, eval::k##name}
const std::pair<const char*, uint32_t> kOps[] = {
    SDFVJ_EV_OP(Nop), SDFVJ_EV_OP(Mov), SDFVJ_EV_OP(Swizzle), SDFVJ_EV_OP(SetComp), SDFVJ_EV_OP(LoadUniform),
    SDFVJ_EV_OP(LoadIndexed), SDFVJ_EV_OP(StoreIndexed), SDFVJ_EV_OP(Add), SDFVJ_EV_OP(Sub), SDFVJ_EV_OP(Mul),
    SDFVJ_EV_OP(Div), SDFVJ_EV_OP(Neg), SDFVJ_EV_OP(Fma), SDFVJ_EV_OP(Mod), SDFVJ_EV_OP(Min), SDFVJ_EV_OP(Max),
    SDFVJ_EV_OP(Clamp), SDFVJ_EV_OP(Mix), SDFVJ_EV_OP(Step), SDFVJ_EV_OP(Smoothstep), SDFVJ_EV_OP(Abs),
    SDFVJ_EV_OP(Sign), SDFVJ_EV_OP(Floor), SDFVJ_EV_OP(Ceil), SDFVJ_EV_OP(Fract), SDFVJ_EV_OP(Round),
    SDFVJ_EV_OP(Trunc), SDFVJ_EV_OP(Sqrt), SDFVJ_EV_OP(InverseSqrt), SDFVJ_EV_OP(Exp), SDFVJ_EV_OP(Exp2),
    SDFVJ_EV_OP(Log), SDFVJ_EV_OP(Log2), SDFVJ_EV_OP(Pow), SDFVJ_EV_OP(Sin), SDFVJ_EV_OP(Cos), SDFVJ_EV_OP(Tan),
    SDFVJ_EV_OP(Asin), SDFVJ_EV_OP(Acos), SDFVJ_EV_OP(Atan), SDFVJ_EV_OP(Atan2), SDFVJ_EV_OP(Dot),
    SDFVJ_EV_OP(Cross), SDFVJ_EV_OP(Less), SDFVJ_EV_OP(LessEqual), SDFVJ_EV_OP(Greater), SDFVJ_EV_OP(GreaterEqual),
    SDFVJ_EV_OP(Equal), SDFVJ_EV_OP(NotEqual), SDFVJ_EV_OP(And), SDFVJ_EV_OP(Or), SDFVJ_EV_OP(Not),
    SDFVJ_EV_OP(Select), SDFVJ_EV_OP(IntDiv), SDFVJ_EV_OP(IntRem), SDFVJ_EV_OP(ShiftRight), SDFVJ_EV_OP(ShiftLeft),
    SDFVJ_EV_OP(BitAnd), SDFVJ_EV_OP(BitOr), SDFVJ_EV_OP(BitXor), SDFVJ_EV_OP(Any), SDFVJ_EV_OP(All),
    SDFVJ_EV_OP(Jump), SDFVJ_EV_OP(JumpIfZero), SDFVJ_EV_OP(JumpIfNotZero), SDFVJ_EV_OP(Return),
};
#undef SDFVJ_EV_OP
static_assert(sizeof kOps / sizeof kOps[0] == eval::kOpCount, "every op of evaluator.h needs its GLSL constant here");
static_assert((eval::kMaxRegisters & (eval::kMaxRegisters - 1)) == 0, "eval.glsl keeps register indices in range with a mask");
static_assert(eval::kMaxRegisters <= (1u << eval::kLaneShift), "a register operand's lane bits are above its index");

// The hooks as the renderer declares them, and what a stub's body calls (render/eval.glsl).
struct Hook {
    const char* name;
    const char* type;
    int args;   // 0, or 1 (a vec3)
};
const Hook kHooks[] = {
    {"map", "vec4", 1},        {"mapGround", "vec4", 1},       {"mapObjects", "vec4", 1},
    {"sceneBound", "vec4", 0}, {"sceneLipschitz", "float", 0}, {"sceneGroundBlend", "float", 0},
    {"sceneBoxMin", "vec3", 0}, {"sceneBoxMax", "vec3", 0},    {"sceneSetup", "void", 0},
};
const Hook* FindHook(const std::string& name) {
    for (const Hook& h : kHooks)
        if (name == h.name) return &h;
    return nullptr;
}

std::string Trim(const std::string& s) {
    const size_t a = s.find_first_not_of(" \t\r\n"), b = s.find_last_not_of(" \t\r\n");
    return a == std::string::npos ? std::string() : s.substr(a, b - a + 1);
}

// Reads an expanded scene's top level: comments, preprocessor lines and brace depth are all it
// needs to tell a function definition (`type name(params) {` at depth 0) from everything else.
// GLSL has no string or character literals.
class StubScanner {
public:
    StubScanner(const std::string& text, int sceneFile, const std::vector<std::string>& files)
        : t_(text), sceneFile_(sceneFile), files_(files) {}

    bool Run(std::string* out, std::string* error) {
        while (i_ < t_.size() && error_.empty()) Step();
        if (error_.empty() && (depth_ != 0 || inComment_)) Fail("a brace or a comment is not closed where the file ends");
        if (error_.empty() && stubbed_ == 0) Fail("no hook function (map, sceneLipschitz, ...) is defined");
        if (!error_.empty()) {
            *error = error_;
            return false;
        }
        EndStatement();
        *out = std::move(out_);
        return true;
    }

private:
    const std::string& t_;
    size_t i_ = 0;
    int sceneFile_, file_ = -1;
    const std::vector<std::string>& files_;
    std::string out_, error_;
    bool lineStart_ = true, inComment_ = false;
    int depth_ = 0;              // braces open
    std::string raw_, code_;     // the statement (or function header) so far: as written; comments blanked
    bool stmtPp_ = false;        // a preprocessor line inside it
    bool inFunction_ = false;    // depth_ > 0 belongs to a function's body
    std::string header_, body_;  // the function's header (code, one line) and its body as written
    std::string fnName_, fnType_, fnParams_, bodyDirective_;
    int fnFile_ = -1, stubbed_ = 0;

    bool InScene() const { return file_ == sceneFile_; }
    std::string FileName() const {
        return file_ >= 0 && (size_t)file_ < files_.size() ? DisplayPath(files_[(size_t)file_]) : std::string("<scene>");
    }
    void Fail(const std::string& what) {
        if (error_.empty()) error_ = FileName() + ": " + what;
    }
    void NewLine() {
        if (!out_.empty() && out_.back() != '\n') out_ += '\n';
    }
    // The scene file's own text: its non-blank lines, right-trimmed (a blank line or a comment
    // edited in it leaves the stub as it was).
    void EmitScene(const std::string& text) {
        std::stringstream lines(text);
        for (std::string line; std::getline(lines, line);) {
            const size_t end = line.find_last_not_of(" \t\r");
            if (end == std::string::npos) continue;
            NewLine();
            out_ += line.substr(0, end + 1) + "\n";
        }
    }
    void EndStatement() {
        if (InScene()) EmitScene(code_);
        else out_ += raw_;
        raw_.clear();
        code_.clear();
        stmtPp_ = false;
    }
    void Add(const std::string& raw, const std::string& code) {
        if (inFunction_) {
            body_ += raw;
        } else {
            raw_ += raw;
            code_ += code;
        }
    }

    void Step() {
        const char c = t_[i_];
        if (c == '/' && i_ + 1 < t_.size() && (t_[i_ + 1] == '/' || t_[i_ + 1] == '*')) return Comment();
        if (c == '#' && lineStart_) return Directive();
        ++i_;
        if (c == '\n') lineStart_ = true;
        else if (c != ' ' && c != '\t' && c != '\r') lineStart_ = false;
        if (c == '{') return Open();
        if (c == '}') return Close();
        Add(std::string(1, c), std::string(1, c));
        if (c == ';' && depth_ == 0) EndStatement();
    }

    void Comment() {
        const bool line = t_[i_ + 1] == '/';
        const size_t end = line ? t_.find('\n', i_) : t_.find("*/", i_ + 2);
        if (!line && end == std::string::npos) {
            inComment_ = true;
            i_ = t_.size();
            return;
        }
        const size_t stop = line ? (end == std::string::npos ? t_.size() : end) : end + 2;
        const std::string text = t_.substr(i_, stop - i_);
        i_ = stop;
        // Blanked: a space, or a line break where the comment held one (a directive after it stays on a line of its own).
        Add(text, text.find('\n') != std::string::npos ? "\n" : " ");
    }

    // A preprocessor line (continued by '\' at its end), its comments blanked in `code`.
    void Directive() {
        std::string raw, code;
        while (i_ < t_.size() && t_[i_] != '\n') {
            if (t_[i_] == '\\' && i_ + 1 < t_.size() && t_[i_ + 1] == '\n') {
                raw += "\\\n";
                code += "\\\n";
                i_ += 2;
            } else if (t_.compare(i_, 2, "//") == 0) {
                const size_t end = std::min(t_.find('\n', i_), t_.size());
                raw += t_.substr(i_, end - i_);
                i_ = end;
            } else if (t_.compare(i_, 2, "/*") == 0) {
                const size_t end = t_.find("*/", i_ + 2);
                if (end == std::string::npos) return Fail("a comment in a preprocessor line is not closed");
                raw += t_.substr(i_, end + 2 - i_);
                code += ' ';
                i_ = end + 2;
            } else {
                raw += t_[i_];
                code += t_[i_++];
            }
        }
        static const std::regex kName(R"(^\s*#\s*(\w*))");
        std::smatch m;
        std::regex_search(code, m, kName);
        const std::string name = m[1];
        if (inFunction_ || depth_ > 0) {
            static const char* kKept[] = {"if", "ifdef", "ifndef", "elif", "else", "endif", "pragma", "error"};
            if (inFunction_ && bodyDirective_.empty() && std::find(std::begin(kKept), std::end(kKept), name) == std::end(kKept))
                bodyDirective_ = Trim(code);
            return Add(raw, code);
        }
        if (!Trim(code_).empty()) {   // inside a declaration that spans lines
            stmtPp_ = true;
            return Add(raw, code);
        }
        if (!InScene()) out_ += raw_;   // the whitespace before it
        raw_.clear();
        code_.clear();
        static const std::regex kLine(R"(^\s*#\s*line\s+\d+\s+(\d+)\s*$)");
        if (std::regex_match(code, m, kLine)) {
            // The file index of a line marker (the text may be a save's, so checked, not stoi)
            const std::string index = m[1];
            int f = -1;
            if (std::from_chars(index.data(), index.data() + index.size(), f).ec != std::errc())
                return Fail("#line names source " + index + ", expected a source number that fits an int");
            file_ = f;
            // The scene's line numbers move with every edit of a body above them: not in the stub.
            if (InScene()) {
                NewLine();
                out_ += "#line " + std::to_string(file_ * 100000 + 1) + " " + std::to_string(file_) + "\n";
                return;
            }
        }
        if (InScene()) EmitScene(code);
        else out_ += raw;
    }

    void Open() {
        if (depth_++ > 0 || inFunction_) return Add("{", "{");
        // Depth 0: a function's body, or a struct, block or initializer list inside a declaration.
        std::string plain;   // the header without its preprocessor lines
        std::stringstream lines(code_);
        for (std::string line; std::getline(lines, line);)
            if (Trim(line).rfind('#', 0) != 0) plain += line + " ";
        static const std::regex kHeader(R"(^\s*((?:\w+\s+)*?)(\w+(?:\s*\[\s*\w*\s*\])?)\s+(\w+)\s*\(([^()]*)\)\s*$)");
        std::smatch m;
        if (!std::regex_match(plain, m, kHeader)) return Add("{", "{");
        if (stmtPp_) return Fail(m[3].str() + "(): a preprocessor line inside its header");
        inFunction_ = true;
        fnType_ = m[2];
        fnName_ = m[3];
        fnParams_ = Trim(m[4]);
        fnFile_ = file_;
        header_ = std::regex_replace(Trim(plain), std::regex(R"(\s+)"), " ");
        body_ = "{";
        bodyDirective_.clear();
    }

    void Close() {
        if (--depth_ < 0) return Fail("a '}' closes nothing");
        if (!inFunction_) return Add("}", "}");
        body_ += '}';
        if (depth_ == 0) EndFunction();
    }

    void EndFunction() {
        inFunction_ = false;
        const Hook* hook = FindHook(fnName_);
        if (!hook && fnFile_ != sceneFile_) {   // an included file's helper: kept as written
            out_ += raw_ + body_;
        } else if (!hook) {
            // The scene's helper: only the hooks' code (the machine's) calls it.
            if (!bodyDirective_.empty()) return Fail(fnName_ + "(): '" + bodyDirective_ + "' inside its body (the stub drops the body)");
        } else {
            if (!bodyDirective_.empty()) return Fail(fnName_ + "(): '" + bodyDirective_ + "' inside its body (the stub drops the body)");
            // The renderer's signature (render.glsl): a vec3 argument or none.
            std::string arg;
            const bool noArgs = fnParams_.empty() || fnParams_ == "void";
            if (hook->args == 1 && !noArgs && fnParams_.find(',') == std::string::npos &&
                std::regex_search(fnParams_, std::regex(R"(\bvec3\b)"))) {
                std::smatch m;
                std::regex_search(fnParams_, m, std::regex(R"((\w+)\s*$)"));
                arg = m[1];
            }
            if (fnType_ != hook->type || (hook->args == 0 && !noArgs) || (hook->args == 1 && arg.empty()))
                return Fail(fnName_ + "() is not the renderer's " + hook->type + " " + hook->name + "(" +
                            (hook->args ? "vec3" : "") + "): '" + header_ + "'");
            std::string call = std::string("eval") + (char)std::toupper((unsigned char)hook->name[0]) + (hook->name + 1) + "(" + arg + ")";
            NewLine();
            out_ += header_ + " { " + (std::string(hook->type) == "void" ? "" : "return ") + call + "; }\n";
            ++stubbed_;
        }
        raw_.clear();
        code_.clear();
        body_.clear();
        stmtPp_ = false;
    }
};

// `vec4 evalUniform(uint slot)`: each slot (eval::UniformSlots: the built-in uniforms of
// render/uniforms.glsl in declaration order, then the scene's inputs) as a vec4 (ints as floats,
// vec2/vec3 padded with 0), the way kLoadUniform reads it.
bool UniformTable(const SceneInfo& scene, std::string* out, std::string* error) {
    std::vector<std::pair<std::string, std::string>> declared;   // name, type
    std::ifstream in(fs::path(DataRoot()) / "shaders" / "render" / "uniforms.glsl");
    static const std::regex kUniform(R"(^\s*uniform\s+(\w+)\s+(\w+)\s*;)");
    for (std::string line; std::getline(in, line);) {
        std::smatch m;
        if (std::regex_search(line, m, kUniform)) declared.emplace_back(m[2], m[1]);
    }
    for (const ParamDecl& p : scene.params) declared.emplace_back("u_" + p.name, "float");   // SceneInputUniforms
    const std::vector<std::string> slots = eval::UniformSlots(scene);
    std::string text = "vec4 evalUniform(uint slot) {\n    switch (slot) {\n";
    for (size_t i = 0; i < slots.size(); ++i) {
        std::string type;
        for (const auto& [name, t] : declared)
            if (name == slots[i]) type = t;
        std::string value;
        if (type == "float") value = "vec4(" + slots[i] + ", 0.0, 0.0, 0.0)";
        else if (type == "int" || type == "uint" || type == "bool") value = "vec4(float(" + slots[i] + "), 0.0, 0.0, 0.0)";
        else if (type == "vec2") value = "vec4(" + slots[i] + ", 0.0, 0.0)";
        else if (type == "vec3") value = "vec4(" + slots[i] + ", 0.0)";
        else if (type == "vec4") value = slots[i];
        else {
            *error = "evaluator: uniform slot " + std::to_string(i) + " '" + slots[i] + "' has " +
                     (type.empty() ? "no declaration" : "type " + type) + " the slot table can read (float, int, uint, bool, vec2-4)";
            return false;
        }
        text += "    case " + std::to_string(i) + "u: return " + value + ";\n";
    }
    *out = text + "    }\n    return vec4(0.0);\n}\n";
    return true;
}

// What eval.glsl expects in front of it (its header comment).
std::string MachineConstants() {
    std::string s;
    for (const auto& [name, value] : EvaluatorOpConstants()) s += "const uint " + name + " = " + std::to_string(value) + "u;\n";
    const auto& hooks = eval::HookNames();
    for (size_t i = 0; i < hooks.size(); ++i) s += "const uint EV_HOOK_" + UpperSnake(hooks[i]) + " = " + std::to_string(i) + "u;\n";
    s += "const uint EV_HOOKS = " + std::to_string(hooks.size()) + "u;\n";
    s += "const uint EV_MAX_REGISTERS = " + std::to_string(eval::kMaxRegisters) + "u;\n";
    s += "const uint EV_NONE = " + std::to_string(eval::kNone) + "u;\n";
    s += "const uint EV_CONST_FLAG = " + std::to_string(eval::kConstFlag) + "u;\n";
    s += "const uint EV_LANE_SHIFT = " + std::to_string(eval::kLaneShift) + "u;\n";
    s += "#define EV_CODE_BINDING " + std::to_string(kEvalCodeBinding) + "\n";
    s += "#define EV_CONST_BINDING " + std::to_string(kEvalConstBinding) + "\n";
    return s;
}

// The uniforms, the scene's inputs, the machine's constants, its uniform table and the machine
// (render/eval.glsl), after `s`'s defines: what the evaluator program and the probe share.
bool AppendMachine(const SceneInfo& scene, const fs::path& root, ShaderSource* s, std::string* error) {
    if (!ExpandIncludes((root / "render" / "uniforms.glsl").string(), s, error)) return false;
    std::string table;
    if (!UniformTable(scene, &table, error)) return false;
    s->text += "#line 1 0\n" + SceneInputUniforms(scene) + MachineConstants() + table;
    return ExpandIncludes((root / "render" / "eval.glsl").string(), s, error);
}

}  // namespace

const std::vector<std::pair<std::string, uint32_t>>& EvaluatorOpConstants() {
    static const std::vector<std::pair<std::string, uint32_t>> ops = [] {
        std::vector<std::pair<std::string, uint32_t>> v;
        for (const auto& [name, value] : kOps) v.emplace_back("EV_" + UpperSnake(name), value);
        return v;
    }();
    return ops;
}

bool EvaluatorStub(const std::string& text, int sceneFile, const std::vector<std::string>& files, std::string* out,
                   std::string* error) {
    return StubScanner(text, sceneFile, files).Run(out, error);
}

bool AssembleEvaluatorProgram(const SceneInfo& scene, const VariantKey& key, ShaderSource* out, std::string* error,
                              int unroll) {
    if (unroll != 1 && unroll != 2 && unroll != 4 && unroll != 8 && unroll != 16) {
        *error = "evaluator: unroll " + std::to_string(unroll) + ", expected 1, 2, 4, 8 or 16";
        return false;
    }
    // The machine's hook slots are evaluator.h's (HookNames order); eval.glsl names these.
    for (const Hook& h : kHooks)
        if (std::find(eval::HookNames().begin(), eval::HookNames().end(), h.name) == eval::HookNames().end()) {
            *error = std::string("evaluator: hook ") + h.name + " is not among evaluator.h's HookNames()";
            return false;
        }
    ShaderSource s;
    s.files.push_back("<generated>");
    s.text = "#version 450 core\n#define SCENE_EVALUATOR 1\n#define SCENE_SETUP_FRAME 0\n#define SCENE_TABLES 0\n"
             "#define ONE_SITE 1\n#define CONE_PREPASS 0\n";
    if (unroll > 1) s.text += "#define EV_UNROLL " + std::to_string(unroll) + "\n";
    for (const auto& d : VariantDefines(key.effects, key.path)) s.text += "#define " + d + "\n";
    const fs::path root = fs::path(DataRoot()) / "shaders";
    if (!AppendMachine(scene, root, &s, error)) return false;
    const size_t sceneAt = s.text.size();
    if (!ExpandIncludes(scene.path, &s, error)) return false;
    const std::string canonical = fs::weakly_canonical(scene.path).string();
    const int sceneFile = (int)(std::find(s.files.begin(), s.files.end(), canonical) - s.files.begin());
    std::string stub;
    if (!EvaluatorStub(s.text.substr(sceneAt), sceneFile, s.files, &stub, error)) {
        *error = "evaluator: " + *error;
        return false;
    }
    s.text.resize(sceneAt);
    s.text += stub;
    // The renderer composes the floor's union itself (render.glsl SCENE_MAP_OF, SCENE_GROUND_SMIN). A
    // scene's own forms of them may read its SCENE_STATE (lib/field_scene.glsl: the blend's
    // reciprocal), which here the machine's registers hold, not the GLSL globals: the renderer's
    // forms, from sceneGroundBlend(), the same union by its contract.
    s.text += "#line 1 0\n#undef SCENE_MAP_OF\n#undef SCENE_GROUND_SMIN\n";
    // The renderer as AssembleProgram adds it, without the frame state's blocks (SCENE_SETUP_FRAME 0).
    const char* mainFile = key.path == RenderPath::Compute ? "main_comp.glsl" : "main_frag.glsl";
    for (const char* file : {"render.glsl", "supersample.glsl", mainFile})
        if (!ExpandIncludes((root / "render" / file).string(), &s, error)) return false;
    s.hash = HashBytes(s.text);
    *out = std::move(s);
    return true;
}

bool AssembleEvaluatorProbe(const SceneInfo& scene, ShaderSource* out, std::string* error) {
    ShaderSource s;
    s.files.push_back("<generated>");
    s.text = "#version 450 core\n#define SCENE_EVALUATOR 1\n#define SDFVJ_COMPUTE 1\n";
    const fs::path root = fs::path(DataRoot()) / "shaders";
    if (!AppendMachine(scene, root, &s, error)) return false;
    s.text += "#line 1 0\nlayout(local_size_x = 64) in;\n"
              "layout(std430, binding = 0) readonly buffer ProbeIn { vec4 probeIn[]; };\n"
              "layout(std430, binding = 1) writeonly buffer ProbeOut { vec4 probeOut[]; };\n"
              "void main() {\n"
              "    uint i = gl_GlobalInvocationID.x;\n"
              "    if (i >= uint(probeIn.length())) return;\n"
              "    evalPrepare();\n"
              "    vec3 p = probeIn[i].xyz;\n"
              "    probeOut[8u * i] = evalMap(p);\n"
              "    probeOut[8u * i + 1u] = evalMapGround(p);\n"
              "    probeOut[8u * i + 2u] = evalMapObjects(p);\n"
              "    probeOut[8u * i + 3u] = ev_bound;\n"
              "    probeOut[8u * i + 4u] = ev_lipschitz;\n"
              "    probeOut[8u * i + 5u] = ev_groundBlend;\n"
              "    probeOut[8u * i + 6u] = ev_boxMin;\n"
              "    probeOut[8u * i + 7u] = ev_boxMax;\n"
              "}\n";
    s.hash = HashBytes(s.text);
    *out = std::move(s);
    return true;
}

}  // namespace sdfvj
