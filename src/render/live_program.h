// LiveProgram: the program on screen, kept current while files change and effects switch.
//
//   LiveProgram live;
//   live.Request(key);                       // a variant: scene + effects + path
//   each frame: live.Update(watcher.Poll()); if (live.Current()) draw(*live.Current(), live.Scene());
//
// Compiles to the side and swaps only on success: a broken save keeps the last good program on
// screen and Error() says "shaders/scenes/midi.glsl:42: ..." until the file is fixed. A save
// that leaves the assembled source unchanged (same content hash) compiles nothing. A change to
// an #included file rebuilds every variant that includes it. Variants are cached by VariantKey.
// A build first looks in the on-disk program cache (program_cache.h): a source compiled in an
// earlier run is on screen at once. Tiered (by default where the driver takes the quick tier's
// hint, NVIDIA): a quick tier (QuickTierText) is compiled first and goes on screen, the optimized
// program compiles behind it and replaces it when ready; the image is the same.
// On NVIDIA builds go to a compile process (compile_process.h) by default: the driver serializes
// compiles process-wide, so only another process keeps the render thread free.
// Render thread only (GL).
#pragma once
#include <algorithm>
#include <cstdint>
#include <future>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "render/render.h"

namespace sdfvj {

// An on/off environment switch: NAME=1|on gives true, NAME=0|off false, anything else `fallback`.
bool EnvSwitch(const char* name, bool fallback);
// An integer environment setting: NAME's value when it is a whole number in [lo, hi], else `fallback`.
int EnvInt(const char* name, int fallback, int lo, int hi);

// One program LiveProgram builds behind the show for the variant on screen, at the lowest
// priority (the literal tier, the evaluator tier): the source it wants, the build in flight, the
// program built, and the sources the driver refused (not tried again).
struct BackgroundTier {
    ShaderSource want;                  // the latest source assembled for wantKey
    VariantKey wantKey;
    PendingProgram pending;
    VariantKey pendingKey;
    uint64_t pendingHash = 0;
    std::shared_ptr<Program> program;   // built from `hash`'s source, for `key`
    VariantKey key;
    uint64_t hash = 0;
    std::vector<uint64_t> failed;
    double buildMs = 0.0, primeMs = 0.0;

    // The program is built for what `onScreen` wants now.
    bool Ready(const VariantKey& onScreen) const { return program && key == onScreen && hash == want.hash && want.hash != 0; }
    // True when `want` is for `onScreen` and still to build: not built, in flight or refused before.
    bool ToBuild(const VariantKey& onScreen) const;
    // Begins building `want` (from the program cache when it has it).
    void Start(const VariantKey& onScreen, CompileProcess* process);
    // The build in flight, finished (blocks until it is); null when the driver refused it (`log`
    // says why; its source is not tried again).
    std::shared_ptr<Program> Finish(std::string* log);
    // `built` (from Finish) becomes the program; primeMs: its first use, timed by the caller.
    void Keep(std::shared_ptr<Program> built, double primeMs);
};

class LiveProgram {
public:
    // Switches to a variant: from the cache at once, else compiled asynchronously while the
    // previous program keeps rendering. The scene header is re-read.
    void Request(const VariantKey& key);
    // Feeds changed file paths (absolute) and finishes a pending compile when it is ready.
    // Returns true when the program on screen changed this call.
    bool Update(const std::vector<std::string>& changedFiles);
    // Blocks until no compile is pending (offline renders, tests).
    void Wait();

