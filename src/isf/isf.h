// ISF module: hosts ISF 2.0 shaders (the Interactive Shader Format of VDMX, Resolume, ...) as
// generators (a scene of their own) and as filters in a post chain over the raymarched frame.
//
// Usage (render thread, a GL 4.5 context current):
//   IsfChain post;
//   if (!post.Load({"shaders/isf/bloom.fs", "shaders/isf/rgb_split.fs"}, &error)) ...   // file:line: ...
//   for (const std::string& n : post.Notices()) log(n);     // what of ISF sdfvj does not support
//   IsfFrameInputs in;  in.time = t;  in.params = {{"amount", 0.5f}};
//   unsigned tex = post.Render(frameRenderer.Texture(), w, h, in);   // the chain's output texture
//   std::vector<uint8_t> rgba = ReadTextureRgba(tex, w, h);
// A generator is a chain whose first file has no image input: post.Render(0, w, h, in).
//
// Parsing (IsfFile) needs no GL and throws nothing: every failure is a value
// "file.fs:LINE: what is wrong, expected what". docs/isf.md lists what is not supported; each
// such feature in a file gives one line in IsfFile::notices and the file still runs.
#pragma once
#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <vector>

#include "core/param_decl.h"
#include "shader/shader.h"

namespace sdfvj {

enum class IsfInputType { Event, Bool, Long, Float, Point2D, Color, Image, Audio, AudioFFT };
const char* IsfInputTypeName(IsfInputType t);

// One entry of INPUTS. Vector values use as many components as the type has (point2D 2, color 4).
struct IsfInput {
    std::string name;                    // the GLSL uniform name, as written
    std::string label;                   // LABEL, else the name
    IsfInputType type = IsfInputType::Float;
    std::array<float, 4> defaultValue{}, minValue{}, maxValue{};
    std::vector<int> values;             // long: VALUES (may be empty: MIN..MAX then)
    std::vector<std::string> labels;     // long: LABELS, one per value
    int maxSamples = 0;                  // audio/audioFFT: MAX (0: native)
    int line = 0;                        // where it is declared in the .fs
};

// One entry of PASSES. An empty target renders to the effect's output.
struct IsfPass {
    std::string target;
    std::string widthExpr, heightExpr;   // "" = the render size; else an expression ($WIDTH, $HEIGHT, $input)
    bool persistent = false;             // kept across frames (feedback)
    bool floatTarget = false;            // RGBA32F instead of RGBA8
    int line = 0;
};

// One entry of IMPORTED: an image file loaded once and sampled by name.
struct IsfImport {
    std::string name;
    std::string path;                    // resolved against the .fs file's folder
    int line = 0;
};

enum class IsfKind { Generator, Filter, Shadertoy };

struct IsfFile {
    std::string path;
    IsfKind kind = IsfKind::Generator;   // Filter: it has an image input (by convention "inputImage")
    std::string isfVersion;              // ISFVSN ("" = 1.0)
    std::string description, credit;
    std::vector<std::string> categories;
    std::vector<IsfInput> inputs;
    std::vector<IsfPass> passes;         // never empty after parsing: one pass to the output at least
    std::vector<IsfImport> imports;
    std::string body;                    // the GLSL after the JSON comment
    int bodyLine = 1;                    // line of the .fs where `body` starts
    std::string vertexPath, vertexBody;  // the .vs of the same name, when there is one
    std::vector<std::string> notices;    // "file.fs:LINE: unsupported ..., what sdfvj does instead"
};

// Parses a whole .fs (text in memory); `path` names it in errors and resolves IMPORTED paths.
// A file without a JSON header that defines mainImage() is a Shadertoy generator.
bool ParseIsfText(const std::string& text, const std::string& path, IsfFile* out, std::string* error);
// Reads path (and path with .vs beside it) and parses.
bool LoadIsfFile(const std::string& path, IsfFile* out, std::string* error);
// True for names ending in .fs (ISF fragment shaders), case-insensitive.
bool IsIsfPath(const std::string& path);
// An ISF effect's source: its .fs (IsIsfPath) or the .vs beside one (what a save of an effect changes).
bool IsIsfSource(const std::string& path);
// A pass of the file keeps its image across frames (PERSISTENT: feedback, such as trails).
bool IsfHasFeedback(const IsfFile& file);

// The inputs as scene parameters, addressed by mappings, OSC, presets and --param like any scene
// input: float -> name, bool/event -> name (0/1), long -> name (int, MIN..MAX of VALUES),
// point2D -> name_x, name_y, color -> name_r, name_g, name_b, name_a. Images have none.
std::vector<ParamDecl> IsfParams(const IsfFile& file);
// Applies --param NAME=VALUE overrides to `values` (clamped; unknown names are an error).
bool ApplyIsfParamOverrides(const std::vector<ParamDecl>& decls, const std::vector<std::string>& overrides,
                            std::vector<std::pair<std::string, float>>* values, std::string* error);

// Evaluates a PASSES WIDTH/HEIGHT expression: numbers, $NAME variables, + - * / % ^, unary -,
// parentheses, pi, e and floor ceil round abs sqrt exp log sin cos tan min max pow. No exceptions;
// error says what and where ("unknown variable '$blur'").
bool EvalIsfExpression(const std::string& expr, const std::map<std::string, double>& vars, double* out,
                       std::string* error);

// The GL 4.5 core program sources for a file: a preamble with the ISF built-ins and the input
// uniforms, the body with its GLSL 1.x words translated (gl_FragColor, texture2D, varying), and
// `#line` directives so a driver error names the .fs and its line (MapCompileLog).
struct IsfSources {
    ShaderSource vertex, fragment;
};
bool TranslateIsf(const IsfFile& file, IsfSources* out, std::string* error);

// Per-frame values an ISF program reads.
struct IsfFrameInputs {
    double time = 0.0, timeDelta = 0.0;
    int frame = 0;
    std::array<float, 4> date{2024, 1, 1, 0};   // DATE: year, month, day, seconds in the day
    std::array<float, 4> mouse{};               // Shadertoy iMouse (pixels)
    float beat = 0.0f, bpm = 120.0f;            // the show's tempo, as scenes get it: u_beat (phase 0..1), u_bpm
    std::vector<std::pair<std::string, float>> params;   // IsfParams names -> value (clamped here)
    // Sound for `audio` / `audioFFT` inputs, e.g. src/audio's AudioSpectrum: waveform samples
    // -1..1 (read by the shader as 0.5 + 0.5 * s) and spectrum bins 0..1, one texel each in a
    // N x 1 texture, rgb = the value. Empty: silence (wave at rest 0.5, spectrum 0).
    std::span<const float> audioWaveform, audioSpectrum;
};

// DATE now, in local time: year, month, day, seconds in the day.
std::array<float, 4> IsfDateNow();

// The row an audio/audioFFT input reads: `values` as they are, or with MAX (maxSamples) below
// their count, MAX texels each the mean of its share of the values (a spectrum's peak stays in
// the texel covering its bin). The texture is that many texels wide (IMG_SIZE says so).
std::vector<float> IsfAudioRow(std::span<const float> values, int maxSamples);

// Render targets a rebuilt chain takes over from the chain it replaced, instead of allocating its
// own. On NVIDIA the first draw into a newly allocated texture holds the CPU (and every context's
// frames) for about 1 ms per MB: a 3840x2160 RGBA32F target's first two draws (its two buffers)
// cost 70-170 ms, a reused one's 0.1 ms (docs/performance.md, "Session 32"). Textures are shared
// by the contexts of a share group; any thread may call it, each with one of them current.
class IsfTexturePool {
public:
    // A texture of that size and internal format the pool held (it no longer does), or 0. The
    // calling context's later commands wait (on the GPU) for those the giver issued before Seal.
    unsigned Take(int w, int h, unsigned format);
    // Keeps `texture` for a later Take.
    void Put(unsigned texture, int w, int h, unsigned format);
    // After Puts: a fence behind the current context's commands so far (which may still read or
    // draw the textures given), which a Take in another context waits for.
    void Seal();
    // Deletes the oldest textures it holds until it holds at most `capBytes`.
    void SetCap(size_t capBytes);
    // Takes that found nothing (the caller made a new texture) so far.
    int Misses() const;
    // Deletes everything it holds, and its fence.
    void Clear();
    static size_t BytesOf(int w, int h, unsigned format);

private:
    struct Entry {
        unsigned texture = 0;
        int w = 0, h = 0;
        unsigned format = 0;
    };
    void Trim();   // mutex_ held
    mutable std::mutex mutex_;
    std::vector<Entry> entries_;   // oldest first
    size_t cap_ = 0, bytes_ = 0;
    int misses_ = 0;
    void* sealed_ = nullptr;       // the last Seal's GLsync
};

// One ISF file with its program, buffers and imported images. Owns GL objects: create, use and
// destroy it on the render thread with the context current.
class IsfEffect {
public:
    IsfEffect();
    ~IsfEffect();
    IsfEffect(const IsfEffect&) = delete;
    IsfEffect& operator=(const IsfEffect&) = delete;
    // Parses, translates, compiles and imports. On failure the effect keeps what it had before
    // (keep-last-good) and error is one or more "file:line: ..." lines.
    bool Load(const std::string& path, std::string* error);
    // The same from a file already parsed (LoadIsfFile): nothing is read from disk.
    bool LoadParsed(IsfFile file, std::string* error);
    // Copies `other`'s last content of each TARGET this effect also has, at the same size and
    // format (a rebuilt effect keeps its PERSISTENT feedback). Textures are shared between
    // contexts, so `other` may have been built in another one.
    void CopyBuffersFrom(const IsfEffect& other);
    // Every target back to transparent black, as a new effect's are.
    void ClearBuffers();
    // New targets come from `pool` where it holds one of their size and format (null: none).
    void SetTexturePool(IsfTexturePool* pool);
    // Keeps the targets of the last `n` other sizes each pass drew at (0: none, the default), so a
    // return to a size (`live`'s render scale under --frame-budget) takes them again, not new ones.
    void SetKeptSizes(int n);
    // Hands every target's textures (those of kept sizes too) to `pool` (the effect keeps none); the bytes they hold.
    size_t GiveTextures(IsfTexturePool& pool);
    // Deletes the objects only the current context can use (vertex array, framebuffers); the next
    // Render, in any context of the share group, makes them there.
    void ReleaseContextObjects();
    bool IsValid() const;
    const IsfFile& File() const;
    const std::vector<ParamDecl>& Params() const;
    // Runs every pass at w x h. `input` is the previous stage's texture (0: none, image inputs
    // then read black). Returns the texture holding the output, valid until the next Render.
    unsigned Render(unsigned input, int w, int h, const IsfFrameInputs& in);
    // Re-reads the .fs/.vs when their bytes changed; a failed reload keeps the running program.
    // Returns 0 unchanged, 1 reloaded, -1 failed (error set). A save whose GLSL is the program's
    // own (the last good file put back after a broken save) compiles nothing.
    int ReloadIfChanged(std::string* error);
    // Programs compiled and linked so far (a reload that compiles nothing leaves it).
    int ProgramsBuilt() const;
    // ShaderSource::hash of the vertex and fragment stages the program was built from.
    std::pair<uint64_t, uint64_t> ProgramHash() const;
private:
    struct State;
    std::unique_ptr<State> s_;
};

// A post chain (or a generator followed by filters): each stage reads the previous one's output.
class IsfChain {
public:
    // Loads every file; false with the first file's error (nothing replaced on failure).
    bool Load(const std::vector<std::string>& paths, std::string* error);
    void Add(std::unique_ptr<IsfEffect> effect) { effects_.push_back(std::move(effect)); }
    // Each stage's feedback from `other`'s stage at the same place in the chain, of the same file.
    void CopyBuffersFrom(const IsfChain& other);
    void ClearBuffers();
    void SetTexturePool(IsfTexturePool* pool);
    void SetKeptSizes(int n);
    size_t GiveTextures(IsfTexturePool& pool);
    void ReleaseContextObjects();
    bool Empty() const { return effects_.empty(); }
    size_t Size() const { return effects_.size(); }
    IsfEffect& Stage(size_t i) { return *effects_[i]; }
    // Every stage's notices, one line each.
    std::vector<std::string> Notices() const;
    // All stages' parameters (a name two stages share is one parameter).
    std::vector<ParamDecl> Params() const;
    unsigned Render(unsigned input, int w, int h, const IsfFrameInputs& in);
    // Hot reload for live: call when a watched file changed (or once a second). Each stage that
    // changed is rebuilt; one that fails keeps running its last good program and adds a line to
    // `errors`. Returns true when any stage was reloaded.
    bool ReloadIfChanged(std::vector<std::string>* errors);
private:
    std::vector<std::unique_ptr<IsfEffect>> effects_;
};

// A hash of an ISF file's bytes and of its .vs beside it: what a save changes.
uint64_t IsfFilesHash(const std::string& fsPath);

// The parameters of several files, parsed only (no GL): for sorting --param before GL exists.
bool IsfListParams(const std::vector<std::string>& paths, std::vector<ParamDecl>* out, std::string* error);
// Moves the NAME=VALUE entries of `params` whose NAME is one of `decls` into `isf`.
void SplitIsfOverrides(const std::vector<ParamDecl>& decls, std::vector<std::string>* params, std::vector<std::string>* isf);

// "a.fs,b.fs" -> {"a.fs", "b.fs"}; a bare name ("bloom") means shaders/isf/bloom.fs.
std::vector<std::string> SplitIsfList(const std::string& list);
// Resolves a post-effect or scene name to a file: a path as given, else shaders/isf/NAME(.fs).
std::string ResolveIsfPath(const std::string& nameOrPath);

// RGBA8 rows of a texture, top row first (as FrameRenderer::ReadPixels).
std::vector<uint8_t> ReadTextureRgba(unsigned texture, int w, int h);

// Reads an image file (PNG, JPEG, BMP, TGA via stb_image) as RGBA8 rows, BOTTOM row first (GL's
// order). False with "path: why" on failure.
bool LoadImageRgba(const std::string& path, int* w, int* h, std::vector<uint8_t>* rgba, std::string* error);

}  // namespace sdfvj
