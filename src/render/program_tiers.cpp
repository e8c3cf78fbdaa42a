#include <epoxy/gl.h>

#include "render/live_program.h"
#include "render/render.h"
#include "scene/scene.h"

#include <algorithm>
#include <cstdlib>

// Program's tiers beside its build (program.cpp): the quick tier's text and the evaluator tier's
// buffers (the scene's code and constants the evaluator program runs; shader/eval_program.h).
namespace sdfvj {

void Program::SetEvaluatorCode(const std::vector<std::array<uint32_t, 4>>& packed, const std::vector<std::array<float, 4>>& constants) {
    if (!evalCode_) glCreateBuffers(1, &evalCode_);
    if (!evalConst_) glCreateBuffers(1, &evalConst_);
    // glNamedBufferData each time: the driver orphans the old store a frame in flight still reads.
    // An empty list still gets one element (a zero-sized buffer cannot be bound).
    const std::array<uint32_t, 4> noCode{};
    const std::array<float, 4> noConst{};
    glNamedBufferData(evalCode_, (GLsizeiptr)(std::max<size_t>(packed.size(), 1) * sizeof noCode), packed.empty() ? noCode.data() : packed[0].data(),
                      GL_STATIC_DRAW);
    glNamedBufferData(evalConst_, (GLsizeiptr)(std::max<size_t>(constants.size(), 1) * sizeof noConst),
                      constants.empty() ? noConst.data() : constants[0].data(), GL_STATIC_DRAW);
}

void Program::BindEvaluator() const {
    if (!evalCode_) return;
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kEvalCodeBinding, evalCode_);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kEvalConstBinding, evalConst_);
}

// The quick tier's form (issue 12, docs/performance.md "Session 40"): the one-site renderer
// (render/one_site.glsl: one call site of the scene's field) with NVIDIA's `unroll none`; before,
// the usual renderer with `inline none`. SDFVJ_QUICK_ONE_SITE=0|1 picks the renderer.
bool QuickTierOneSite() {
    static const bool oneSite = EnvSwitch("SDFVJ_QUICK_ONE_SITE", true);
    return oneSite;
}

// NVIDIA's compiler hints for the quick tier: `unroll none` for the one-site renderer, `inline none`
// for the usual one, or SDFVJ_QUICK_OPTIONS (words joined by '-', hints by ':',
// "inline-none:unroll-none"; "none": no hint), for measuring others (bench reload --modes
// render-process+SDFVJ_QUICK_OPTIONS=...). A value with anything but letters, '-' and ':' is ignored.
std::string QuickTierPragmas() {
    const char* env = std::getenv("SDFVJ_QUICK_OPTIONS");
    std::string options = env ? env : "";
    if (options == "none") return "";
    const bool valid = !options.empty() && options.size() < 200 &&
                       options.find_first_not_of("abcdefghijklmnopqrstuvwxyz-:") == std::string::npos;
    if (!valid) options = QuickTierOneSite() ? "unroll-none" : "inline-none";
    std::string pragmas;
    size_t at = 0;
    while (at <= options.size()) {
        size_t end = options.find(':', at);
        if (end == std::string::npos) end = options.size();
        std::string hint = options.substr(at, end - at);
        for (char& c : hint)
            if (c == '-') c = ' ';
        if (!hint.empty()) pragmas += "#pragma optionNV(" + hint + ")\n";
        at = end + 1;
    }
    return pragmas;
}

// QUICK_TIER 1 in the quick tier's text: a scene may pick code that builds sooner there, the same
// field (character.glsl: no part skip, a division per capsule: NVIDIA's link 0.85x, session 43).
// SDFVJ_QUICK_SCENE=0: not defined, for measuring.
bool QuickTierSceneDefine() {
    static const bool on = EnvSwitch("SDFVJ_QUICK_SCENE", true);
    return on;
}

std::string QuickTierText(const std::string& text) {
    const size_t eol = text.find('\n');
    if (text.rfind("#version", 0) != 0 || eol == std::string::npos) return text;
    // No cone pre-pass either (main_comp.glsl): its march is one more map() call site to compile.
    return text.substr(0, eol + 1) + QuickTierPragmas() + "#define CONE_PREPASS 0\n" + (QuickTierOneSite() ? "#define ONE_SITE 1\n" : "") +
           (QuickTierSceneDefine() ? "#define QUICK_TIER 1\n" : "") + text.substr(eol + 1);
}

}  // namespace sdfvj
