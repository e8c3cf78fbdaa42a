// LiveProgram's evaluator tier (issue 12): a structural save drawn with no driver build.
//
// Once the variant on screen is built, the scene's *evaluator program* is built behind it at the
// lowest priority (shader/eval_program.h: the renderer with the scene's hook functions calling a
// register machine, render/eval.glsl). Its source depends on the scene's text outside the hooks'
// bodies only, so a later save that edits what the hooks (and the helpers they call) compute
// assembles the same evaluator program: the save is translated on the CPU (shader/evaluator.h:
// glslang, then the machine's code), the code is uploaded to the evaluator program, and that
// program goes on screen in the same Update(). The optimized program of the save compiles behind
// it as before and replaces it. A save the translation refuses (a construct the machine lacks, a
// changed header or top level) compiles as before, quick tier first.
#include "render/live_program.h"

#include <chrono>
#include <future>

#include "render/compile_worker.h"
#include "shader/eval_program.h"
#include "shader/evaluator.h"

namespace sdfvj {

namespace {
double NowMs() {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
}  // namespace

void LiveProgram::SetEvaluatorTier(bool on) {
    evalTier_ = EnvSwitch("SDFVJ_EVALUATOR_TIER", on);
    // glslang's first compile in a process sets up its tables (~200 ms): on a thread of its own now,
    // not in the reload step of the first save (Translate waits for it under its lock).
    if (evalTier_ && !evalPrepared_.valid()) evalPrepared_ = std::async(std::launch::async, [] { eval::PrepareTranslator(); });
}

bool LiveProgram::EvaluatorTierReady() const { return eval_.Ready(key_); }

void LiveProgram::WantEvaluator(const SceneInfo& scene) {
    if (!evalTier_) return;
    ShaderSource src;
    std::string error;
    eval_.wantKey = key_;
    // On llvmpipe the machine's loop is unrolled (its 65,535 loop iterations a shader, eval_program.h).
    if (!AssembleEvaluatorProgram(scene, key_, &src, &error, IsSoftwareRenderer() ? kEvaluatorUnrollSoftware : 1)) {
        eval_.want = ShaderSource{};   // this scene's top level cannot be stubbed: saves compile as before
        evalError_ = error;
        return;
    }
    eval_.want = std::move(src);
}

void LiveProgram::StartEvaluator(bool force) {
    if (evalTier_ && current_ && eval_.wantKey != key_) WantEvaluator(scene_);   // turned on after the variant was asked for
    if (evalTier_ && BackgroundIdle(force) && eval_.ToBuild(key_)) eval_.Start(key_, Process());
}

// Translates `scene` (as saved now) into `program`'s code. false: the machine cannot run it.
bool LiveProgram::UploadEvaluatorCode(const SceneInfo& scene, const VariantKey& key, Program* program) {
    const double t0 = NowMs();
    std::string unit, error;
    std::vector<std::string> slots;
    eval::Program code;
    if (!eval::AssembleEvaluatorUnit(scene, key, &unit, &slots, &error) || !eval::Translate(unit, slots, &code, &error)) {
        evalError_ = error;
        return false;
    }
    program->SetEvaluatorCode(eval::PackCode(code), code.constants);
    evalTranslateMs_ = NowMs() - t0;
    evalError_.clear();
    return true;
}

void LiveProgram::FinishEvaluator() {
    std::string log;
    std::shared_ptr<Program> program = eval_.Finish(&log);
    if (program && !UploadEvaluatorCode(scene_, eval_.pendingKey, program.get())) {
        eval_.failed.push_back(eval_.pendingHash);
        program.reset();
    } else if (!program && evalError_.empty()) {
        evalError_ = log;
    }
    if (program) {
        program->MarkEvaluatorTier();
        // Used once now (with the scene's code bound), so NVIDIA's finishing of a program at its first
        // draw falls between saves, not on the frame that shows one (as for the literal tier).
        const double t0 = NowMs();
        if (!IsSoftwareRenderer()) {
            program->BindEvaluator();
            PrimeProgram(program->Id(), eval_.pendingKey.path, false);
        }
        eval_.Keep(std::move(program), NowMs() - t0);
    }
    Trim();
}

bool LiveProgram::WaitEvaluatorTier() {
    if (!evalTier_) return false;
    Wait();
    StartEvaluator(true);
    if (eval_.pending.Active()) FinishEvaluator();
    return EvaluatorTierReady();
}

bool LiveProgram::TryEvaluator(const SceneInfo& scene) {
    if (!EvaluatorTierReady()) return false;
    const uint64_t built = eval_.hash;
    WantEvaluator(scene);   // the save's top level: the same evaluator program?
    if (eval_.want.hash != built) return false;
    if (!UploadEvaluatorCode(scene, key_, eval_.program.get())) return false;
    current_ = eval_.program;
    scene_ = scene;
    error_.clear();
    ++evalSwaps_;
    return true;
}

}  // namespace sdfvj