    const Program* Current() const { return current_.get(); }
    // The program on screen, shared: a crossfade keeps the old scene's program alive while it
    // fades out, whatever the cache does meanwhile.
    std::shared_ptr<const Program> CurrentShared() const { return current_; }
    const SceneInfo& Scene() const { return scene_; }
    const VariantKey& Key() const { return key_; }
    const std::string& Error() const { return error_; }   // empty when the last build succeeded
    int CompilesStarted() const { return compiles_; }
    // Variants kept compiled besides the one on screen, least recently used dropped first (a
    // show that toggles effects for hours reaches many variants; each holds the driver's code,
    // tens of MB on llvmpipe). Default kDefaultCacheLimit; at least 1.
    static constexpr size_t kDefaultCacheLimit = 12;
    void SetCacheLimit(size_t n) { cacheLimit_ = std::max<size_t>(n, 1); }
    size_t CachedVariants() const { return cache_.size(); }
    bool IsCached(const VariantKey& key) const { return cache_.count(key) != 0; }
    bool Pending() const { return pending_.Active() || quick_.Active(); }
    // Tiered compiles on or off (default: TieredCompileDefault()). Takes effect at the next build.
    void SetTiered(bool on) { tiered_ = on ? 1 : 0; }
    bool Tiered() const { return tiered_ == 1 || (tiered_ < 0 && TieredCompileDefault()); }
    // True where the driver honours `#pragma optionNV` hints (GL_VENDOR contains NVIDIA),
    // unless SDFVJ_TIERED=0. Needs a current context.
    static bool TieredCompileDefault();
    // Builds go to this compile process (nullptr: none, in-process). Default: ProcessCompileDefault().
    void SetCompileProcess(CompileProcess* process) { process_ = process; processSet_ = true; }
    // True on NVIDIA (GL_VENDOR), unless SDFVJ_COMPILE_PROCESS=0; SDFVJ_COMPILE_PROCESS=1 turns it on
    // anywhere. Needs a current context.
    static bool ProcessCompileDefault();
    // Whether binaries (the compile process's, the program cache's) should be loaded and used once
    // on a loader thread before they go on screen (PendingProgram::SetLoader): where the compile
    // process is used: only with SDFVJ_LOADER=1 (measured on the H200: NVIDIA finishes a loaded
    // program per context, so the loader's use does not spare the render context's; off by default).
    // On llvmpipe on by default, for the program cache's loads (SDFVJ_LOADER=0: off).
    static bool LoaderDefault();
    // The literal tier (off by default; `live` and `bench reload` turn it on): once the variant on
    // screen is built, the same scene with its float literals as uniforms (literals.h) is built
    // behind it, at the lowest priority, and used once; a later save that changes only those numbers
    // puts it on screen in that Update() with the new values (no compile: the next frame shows
    // them), while the optimized program of the save compiles behind it and replaces it as usual.
    // Its build starts 2 s after the last program landed. SDFVJ_LITERAL_TIER=0|1 overrides `on`.
    void SetLiteralTier(bool on);
    bool LiteralTier() const { return literalTier_; }
    // The literal tier of the variant on screen is built (tests, the bench wait for it).
    bool LiteralTierReady() const { return lifted_.Ready(key_); }
    // Blocks until the literal tier of the variant on screen is built (false: it cannot be).
    bool WaitLiteralTier();
    // Variants the performer can reach next (the effect pads' toggles, the presets' variants),
    // built ahead at the lowest priority (one at a time, when nothing else compiles) into the
    // variant cache, so that asking for one later shows it at once. Replaces the queue; keeps
    // room in the cache (at most its limit - 2 variants besides the one on screen); a saved file
    // drops what it touched, as for any cached variant.
    void Prefetch(const std::vector<VariantKey>& keys);
    size_t PrefetchQueued() const { return prefetch_.size() + (prefetchPending_.Active() ? 1 : 0); }
    int Prefetched() const { return prefetched_; }   // variants built ahead so far
    // Each variant built ahead is also used once on the render context when it arrives (as the
    // literal tier is): NVIDIA finishes a program at its first use on each context, so that wait
    // falls when it is built rather than on the frame that shows it. Not on llvmpipe.
    void SetPrimePrefetched(bool on) { primePrefetched_ = on; }
    double PrefetchPrimeMs() const { return prefetchPrimeMs_; }   // the longest such use so far
    int LiteralSwaps() const { return literalSwaps_; }   // saves put on screen by the literal tier
    // The literal tier's last build: its compile (ProgramOrigin::buildMs) and its one use on the
    // render thread (PrimeProgram, glFinish): on NVIDIA a frame that long after a structural save.
    double LiteralBuildMs() const { return lifted_.buildMs; }
    double LiteralPrimeMs() const { return lifted_.primeMs; }
    // The evaluator tier (live_program_eval.cpp; off by default: `bench reload --modes MODE-evaluator`
    // turns it on; SDFVJ_EVALUATOR_TIER=0|1 overrides, also in `live`): once the variant on screen is
    // built, its scene's evaluator program (shader/eval_program.h) is built behind it at the lowest
    // priority and used once; a later save whose text outside the hooks' bodies is the same is
    // translated on the CPU (shader/evaluator.h) and drawn by that program in the same Update(),
    // no build; the save's optimized program compiles behind it and replaces it.
    void SetEvaluatorTier(bool on);
    bool EvaluatorTier() const { return evalTier_; }
    bool EvaluatorTierReady() const;
    bool WaitEvaluatorTier();   // blocks until the variant on screen's evaluator program is built
    int EvaluatorSwaps() const { return evalSwaps_; }   // saves put on screen by the evaluator tier
    double EvaluatorBuildMs() const { return eval_.buildMs; }
    double EvaluatorPrimeMs() const { return eval_.primeMs; }
    double EvaluatorTranslateMs() const { return evalTranslateMs_; }   // the last save's translation
    const std::string& EvaluatorError() const { return evalError_; }   // why the last save could not be evaluated

private:
    // Programs are shared between the cache and the screen: evicting a cache entry (its files
    // changed) never frees the program still on screen while its replacement compiles.
    struct Cached {
        std::shared_ptr<const Program> program;
        SceneInfo scene;
        uint64_t lastUsed = 0;   // useClock_ when it was last asked for or built
    };
    void Rebuild();   // reassemble key_ and compile when the source hash differs
    void Finish();
    void FinishQuick();
    void CancelBuilds();
    void Evict();     // drop least recently used variants down to cacheLimit_ (never key_)
    void Trim();      // hand the heap a compile freed back to the system (glibc malloc_trim; SDFVJ_MALLOC_TRIM=0: off)
    void WantLifted(const SceneInfo& scene);   // assemble key_'s lifted source into lifted_.want
    bool BackgroundIdle(bool force) const;     // a background tier may start building (and, unless forced, kLiteralDelayMs after the last change)
    void StartLifted(bool force = false);      // build lifted_.want when BackgroundIdle(force)
    void FinishLifted();
    void StartPrefetch();
    void WantEvaluator(const SceneInfo& scene);   // assemble key_'s evaluator program into eval_.want
    void StartEvaluator(bool force = false);
    void FinishEvaluator();
    bool TryEvaluator(const SceneInfo& scene);    // a save drawn by the built evaluator program
    bool UploadEvaluatorCode(const SceneInfo& scene, const VariantKey& key, Program* program);
    void RequeuePrefetch();   // a prefetch in flight is cancelled and asked for again first
    void FinishPrefetch();
    CompileProcess* Process() const;

