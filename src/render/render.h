// Render module: GL programs for scene variants, drawing them into an offscreen texture on the
// fragment or compute path, reading pixels back, and a headless EGL context to do it without a
// display. Only the render thread may call anything here (GL has one current context per thread).
#pragma once
#include <cstdint>
#include <map>
#include <memory>
#include <array>
#include <string>
#include <vector>

#include "scene/scene.h"
#include "shader/shader.h"

namespace sdfvj {

// An OpenGL 4.5 core context with no window: EGL device platform, then surfaceless, then the
// default display. Never GLFW (its headless EGL failed on the GPU machines).
class HeadlessContext {
public:
    HeadlessContext() = default;
    ~HeadlessContext();
    HeadlessContext(const HeadlessContext&) = delete;
    HeadlessContext& operator=(const HeadlessContext&) = delete;
    // False with one readable line when no GL is available.
    bool Create(std::string* error);
    // A second context on the same display that shares programs with `main` (for a
    // CompileWorker). Created on the render thread; MakeCurrent() it on the worker.
    // share = false: a second context on the same display that shares no objects (for a
    // CompileWorker in binary hand-over mode).
    bool CreateShared(const HeadlessContext& main, std::string* error, bool share = true);
    bool MakeCurrent();
    // Makes no context current on the calling thread and frees EGL's state for it (a worker
    // thread calls this before it ends).
    void ReleaseCurrent();
    std::string Description() const { return description_; }  // "EGL device platform: llvmpipe (...)"
    // Whether this context's EGL display has an extension (EGL_KHR_fence_sync, say).
    bool HasEglExtension(const char* name) const;
private:
    void* display_ = nullptr;
    void* context_ = nullptr;
    bool shared_ = false;
    std::string description_;
};

// Raymarch quality knobs; all are uniforms, so changing them never recompiles.
struct Quality {
    int maxSteps = 128;
    float hitEps = 1e-3f;       // relative to distance travelled (t * eps), see render.glsl
    float maxDist = 50.0f;
    float stepFactor = 1.0f;    // further divided by the scene's Lipschitz bound in the shader
    float fixedStep = 0.05f;    // MARCH_FIXED step length
    int shadowSteps = 48;       // 48 keeps every scene within 0.1% of a 1024-step shadow (docs/accuracy.md)
    float shadowK = 8.0f;       // penumbra: higher is harder
    int aoSamples = 5;
    float normalEps = 1e-3f;
    // Compute path: a low-resolution pre-pass marches one cone per 8x8 tile and every primary ray
    // starts where its tile's cone met a surface (render/march.glsl coneStart; docs/performance.md).
    bool conePrepass = true;
};

// Everything a frame sets besides the program: clock, camera, light, quality, scene parameters.
struct FrameInputs {
    double time = 0.0;
    int frame = 0;
    float beat = 0.0f;          // phase 0..1 within the beat
    float bpm = 120.0f;
    Quality quality;
    std::vector<std::pair<std::string, float>> params;   // scene parameters by name (no u_ prefix)
    int effectsOff = 0;   // u_effectsOff: compiled-in effects switched off at run time (benchmark only)
    float orbitYaw = 0.0f, orbitPitch = 0.0f;   // radians around the scene's camera target (live's mouse orbit)
};

// The scene's camera position turned by `yaw` around the vertical through its target and by
// `pitch` up or down (kept short of the poles); the distance to the target is kept.
Vec3f OrbitCamera(const SceneInfo& scene, float yaw, float pitch);

// render.glsl cameraRay's basis for a camera at `pos` looking at `target` (uniforms.glsl
// CAMERA_UNIFORMS): forward, and the screen's right and up scaled to one pixel, so that the ray
// through fragCoord is normalize(forward + (x - w/2) dx + (y - h/2) dy); pixelAngle = 2 tan(fov/2) / h.
struct CameraBasis {
    Vec3f forward{}, dx{}, dy{};
    float pixelAngle = 0.0f;
};
CameraBasis MakeCameraBasis(const Vec3f& pos, const Vec3f& target, float fovDegrees, int height);

// The buffer of a scene's frame state (Program::FrameState, main_comp.glsl SCENE_STATE_FRAME):
// kSceneStateBytes, bound at kSceneStateBinding both as the storage block the setup writes and as
// the uniform block the frame reads.
unsigned CreateSceneStateBuffer();
void BindSceneStateBuffer(unsigned buffer);

// How a program came to be: a test or the bench reads it, the frame ignores it.
struct ProgramOrigin {
    bool fromCache = false;   // loaded from the on-disk program cache (program_cache.h): nothing compiled
    bool quickTier = false;   // the quickly built first tier of a tiered compile (an optimized one follows)
    bool literalTier = false; // the scene's literals as uniforms (LiveProgram's literal tier; quickTier too)
    bool evaluatorTier = false; // the scene's evaluator program (shader/eval_program.h; quickTier too)
    bool fromProcess = false; // compiled in the compile process, loaded here as its binary
    double buildMs = 0.0;     // wall time of its compile + link (+ the worker's priming draw), on whichever thread built it
    double beginCallMs = 0.0;   // time the render thread spent in PendingProgram::Begin (driver calls that block show here)
    double finishCallMs = 0.0;  // ... and in Finish, once Ready() (status queries, uniform lookup, cache store)
    bool usedBeforeHandOver = false;   // loaded and used once on the loader's context (PendingProgram::SetLoader)
    double loadMs = 0.0;               // ... that load and first use, on the loader's thread
};

// Which build of a source: the optimized program, or a quick first tier that goes on screen
// while the optimized one compiles (NVIDIA: QuickTierText, the one-site renderer with its hint).
enum class BuildTier { Optimized, Quick };

// The source of the quick tier: right after #version (lines before any #line directive, so error
// lines stay right) NVIDIA's hint, no cone pre-pass, and the one-site renderer (ONE_SITE 1,
// render/one_site.glsl: one call site of the scene's field, the same pixels) with `#pragma
// optionNV(unroll none)`; SDFVJ_QUICK_ONE_SITE=0: the usual renderer with `inline none`.
// Drivers other than NVIDIA ignore the hint (Mesa tiers only with SDFVJ_TIERED=1).
std::string QuickTierText(const std::string& text);
// Whether the quick tier is the one-site renderer (SDFVJ_QUICK_ONE_SITE, default on; read once).
bool QuickTierOneSite();

// A linked program and the uniforms it actually declares.
class Program {
public:
    Program() = default;
    ~Program();
    Program(const Program&) = delete;
    Program& operator=(const Program&) = delete;
    // Compiles and links; on failure returns false and `log` holds file:line messages.
    bool Build(const ShaderSource& src, RenderPath path, std::string* log);
    bool IsValid() const { return id_ != 0; }
    unsigned Id() const { return id_; }
    RenderPath Path() const { return path_; }
    // A compute program's work-group size (main_comp.glsl's WORKGROUP_X/Y; 8x8 unless a scene
    // defines them): FrameRenderer sizes its dispatches from it.
    int GroupX() const { return group_[0]; }
    int GroupY() const { return group_[1]; }
    // A compute program whose scene's setup runs once per frame (main_comp.glsl SCENE_STATE_FRAME):
    // FrameRenderer binds the state's buffer and has it filled before the frame.
    bool FrameState() const { return frameState_; }
    // A compute program that traces its bounce once per 2x2 pixels (quad_reflections.glsl QUAD_REFLECTIONS):
    // FrameRenderer dispatches the quads' pass, into an image of its own, before the frame.
    bool QuadReflections() const { return quadReflections_; }
    // ... and leaves the bounces no quad lends to a list (quad_reflections.glsl QUAD_REFLECTIONS_DEFER), which
    // FrameRenderer traces in a dispatch of their own after the frame.
    bool QuadDefer() const { return quadDefer_; }
    const ShaderSource& Source() const { return source_; }
    // Takes ownership of a linked GL program (PendingProgram::Finish uses this).
    void Adopt(unsigned id, RenderPath path, const ShaderSource& src, const ProgramOrigin& origin = {});
    const ProgramOrigin& Origin() const { return origin_; }
    bool FromCache() const { return origin_.fromCache; }
    bool QuickTier() const { return origin_.quickTier; }
    void MarkLiteralTier() { origin_.quickTier = origin_.literalTier = true; }
    void MarkEvaluatorTier() { origin_.quickTier = origin_.evaluatorTier = true; }
    // An evaluator program's code (shader/evaluator.h PackCode, and its constants): uploaded to
    // buffers this program owns, bound (BindEvaluator) wherever it is drawn. A later call replaces
    // the code (a save's translation) without a build.
    void SetEvaluatorCode(const std::vector<std::array<uint32_t, 4>>& packed, const std::vector<std::array<float, 4>>& constants);
    bool HasEvaluator() const { return evalCode_ != 0; }
    void BindEvaluator() const;
    // Active uniform names (after the compiler dropped unused ones).
    std::vector<std::string> ActiveUniforms() const;
    // Sets a uniform only if the program declares it; converts to its declared type.
    void Set(const std::string& name, float x) const;
    void Set(const std::string& name, float x, float y) const;
    void Set(const std::string& name, float x, float y, float z) const;
    // A float array uniform (`name` without [0]), from its first element.
    void SetFloats(const std::string& name, const std::vector<float>& values) const;
    // The values of u_lit[i] this program draws with (a lifted source's literals, AssembleProgram
    // liftLiterals): its source's at first; LiveProgram's literal tier sets a retuned save's.
    const std::vector<float>& Literals() const { return literals_; }
    void SetLiterals(const std::vector<float>& values) { literals_ = values; }
private:
    struct Slot { int location; unsigned type; };
    unsigned id_ = 0;
    RenderPath path_ = RenderPath::Fragment;
    int group_[3] = {8, 8, 1};
    bool frameState_ = false;
    bool quadReflections_ = false;
    bool quadDefer_ = false;
    ShaderSource source_;
    ProgramOrigin origin_;
    std::map<std::string, Slot> uniforms_;
    std::vector<float> literals_;
    unsigned evalCode_ = 0, evalConst_ = 0;   // GL buffers (SetEvaluatorCode)
};

// A program being compiled and linked. Where GL_KHR_parallel_shader_compile exists the driver
// compiles on its own threads and Ready() polls without blocking (the driver may still stall a
// call: `sdfvj bench reload` shows which); elsewhere Ready() is true at once and Finish() waits.
// An optimized build that links is stored in the on-disk program cache (program_cache.h);
// BeginFromCache() starts from there when it can.
class CompileWorker;
class CompileProcess;
class PendingProgram {
public:
    // With a worker, Begin() queues the compile on the worker's thread and context instead.
    static void SetWorker(CompileWorker* worker);
    // With a loader (a CompileWorker whose context shares objects with the render thread's), a
    // program binary from the compile process or the program cache is loaded there and used once
    // (a 1x1 dispatch or draw, glFinish) before Ready() says so: the driver's lazy finalization of
    // a loaded binary at its first use (150-600 ms on NVIDIA) happens off the render thread.
    // Binaries the driver refuses there are built again the way they would be without a loader.
    static void SetLoader(CompileWorker* loader);
    static CompileWorker* Loader();
    static CompileWorker* Worker();
    // With a usable compile process (compile_process.h), Begin() sends the compile there (before
    // any worker); Finish() loads its binary, or compiles here when the process cannot serve.
    void SetProcess(CompileProcess* process) { process_ = process; }
    PendingProgram() = default;
    ~PendingProgram();
    PendingProgram(const PendingProgram&) = delete;
    PendingProgram& operator=(const PendingProgram&) = delete;
    // Compiles `src` (the quick tier: QuickTierText of it, never cached). Program::Source() of the
    // result is `src` either way.
    void Begin(const ShaderSource& src, RenderPath path, BuildTier tier = BuildTier::Optimized);
    // Takes the program from the on-disk cache when it holds this source for this driver: then
    // true, Ready() at once and the program FromCache(). False (nothing started) otherwise.
    bool BeginFromCache(const ShaderSource& src, RenderPath path);
    bool Active() const { return id_ != 0 || ticket_ != 0 || procTicket_ != 0 || loadTicket_ != 0; }
    bool FromCache() const { return origin_.fromCache; }
    bool Ready() const;
    // On success moves the program into `into`; on failure `into` is untouched and `log` holds
    // file:line messages. Either way the pending program is done.
    bool Finish(Program* into, std::string* log);
    void Cancel();
    const ShaderSource& Source() const { return source_; }
    static bool ParallelCompileAvailable();
private:
    unsigned id_ = 0;
    std::vector<unsigned> stages_;
    uint64_t ticket_ = 0;                 // job on the CompileWorker
    mutable bool workerDone_ = false;
    mutable unsigned workerProgram_ = 0;
    mutable std::string workerLog_;
    mutable std::vector<uint8_t> workerBinary_;   // binary hand-over mode
    mutable unsigned workerFormat_ = 0;
    mutable double workerMs_ = 0.0;
    mutable bool workerNoBinary_ = false;         // binary hand-over refused: Finish() compiles here
    CompileProcess* process_ = nullptr;
    bool retrievable_ = false;                    // ask for a binary even when not storing (source hand-over)
    uint64_t procTicket_ = 0;                     // job on the compile process
    mutable bool procDone_ = false;
    mutable bool procDied_ = false;               // the server died first: Finish() compiles here
    bool FinishInProcess(Program* into, std::string* log);
    mutable uint64_t loadTicket_ = 0;             // job on the loader (SetLoader)
    mutable bool loadDone_ = false;
    mutable unsigned loadProgram_ = 0;
    mutable double loadMs_ = 0.0;
    mutable bool loadFromCache_ = false;          // the binary came from the program cache (else the process)
    bool StartLoad(unsigned format, std::vector<uint8_t> binary) const;
    bool PollLoad() const;
    ShaderSource source_;
    RenderPath path_ = RenderPath::Fragment;
    ProgramOrigin origin_;
    double beganAt_ = 0.0;                        // steady clock, ms
};

// Draws programs into an RGBA8 texture of a given size and reads it back. With a float target
// (Resize(..., true)) the texture is RGBA32F: programs with DEBUG_VIEW 4/5 (geometry, linear
// radiance) write unclamped floats there, read back with ReadPixelsFloat.
class FrameRenderer {
public:
    FrameRenderer() = default;
    ~FrameRenderer();
    FrameRenderer(const FrameRenderer&) = delete;
    FrameRenderer& operator=(const FrameRenderer&) = delete;
    bool Resize(int width, int height, std::string* error, bool floatTarget = false);
    // Keeps the targets of the last `n` other sizes (0: none, the default) so that a Resize back to
    // one of them takes it again instead of allocating: on NVIDIA a new texture's first draw holds
    // the CPU and every context's frames for about 1 ms per MB (docs/performance.md, "Session 33"),
    // and `live --frame-budget` or the resolution slider move between a few sizes.
    void SetKeptSizes(int n);
    // Sizes a Resize allocated a new target for (not taken from the kept ones) so far.
    int TargetsMade() const { return targetsMade_; }
    int Width() const { return width_; }
    bool FloatTarget() const { return floatTarget_; }
    int Height() const { return height_; }
    // Sets built-in, scene and quality uniforms, then draws. With `timeGpu` the draw is timed
    // (see LastGpuMs; costs a sync, use in benchmarks only): a GL timer query on a GPU, glFinish
    // and a wall clock on llvmpipe, whose timer queries are meaningless.
    void Draw(const Program& program, const SceneInfo& scene, const FrameInputs& in, bool timeGpu = false);
    double LastGpuMs() const { return lastGpuMs_; }
    // Compute path: the frame's dispatch split into `n` horizontal strips with a glFinish after
    // each (1: one dispatch, the default). The same pixels; the GPU is free between strips for
    // another process's work (a render server's first frame while the show's frames go on).
    void SetStrips(int n) { strips_ = n < 1 ? 1 : n; }
    // A program with Program::QuadDefer: room for `entries` listed bounces (-1, the default: an
    // eighth of the frame's pixels; past it a pixel traces its own bounce in the frame), and how
    // many the last Draw listed, the ones past the room included (reads the GPU back: a sync).
    void SetQuadDeferRoom(long long entries) { deferRoomAsked_ = entries; }
    long long LastQuadDeferred() const;
    // RGBA rows, top row first.
    std::vector<uint8_t> ReadPixels() const;
    // RGBA32F rows of a float target, BOTTOM row first (row y is fragCoord.y = y + 0.5).
    std::vector<float> ReadPixelsFloat() const;
    unsigned Framebuffer() const { return fbo_; }
    unsigned Texture() const { return texture_; }
private:
    struct Target {
        int w = 0, h = 0;
        bool isFloat = false;
        unsigned fbo = 0, texture = 0, cone = 0;
    };
    void Release();
    static void ReleaseTarget(Target& t);
    // The list's buffers made or grown for this frame's room (SetQuadDeferRoom); the room they hold.
    long long QuadDeferRoom();
    Target Current() const { return {width_, height_, floatTarget_, fbo_, texture_, coneTexture_}; }
    int width_ = 0, height_ = 0;
    bool floatTarget_ = false;
    unsigned fbo_ = 0, texture_ = 0, vao_ = 0, query_ = 0;
    unsigned coneTexture_ = 0;   // r32f, one texel per 8x8 tile: the cone pre-pass's start distances
    std::vector<Target> kept_;   // other sizes' targets, the least recently left first
    size_t keepSizes_ = 0;
    int targetsMade_ = 0;
    unsigned stateBuffer_ = 0;   // the scene's frame state (Program::FrameState), kSceneStateBytes
    unsigned quadTexture_ = 0;   // rgba32ui, one texel per 2x2 pixels (Program::QuadReflections), made when first asked for
    int quadW_ = 0, quadH_ = 0;
    unsigned deferHead_ = 0, deferBuffer_ = 0;   // the list of bounces (Program::QuadDefer): its head, room for deferRoom_ entries
    long long deferRoom_ = 0, deferFailed_ = 0;   // the room made; the room asked for that no memory held (0: none)
    long long deferRoomAsked_ = -1;   // SetQuadDeferRoom; -1: an eighth of the frame's pixels
    double lastGpuMs_ = 0.0;
    int strips_ = 1;
};

// Mixes two rendered frames (FrameRenderer textures of one size) into a target framebuffer
// (0 = the window): a scene change that morphs fades from the old scene's frame to the new one's.
class Crossfade {
public:
    Crossfade() = default;
    ~Crossfade();
    Crossfade(const Crossfade&) = delete;
    Crossfade& operator=(const Crossfade&) = delete;
    bool Init(std::string* error);     // compiles its small program once; false with a reason
    // t = 0 shows `from`, t = 1 shows `to`.
    void Draw(unsigned fromTexture, unsigned toTexture, float t, unsigned targetFramebuffer, int width, int height);
private:
    unsigned program_ = 0, vao_ = 0;
    int mixLocation_ = -1;
};

// Median of benchmark samples (0 for none).
double MedianMs(std::vector<double> samples);

// GL_RENDERER string of the current context.
std::string GlRendererName();
// True on Mesa's software rasterizer, where timer queries are meaningless (time with glFinish).
bool IsSoftwareRenderer();
// Whether shaders should compile on a CompileWorker rather than through the driver's own
// parallel compile. Measured (`sdfvj bench reload`, docs/performance.md): on Mesa a compile on
// the render thread blocks the frame for all of it (~0.5 s) and the worker keeps frames at
// ~18 ms; on NVIDIA the worker's compile holds a driver lock that stalls the render thread for
// the whole compile (0.4-1.5 s) while GL_KHR_parallel_shader_compile stalls one frame ~0.2 s.
bool PreferCompileThread();

// Picks the faster path for this GPU by timing both on a small probe (cached per GL_RENDERER in
// $XDG_CACHE_HOME/sdfvj/paths.json). Logs the decision to `log` when given.
RenderPath ProbeRenderPath(const SceneInfo& scene, std::string* log);

// Writes RGBA rows (top first) as PNG. False with a reason on failure.
bool WritePng(const std::string& path, int width, int height, const std::vector<uint8_t>& rgba, std::string* error);

}  // namespace sdfvj
