#include "render/live_program.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <charconv>
#include <cstring>
#include <filesystem>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "render/compile_process.h"
#include "render/compile_worker.h"
#include "shader/literals.h"

namespace fs = std::filesystem;

namespace sdfvj {

bool EnvSwitch(const char* name, bool fallback) {
    const char* env = std::getenv(name);
    if (env && (std::strcmp(env, "0") == 0 || std::strcmp(env, "off") == 0)) return false;
    if (env && (std::strcmp(env, "1") == 0 || std::strcmp(env, "on") == 0)) return true;
    return fallback;
}

int EnvInt(const char* name, int fallback, int lo, int hi) {
    const char* e = std::getenv(name);
    if (!e) return fallback;
    const char* end = e + std::strlen(e);
    int v = 0;
    if (std::from_chars(e, end, v).ptr != end || v < lo || v > hi) return fallback;
    return v;
}

namespace {
bool VendorIsNvidia() {
    const GLubyte* vendor = glGetString(GL_VENDOR);
    return vendor && std::strstr((const char*)vendor, "NVIDIA") != nullptr;
}
}  // namespace

bool LiveProgram::TieredCompileDefault() { return EnvSwitch("SDFVJ_TIERED", VendorIsNvidia()); }

bool LiveProgram::ProcessCompileDefault() { return EnvSwitch("SDFVJ_COMPILE_PROCESS", VendorIsNvidia()); }

bool LiveProgram::LoaderDefault() {
    // On a GPU off unless asked for: on the H200 the driver finishes a loaded program once per
    // CONTEXT (a use on the loader's shared context does not spare the render context's first use,
    // and the loader's own finishing delays save -> screen by 120-570 ms): docs/performance.md.
    // On llvmpipe on: a program the program cache serves (an effect pad's variant built in an
    // earlier run) was JITted by the show's first draw (320-580 ms, a frozen frame in the soak with
    // Mesa's disk cache cold); the loader's draw puts that code in Mesa's disk cache, where the
    // show's first draw reads it (as it does for the compile thread's builds).
    return EnvSwitch("SDFVJ_LOADER", IsSoftwareRenderer());
}

void LiveProgram::SetLiteralTier(bool on) { literalTier_ = EnvSwitch("SDFVJ_LITERAL_TIER", on); }

namespace {
double SteadyMs() {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
}  // namespace

CompileProcess* LiveProgram::Process() const {
    return processSet_ ? process_ : ProcessCompileDefault() ? SharedCompileProcess() : nullptr;
}

void LiveProgram::WantLifted(const SceneInfo& scene) {
    if (!literalTier_) return;
    ShaderSource lifted;
    std::string error;
    if (!AssembleProgram(scene, key_, &lifted, &error, true)) return;
    lifted_.want = std::move(lifted);
    lifted_.wantKey = key_;
}

bool BackgroundTier::ToBuild(const VariantKey& onScreen) const {
    return !pending.Active() && wantKey == onScreen && want.hash != 0 && !Ready(onScreen) &&
           std::find(failed.begin(), failed.end(), want.hash) == failed.end();
}

void BackgroundTier::Start(const VariantKey& onScreen, CompileProcess* process) {
    pendingKey = onScreen;
    pendingHash = want.hash;
    pending.SetProcess(process);
    if (!pending.BeginFromCache(want, onScreen.path)) pending.Begin(want, onScreen.path);
}

std::shared_ptr<Program> BackgroundTier::Finish(std::string* log) {
    auto built = std::make_shared<Program>();
    if (pending.Finish(built.get(), log)) return built;
    failed.push_back(pendingHash);
    return nullptr;
}

void BackgroundTier::Keep(std::shared_ptr<Program> built, double prime) {
    primeMs = prime;
    buildMs = built->Origin().buildMs;
    program = std::move(built);
    key = pendingKey;
    hash = pendingHash;
}

// Nothing else compiles, the variant on screen is good, and (unless forced) kLiteralDelayMs have
// passed since the last change: the show gets its frames (and the CPU, on llvmpipe) first.
bool LiveProgram::BackgroundIdle(bool force) const {
    return !lifted_.pending.Active() && !eval_.pending.Active() && !pending_.Active() && !quick_.Active() && current_ &&
           error_.empty() && (force || SteadyMs() - settledAt_ >= kLiteralDelayMs);
}

void LiveProgram::StartLifted(bool force) {
    if (literalTier_ && BackgroundIdle(force) && lifted_.ToBuild(key_)) lifted_.Start(key_, Process());
}

void LiveProgram::FinishLifted() {
    std::string log;
    // null: a literal in a place that wants a constant expression, say: saves compile as before.
    std::shared_ptr<Program> program = lifted_.Finish(&log);
    if (program) {
        program->MarkLiteralTier();
        // Used once here, now, so the driver's lazy finishing at a program's first draw (NVIDIA) falls
        // between saves rather than on the frame that shows a retuned save.
        const double primeStart = SteadyMs();
        // Not on llvmpipe: with Mesa's disk cache on its first draw is quick anyway (11-20 ms at
        // 320x180), and with the cache off this use would JIT on the render thread (690 ms) after
        // every structural save instead of at the first retune. (With the cache on, the use cost
        // 711-943 ms: the 1x1 target's draw state is another llvmpipe variant.)
        if (!IsSoftwareRenderer()) PrimeProgram(program->Id(), lifted_.pendingKey.path, false);
        lifted_.Keep(std::move(program), SteadyMs() - primeStart);
    }
    Trim();
}

void LiveProgram::Prefetch(const std::vector<VariantKey>& keys) {
    prefetch_.clear();
    for (const VariantKey& k : keys)
        if (k != key_ && !cache_.count(k) && std::find(prefetch_.begin(), prefetch_.end(), k) == prefetch_.end())
            prefetch_.push_back(k);
}

void LiveProgram::RequeuePrefetch() {
    if (!prefetchPending_.Active()) return;
    prefetch_.insert(prefetch_.begin(), prefetchKey_);
    prefetchPending_.Cancel();
}

void LiveProgram::StartPrefetch() {
    while (!prefetch_.empty() && !prefetchPending_.Active() && !pending_.Active() && !quick_.Active() &&
           !lifted_.pending.Active() && !eval_.pending.Active() && cache_.size() + 2 <= cacheLimit_) {
        const VariantKey k = prefetch_.front();
        prefetch_.erase(prefetch_.begin());
        if (k == key_ || cache_.count(k)) continue;
        SceneInfo scene;
        ShaderSource src;
        std::string error;
        if (!LoadScene(k.scenePath, &scene, &error) || !AssembleProgram(scene, k, &src, &error)) continue;   // asked for, it reports
        prefetchKey_ = k;
        prefetchScene_ = scene;
        prefetchPending_.SetProcess(Process());
        if (!prefetchPending_.BeginFromCache(src, k.path)) prefetchPending_.Begin(src, k.path);
    }
}

void LiveProgram::FinishPrefetch() {
    auto program = std::make_unique<Program>();
    std::string log;
    const bool ok = prefetchPending_.Finish(program.get(), &log);   // a variant that fails reports when asked for
    if (ok && prefetchKey_ != key_ && !cache_.count(prefetchKey_)) {
        if (primePrefetched_ && !IsSoftwareRenderer()) {
            const auto primeStart = std::chrono::steady_clock::now();
            PrimeProgram(program->Id(), prefetchKey_.path, false);
            prefetchPrimeMs_ = std::max(prefetchPrimeMs_, std::chrono::duration<double, std::milli>(
                                                             std::chrono::steady_clock::now() - primeStart).count());
        }
        Cached& slot = cache_[prefetchKey_];
        slot.program = std::move(program);
        slot.scene = prefetchScene_;
        slot.lastUsed = 0;   // never asked for: the first to go when the cache is full
        ++prefetched_;
        Evict();
    }
    Trim();
}

bool LiveProgram::WaitLiteralTier() {
    if (!literalTier_) return false;
    Wait();
    StartLifted(true);
    if (lifted_.pending.Active()) FinishLifted();
    return LiteralTierReady();
}

void LiveProgram::CancelBuilds() {
    pending_.Cancel();
    quick_.Cancel();
}

void LiveProgram::Request(const VariantKey& key) {
    key_ = key;
    auto it = cache_.find(key);
    if (it != cache_.end()) {
        CancelBuilds();
        it->second.lastUsed = ++useClock_;
        current_ = it->second.program;
        scene_ = it->second.scene;
        error_.clear();
        if (literalTier_ && lifted_.wantKey != key) {
            lifted_.pending.Cancel();
            WantLifted(scene_);   // the cached variant's header: current, a save evicts it
        }
        if (evalTier_ && eval_.wantKey != key) {
            eval_.pending.Cancel();
            WantEvaluator(scene_);
        }
        return;
    }
    Rebuild();
}

void LiveProgram::Rebuild() {
    SceneInfo scene;
    std::string error;
    if (!LoadScene(key_.scenePath, &scene, &error)) {
        error_ = error + " — still showing the previous shader";
        return;
    }
    ShaderSource src;
    if (!AssembleProgram(scene, key_, &src, &error)) {
        error_ = error + " — still showing the previous shader";
        return;
    }
    WantLifted(scene);
    auto it = cache_.find(key_);
    if (it != cache_.end() && it->second.program->Source().hash == src.hash) {
        // A no-op save, or a broken save undone: the cached program is the right one again.
        CancelBuilds();
        it->second.lastUsed = ++useClock_;
        current_ = it->second.program;
        scene_ = it->second.scene;
        error_.clear();
        return;
    }
    if (pending_.Active() && pendingKey_ == key_ && pendingHash_ == src.hash) return;
    pendingScene_ = scene;
    pendingKey_ = key_;
    pendingHash_ = src.hash;
    // Only numbers changed: the literal tier shows them now, the optimized program follows.
    const bool retuned = LiteralTierReady();
    if (retuned) {
        lifted_.program->SetLiterals(lifted_.want.literals);
        current_ = lifted_.program;
        scene_ = scene;
        error_.clear();
        ++literalSwaps_;
    }
    // A structural save the evaluator program can draw: on screen now, no build (live_program_eval.cpp).
    const bool evaluated = !retuned && TryEvaluator(scene);
    if (!evaluated) WantEvaluator(scene);
    lifted_.pending.Cancel();   // a real build goes first
    eval_.pending.Cancel();
    RequeuePrefetch();
    if (pending_.BeginFromCache(src, key_.path)) {
        quick_.Cancel();
        return;   // compiled in an earlier run: Update() puts it on screen
    }
    CompileProcess* process = Process();
    quick_.SetProcess(process);
    pending_.SetProcess(process);
    // The quick tier is queued first: on a compile worker (one job at a time) it must not wait
    // behind the optimized build. Not needed when the literal tier is on screen.
    if (Tiered() && !retuned && !evaluated) quick_.Begin(src, key_.path, BuildTier::Quick);
    else quick_.Cancel();
    pending_.Begin(src, key_.path);
    ++compiles_;
}

void LiveProgram::FinishQuick() {
    auto program = std::make_unique<Program>();
    std::string log;
    // A quick tier that fails says nothing: the optimized build of the same source reports.
    if (!quick_.Finish(program.get(), &log)) return;
    if (pendingKey_ != key_ || !pending_.Active()) return;
    current_ = std::move(program);   // on screen, not in cache_: the optimized program goes there
    scene_ = pendingScene_;
    error_.clear();
}

void LiveProgram::Finish() {
    quick_.Cancel();   // the optimized program is here: a quick tier still compiling is not needed
    auto program = std::make_unique<Program>();
    std::string log;
    if (!pending_.Finish(program.get(), &log)) {
        error_ = log;
        Trim();
        return;
    }
    error_.clear();
    Cached& slot = cache_[pendingKey_];
    slot.program = std::move(program);
    slot.scene = pendingScene_;
    slot.lastUsed = ++useClock_;
    if (pendingKey_ == key_) {
        current_ = slot.program;
        scene_ = slot.scene;
    }
    Evict();
    Trim();
}

void LiveProgram::Evict() {
    while (cache_.size() > cacheLimit_) {
        auto oldest = cache_.end();
        for (auto it = cache_.begin(); it != cache_.end(); ++it)
            if (it->first != key_ && (oldest == cache_.end() || it->second.lastUsed < oldest->second.lastUsed)) oldest = it;
        if (oldest == cache_.end()) return;
        cache_.erase(oldest);   // a program still on screen (current_) or fading out lives on in its shared_ptr
    }
}

void LiveProgram::Trim() {
#if defined(__GLIBC__)
    // A compile on llvmpipe (LLVM) or in the driver allocates and frees tens of MB; glibc keeps
    // freed pages of every arena mapped, so a show's RSS would climb with each compile. Measured
    // in scripts/soak.sh (docs/reliability.md). Where the compile thread trims after each of its
    // jobs (CompileWorker::SetTrimAfterJobs: the trim held the frame that put a program on screen
    // 8-22 ms on llvmpipe) not here.
    static const bool off = [] {
        const char* env = std::getenv("SDFVJ_MALLOC_TRIM");
        return env && std::strcmp(env, "0") == 0;
    }();
    if (off) return;
    if (CompileWorker* worker = PendingProgram::Worker() ? PendingProgram::Worker() : PendingProgram::Loader())
        worker->SetTrimAfterJobs(true);
    else
        malloc_trim(0);
#endif
}

bool LiveProgram::Update(const std::vector<std::string>& changedFiles) {
    const Program* before = current_.get();
    const int swapsBefore = literalSwaps_;
    const int evalSwapsBefore = evalSwaps_;
    if (!changedFiles.empty()) {
        RequeuePrefetch();   // assembled before the save: built again from the new files
        bool affectsCurrent = false;
        for (const std::string& changed : changedFiles) {
            std::string canon = fs::weakly_canonical(changed).string();
            auto uses = [&](const Program& p) {
                const auto& files = p.Source().files;
                return std::find(files.begin(), files.end(), canon) != files.end();
            };
            // Owners of the changed file other than the variant asked for are dropped from the
            // cache; they rebuild when requested again. The program on screen may be one of them
            // (an effect toggle is still compiling): current_ keeps it alive until replaced.
            for (auto it = cache_.begin(); it != cache_.end();) {
                if (uses(*it->second.program) && it->first != key_) it = cache_.erase(it);
                else ++it;
            }
            if ((current_ && uses(*current_)) || canon == fs::weakly_canonical(key_.scenePath).string() ||
                (pending_.Active() && std::find(pending_.Source().files.begin(), pending_.Source().files.end(), canon) !=
                                          pending_.Source().files.end()) ||
                !error_.empty())   // after a failed build any save may be the fix
                affectsCurrent = true;
        }
        if (affectsCurrent) Rebuild();
    }
    if (quick_.Active() && quick_.Ready()) FinishQuick();
    if (pending_.Active() && pending_.Ready()) Finish();
    if (current_.get() != before || pending_.Active() || quick_.Active()) settledAt_ = SteadyMs();
    if (lifted_.pending.Active()) {
        if (lifted_.pending.Ready()) FinishLifted();
    } else {
        StartLifted();
    }
    if (eval_.pending.Active()) {
        if (eval_.pending.Ready()) FinishEvaluator();
    } else if (!lifted_.pending.Active()) {
        StartEvaluator();
    }
    if (prefetchPending_.Active()) {
        if (prefetchPending_.Ready()) FinishPrefetch();
    } else {
        StartPrefetch();
    }
    return current_.get() != before || literalSwaps_ != swapsBefore || evalSwaps_ != evalSwapsBefore;
}

void LiveProgram::Wait() {
    if (pending_.Active()) Finish();
    quick_.Cancel();
}

std::string NudgeFirstConstant(const std::string& text, double delta, bool* found) {
    *found = false;
    const size_t header = text.find("*/");
    size_t i = text.find('{', header == std::string::npos ? 0 : header + 2);
    auto isDigit = [&](size_t k) { return k < text.size() && text[k] >= '0' && text[k] <= '9'; };
    auto isWord = [&](size_t k) {
        return k < text.size() && (std::isalnum((unsigned char)text[k]) || text[k] == '_');
    };
    for (; i != std::string::npos && i < text.size(); ++i) {
        if (text.compare(i, 2, "//") == 0) {   // skip line and block comments
            i = text.find('\n', i);
            if (i == std::string::npos) break;
            continue;
        }
        if (text.compare(i, 2, "/*") == 0) {
            i = text.find("*/", i);
            if (i == std::string::npos) break;
            ++i;
            continue;
        }
        if (!isDigit(i) || (i > 0 && (isWord(i - 1) || text[i - 1] == '.'))) continue;
        size_t k = i;
        while (isDigit(k)) ++k;
        if (k >= text.size() || text[k] != '.' || !isDigit(k + 1)) continue;
        ++k;
        while (isDigit(k)) ++k;
        if (k >= text.size() || text[k] != 'f' || isWord(k + 1)) continue;
        char nudge[40];
        std::snprintf(nudge, sizeof nudge, "+%.9ff)", delta);
        *found = true;
        return text.substr(0, i) + "(" + text.substr(i, k + 1 - i) + nudge + text.substr(k + 1);
    }
    return text;
}

std::string RetuneFirstConstant(const std::string& text, double value, bool* found) {
    size_t begin = 0, end = 0;
    *found = FindFirstLiftable(text, &begin, &end);
    if (!*found) return text;
    char number[40];
    std::snprintf(number, sizeof number, "%.9gf", value);
    std::string n = number;
    if (n.find_first_of(".e") == std::string::npos) n.insert(n.size() - 1, ".0");   // still a float literal
    return text.substr(0, begin) + n + text.substr(end);
}

}  // namespace sdfvj