    VariantKey key_;
    SceneInfo scene_;                       // header of the program on screen
    SceneInfo pendingScene_;
    VariantKey pendingKey_;
    std::shared_ptr<const Program> current_;
    std::map<VariantKey, Cached> cache_;
    PendingProgram pending_;               // the optimized program (or one from the disk cache)
    PendingProgram quick_;                 // its quick tier, while tiered
    CompileProcess* process_ = nullptr;
    bool processSet_ = false;              // false: ProcessCompileDefault() picks the shared process
    int tiered_ = -1;                      // -1: TieredCompileDefault(), asked when a build starts (GL current)
    uint64_t pendingHash_ = 0;
    std::string error_;
    int compiles_ = 0;
    size_t cacheLimit_ = kDefaultCacheLimit;
    uint64_t useClock_ = 0;
    // The literal tier: one program, for the variant on screen (built from the skeleton of its source).
    bool literalTier_ = false;
    BackgroundTier lifted_;
    int literalSwaps_ = 0;
    static constexpr double kLiteralDelayMs = 2000.0;
    double settledAt_ = 0.0;               // steady ms of the last change on screen or build in flight
    // The evaluator tier: one program, for the variant on screen's scene shape.
    bool evalTier_ = false;
    BackgroundTier eval_;
    int evalSwaps_ = 0;
    double evalTranslateMs_ = 0.0;
    std::string evalError_;
    std::future<void> evalPrepared_;   // glslang set up ahead (SetEvaluatorTier)
    // Variants built ahead (Prefetch).
    std::vector<VariantKey> prefetch_;     // still to build, first first
    PendingProgram prefetchPending_;
    VariantKey prefetchKey_;
    SceneInfo prefetchScene_;
    int prefetched_ = 0;
    bool primePrefetched_ = false;
    double prefetchPrimeMs_ = 0.0;
};

// For reload benchmarks and tests, the edit a live coder makes: `sceneText` with its first float
// literal inside a function body (after the JSON header, outside comments) written as
// `1.5f` -> `(1.5f+0.000123f)`, so every save is a program no driver cache has seen (an unused
// constant or a comment would be optimized away before the caches' keys are taken). Returns the
// text unchanged and `found` false when the scene has no such literal.
std::string NudgeFirstConstant(const std::string& sceneText, double delta, bool* found);
// The edit that only retunes a number: the first literal LiftLiterals lifts (literals.h), written
// as `value` ("%.9gf"); the skeleton stays the same. Unchanged text and `found` false without one.
std::string RetuneFirstConstant(const std::string& sceneText, double value, bool* found);

}  // namespace sdfvj
