// The ISF pass graph on the current GL context: one program per file, a double-buffered texture
// per TARGET (a pass reads the previous content of its own target while writing the new one,
// which is what PERSISTENT feedback needs), imported images, and a chain of effects.
// Render thread only: every function here makes GL calls.
#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <utility>
#include <vector>

#include "isf/isf.h"
#include "render/gl_stages.h"
#include "render/kept_sizes.h"

namespace sdfvj {

namespace {

constexpr int kMaxSide = 16384;

// Two textures (front: the last content, back: being drawn) and their framebuffers.
struct Buffer {
    unsigned tex[2] = {0, 0}, fbo[2] = {0, 0};
    int w = 0, h = 0, front = 0;
    bool isFloat = false;
    // Other sizes' textures, the least recently left first (IsfEffect::SetKeptSizes): a return to
    // a size takes them again, with no new texture's first draw.
    struct Kept {
        unsigned tex[2] = {0, 0};
        int w = 0, h = 0;
        bool isFloat = false;
    };
    std::vector<Kept> kept;

    static void DeleteKept(Kept& k) {
        glDeleteTextures(2, k.tex);
        k = Kept{};
    }
    void Release() {
        glDeleteFramebuffers(2, fbo);
        glDeleteTextures(2, tex);
        tex[0] = tex[1] = fbo[0] = fbo[1] = 0;
        w = h = 0;
        for (Kept& k : kept) DeleteKept(k);
        kept.clear();
    }
    // (Re)creates both textures cleared to transparent black when size or format changed (taken
    // from the kept sizes, or from `pool`, where they have them). With `keep` > 0 the size left is
    // kept (at most `keep` sizes). `carry` (a PERSISTENT target): the last content, scaled to the new
    // size, so feedback (trails) goes on through a render-scale move instead of starting from black.
    void Ensure(int width, int height, bool floatTarget, IsfTexturePool* pool, size_t keep, bool carry) {
        if (tex[0] && w == width && h == height && isFloat == floatTarget) {
            if (!fbo[0]) {   // drawn first in another context (IsfEffect::ReleaseContextObjects)
                glCreateFramebuffers(2, fbo);
                for (int i = 0; i < 2; ++i) glNamedFramebufferTexture(fbo[i], GL_COLOR_ATTACHMENT0, tex[i], 0);
            }
            return;
        }
        glDeleteFramebuffers(2, fbo);
        fbo[0] = fbo[1] = 0;
        const unsigned last = carry ? tex[front] : 0;
        const int lastW = w, lastH = h;
        std::vector<Kept> released;   // deleted once `last` is copied
        const Kept next = SwapKeptSize(kept, keep, Kept{{tex[0], tex[1]}, tex[0] ? w : 0, h, isFloat}, width, height, floatTarget,
                                       [&](Kept& k) { released.push_back(k); });
        tex[0] = next.tex[0], tex[1] = next.tex[1];
        glCreateFramebuffers(2, fbo);
        const float zero[4] = {0, 0, 0, 0};
        const unsigned format = floatTarget ? GL_RGBA32F : GL_RGBA8;
        for (int i = 0; i < 2; ++i) {
            if (!tex[i] && pool) tex[i] = pool->Take(width, height, format);
            if (!tex[i]) {
                glCreateTextures(GL_TEXTURE_2D, 1, &tex[i]);
                glTextureStorage2D(tex[i], 1, format, width, height);
            }
            glClearTexImage(tex[i], 0, GL_RGBA, GL_FLOAT, zero);
            glNamedFramebufferTexture(fbo[i], GL_COLOR_ATTACHMENT0, tex[i], 0);
        }
        if (last) {   // into the front texture, which the next pass reads
            unsigned read = 0;
            glCreateFramebuffers(1, &read);
            glNamedFramebufferTexture(read, GL_COLOR_ATTACHMENT0, last, 0);
            glBlitNamedFramebuffer(read, fbo[0], 0, 0, lastW, lastH, 0, 0, width, height, GL_COLOR_BUFFER_BIT, GL_LINEAR);
            glDeleteFramebuffers(1, &read);
        }
        for (Kept& k : released) DeleteKept(k);
        w = width;
        h = height;
        isFloat = floatTarget;
        front = 0;
    }
    unsigned Front() const { return tex[front]; }
};

unsigned OnePixelTexture(const uint8_t rgba[4]) {
    unsigned t = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &t);
    glTextureStorage2D(t, 1, GL_RGBA8, 1, 1);
    glTextureSubImage2D(t, 0, 0, 0, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
    return t;
}

// One stage, its log's lines mapped back to the .fs/.vs; 0 on failure.
unsigned IsfStage(GLenum kind, const ShaderSource& src, std::string* log) {
    std::string raw;
    unsigned s = CompileStage(kind, src.text.c_str(), &raw);
    if (!s) *log += MapCompileLog(raw.c_str(), src);
    return s;
}

// Links the two stages; 0 with file:line messages in `error` on failure.
unsigned BuildProgram(const IsfSources& src, const std::string& path, std::string* error) {
    std::string log;
    unsigned vs = IsfStage(GL_VERTEX_SHADER, src.vertex, &log);
    unsigned fs = IsfStage(GL_FRAGMENT_SHADER, src.fragment, &log);
    if (!vs || !fs) {
        if (vs) glDeleteShader(vs);
        if (fs) glDeleteShader(fs);
        *error = log.empty() ? path + ":1: the shader does not compile" : log;
        while (!error->empty() && error->back() == '\n') error->pop_back();
        return 0;
    }
    std::string raw;
    if (unsigned p = LinkStages({vs, fs}, &raw)) return p;
    *error = path + ":1: the shader does not link: " + raw;
    while (!error->empty() && error->back() == '\n') error->pop_back();
    return 0;
}

}  // namespace

uint64_t IsfFilesHash(const std::string& fsPath) {
    std::string bytes;
    for (std::string p : {fsPath, fsPath.substr(0, fsPath.size() - 3) + ".vs"}) {
        std::ifstream in(p, std::ios::binary);
        std::stringstream ss;
        if (in) ss << in.rdbuf();
        bytes += ss.str() + '\0';
    }
    return HashBytes(bytes);
}

struct IsfEffect::State {
    std::string path;
    IsfFile file;
    std::vector<ParamDecl> params;
    unsigned program = 0, vao = 0, sampler = 0, black = 0, silence = 0;
    std::map<std::string, std::pair<unsigned, int>> audioTex;   // audio/audioFFT input -> texture, width
    std::map<std::string, int> locations;
    std::map<std::string, Buffer> buffers;          // by TARGET; "" is the output
    std::map<std::string, unsigned> imports;        // IMPORTED name -> texture
    uint64_t hash = 0;                              // of the bytes last loaded (or last tried)
    std::pair<uint64_t, uint64_t> programHash{};    // ShaderSource::hash of the stages `program` was built from
    int built = 0;                                  // programs built (ProgramsBuilt)
    std::vector<unsigned> boundUnits;
    IsfTexturePool* pool = nullptr;                 // where new targets come from (SetTexturePool)
    size_t keepSizes = 0;                           // other sizes' targets kept (SetKeptSizes)

    int Location(const std::string& name) {
        auto it = locations.find(name);
        if (it != locations.end()) return it->second;
        return locations[name] = glGetUniformLocation(program, name.c_str());
    }
    void BindImage(const std::string& name, unsigned texture) {
        const int loc = Location(name);
        if (loc < 0) return;
        const unsigned unit = (unsigned)boundUnits.size();
        glBindTextureUnit(unit, texture);
        glBindSampler(unit, sampler);
        glUniform1i(loc, (int)unit);
        boundUnits.push_back(unit);
    }
    void ReleaseProgram() {
        if (program) glDeleteProgram(program);
        for (auto& [n, t] : imports) glDeleteTextures(1, &t);
        imports.clear();
        locations.clear();
        program = 0;
    }
};

IsfEffect::IsfEffect() : s_(std::make_unique<State>()) {}

IsfEffect::~IsfEffect() {
    s_->ReleaseProgram();
    for (auto& [n, b] : s_->buffers) b.Release();
    if (s_->vao) glDeleteVertexArrays(1, &s_->vao);
    if (s_->sampler) glDeleteSamplers(1, &s_->sampler);
    if (s_->black) glDeleteTextures(1, &s_->black);
    if (s_->silence) glDeleteTextures(1, &s_->silence);
    for (auto& [n, t] : s_->audioTex)
        if (t.first) glDeleteTextures(1, &t.first);
}

std::vector<float> IsfAudioRow(std::span<const float> values, int maxSamples) {
    const size_t n = values.size();
    if (maxSamples <= 0 || size_t(maxSamples) >= n) return std::vector<float>(values.begin(), values.end());
    // MAX below the native count: texel i is the mean of values [i*n/m, (i+1)*n/m), so a peak in
    // the spectrum stays in the texel covering it and the waveform keeps its whole window.
    const size_t m = size_t(maxSamples);
    std::vector<float> out(m, 0.0f);
    for (size_t i = 0; i < m; ++i) {
        const size_t b = i * n / m, e = std::max(b + 1, (i + 1) * n / m);
        double sum = 0.0;
        for (size_t k = b; k < e; ++k) sum += std::isfinite(values[k]) ? values[k] : 0.0f;
        out[i] = float(sum / double(e - b));
    }
    return out;
}

namespace {
// Uploads one audio row as an N x 1 RGBA32F texture (rgb = value, a = 1); remade when N changes.
unsigned UploadAudioRow(unsigned* tex, int* size, std::span<const float> values, bool wave) {
    const int n = (int)values.size();
    if (*tex && *size != n) {
        glDeleteTextures(1, tex);
        *tex = 0;
    }
    if (!*tex) {
        glCreateTextures(GL_TEXTURE_2D, 1, tex);
        glTextureStorage2D(*tex, 1, GL_RGBA32F, n, 1);
        *size = n;
    }
    std::vector<float> rgba((size_t)n * 4, 1.0f);
    for (int i = 0; i < n; ++i) {
        float v = values[(size_t)i];
        if (!std::isfinite(v)) v = 0.0f;
        v = wave ? 0.5f + 0.5f * std::clamp(v, -1.0f, 1.0f) : std::clamp(v, 0.0f, 1.0f);
        rgba[(size_t)i * 4] = rgba[(size_t)i * 4 + 1] = rgba[(size_t)i * 4 + 2] = v;
    }
    glTextureSubImage2D(*tex, 0, 0, 0, n, 1, GL_RGBA, GL_FLOAT, rgba.data());
    return *tex;
}
}  // namespace

bool IsfEffect::IsValid() const { return s_->program != 0; }
int IsfEffect::ProgramsBuilt() const { return s_->built; }
std::pair<uint64_t, uint64_t> IsfEffect::ProgramHash() const { return s_->programHash; }
const IsfFile& IsfEffect::File() const { return s_->file; }
const std::vector<ParamDecl>& IsfEffect::Params() const { return s_->params; }

bool IsfEffect::Load(const std::string& path, std::string* error) {
    s_->hash = IsfFilesHash(path);
    s_->path = path;
    IsfFile file;
    return LoadIsfFile(path, &file, error) && LoadParsed(std::move(file), error);
}

bool IsfEffect::LoadParsed(IsfFile file, std::string* error) {
    State& s = *s_;
    const std::string path = file.path;
    IsfSources src;
    if (!TranslateIsf(file, &src, error)) return false;
    // The GLSL of the program on screen (a save that puts back the last good file after a broken
    // one, or changes only what the GLSL does not see): nothing to compile, and no frame waits.
    const std::pair<uint64_t, uint64_t> programHash{src.vertex.hash, src.fragment.hash};
    const bool sameProgram = s.program && programHash == s.programHash && file.imports.empty() && s.imports.empty();
    std::map<std::string, unsigned> imports;
    auto dropImports = [&] { for (auto& [n, t] : imports) glDeleteTextures(1, &t); };
    for (const IsfImport& im : file.imports) {
        int w = 0, h = 0;
        std::vector<uint8_t> rgba;
        std::string why;
        if (!LoadImageRgba(im.path, &w, &h, &rgba, &why)) {
            dropImports();
            *error = path + ":" + std::to_string(im.line) + ": IMPORTED '" + im.name + "': " + why;
            return false;
        }
        unsigned t = 0;
        glCreateTextures(GL_TEXTURE_2D, 1, &t);
        glTextureStorage2D(t, 1, GL_RGBA8, w, h);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
        glTextureSubImage2D(t, 0, 0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
        imports[im.name] = t;
    }
    const unsigned program = sameProgram ? s.program : BuildProgram(src, path, error);
    if (!program) {
        dropImports();
        return false;
    }
    // Success: swap in. Buffers of targets the new file still has are kept (feedback survives a reload).
    if (!sameProgram) {
        ++s.built;
        s.ReleaseProgram();
        s.program = program;
        s.programHash = programHash;
        s.imports = std::move(imports);
    }
    s.file = std::move(file);
    s.params = IsfParams(s.file);
    for (auto it = s.buffers.begin(); it != s.buffers.end();) {
        const bool used = std::any_of(s.file.passes.begin(), s.file.passes.end(), [&](const IsfPass& p) { return p.target == it->first; });
        if (used) ++it;
        else { it->second.Release(); it = s.buffers.erase(it); }
    }
    if (!s.vao) {
        glCreateVertexArrays(1, &s.vao);
        glCreateSamplers(1, &s.sampler);
        glSamplerParameteri(s.sampler, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glSamplerParameteri(s.sampler, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glSamplerParameteri(s.sampler, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glSamplerParameteri(s.sampler, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        const uint8_t black[4] = {0, 0, 0, 255}, grey[4] = {128, 128, 128, 255};
        s.black = OnePixelTexture(black);
        s.silence = OnePixelTexture(grey);   // an "audio" wave at rest is 0.5
    }
    return true;
}

void IsfEffect::ClearBuffers() {
    const float zero[4] = {0, 0, 0, 0};
    for (auto& [target, b] : s_->buffers)
        for (unsigned t : b.tex)
            if (t) glClearTexImage(t, 0, GL_RGBA, GL_FLOAT, zero);
}

void IsfEffect::SetTexturePool(IsfTexturePool* pool) { s_->pool = pool; }

void IsfEffect::SetKeptSizes(int n) { s_->keepSizes = (size_t)std::max(n, 0); }

void IsfEffect::ReleaseContextObjects() {
    if (s_->vao) glDeleteVertexArrays(1, &s_->vao);
    s_->vao = 0;
    for (auto& [target, b] : s_->buffers) {
        glDeleteFramebuffers(2, b.fbo);
        b.fbo[0] = b.fbo[1] = 0;
    }
}

size_t IsfEffect::GiveTextures(IsfTexturePool& pool) {
    size_t bytes = 0;
    auto give = [&](unsigned& t, int w, int h, bool isFloat) {
        if (!t) return;
        const unsigned format = isFloat ? GL_RGBA32F : GL_RGBA8;
        pool.Put(t, w, h, format);
        bytes += IsfTexturePool::BytesOf(w, h, format);
        t = 0;
    };
    for (auto& [target, b] : s_->buffers) {
        for (unsigned& t : b.tex) give(t, b.w, b.h, b.isFloat);
        for (Buffer::Kept& k : b.kept)
            for (unsigned& t : k.tex) give(t, k.w, k.h, k.isFloat);
        b.Release();   // its framebuffers (the textures are the pool's now)
    }
    return bytes;
}

void IsfEffect::CopyBuffersFrom(const IsfEffect& other) {
    for (auto& [target, b] : s_->buffers) {
        auto it = other.s_->buffers.find(target);
        if (it == other.s_->buffers.end() || !b.tex[0]) continue;
        const Buffer& o = it->second;
        if (!o.tex[0] || o.w != b.w || o.h != b.h || o.isFloat != b.isFloat) continue;
        glCopyImageSubData(o.Front(), GL_TEXTURE_2D, 0, 0, 0, 0, b.Front(), GL_TEXTURE_2D, 0, 0, 0, 0, b.w, b.h, 1);
    }
}

int IsfEffect::ReloadIfChanged(std::string* error) {
    if (s_->path.empty() || IsfFilesHash(s_->path) == s_->hash) return 0;
    return Load(s_->path, error) ? 1 : -1;   // Load records the new hash either way: one report per save
}

unsigned IsfEffect::Render(unsigned input, int w, int h, const IsfFrameInputs& in) {
    State& s = *s_;
    if (!s.program) return input;   // a file that never loaded passes its input through
    const IsfFile& f = s.file;
    auto valueOf = [&](const ParamDecl& d) {
        for (const auto& [n, v] : in.params)
            if (n == d.name) return ClampParam(d, v);
        return d.defaultValue;
    };
    std::map<std::string, float> values;
    for (const ParamDecl& d : s.params) values[d.name] = valueOf(d);
    std::map<std::string, double> vars{{"WIDTH", w}, {"HEIGHT", h}};
    for (const IsfInput& i : f.inputs) {
        auto it = values.find(i.type == IsfInputType::Point2D ? i.name + "_x" : i.type == IsfInputType::Color ? i.name + "_r" : i.name);
        if (it != values.end()) vars[i.name] = it->second;
    }
    int inputW = 1, inputH = 1;
    if (input) {
        glGetTextureLevelParameteriv(input, 0, GL_TEXTURE_WIDTH, &inputW);
        glGetTextureLevelParameteriv(input, 0, GL_TEXTURE_HEIGHT, &inputH);
    }

    glUseProgram(s.program);
    if (!s.vao) glCreateVertexArrays(1, &s.vao);   // drawn first in another context
    glBindVertexArray(s.vao);
    SetOverwriteBlend();
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_CULL_FACE);
    // The frame's sound, uploaded once for all passes (only when the file has audio inputs).
    unsigned wave = s.silence, fft = s.black;
    // One texture per input: its MAX (sample count) may be below the native 512 (IsfAudioRow).
    std::map<std::string, unsigned> audioOf;
    for (const IsfInput& i : f.inputs) {
        if (i.type != IsfInputType::Audio && i.type != IsfInputType::AudioFFT) continue;
        const bool isWave = i.type == IsfInputType::Audio;
        const std::span<const float> values = isWave ? in.audioWaveform : in.audioSpectrum;
        if (values.empty()) continue;   // silence: the shared 1x1 textures
        auto& [tex, width] = s.audioTex[i.name];
        const std::vector<float> row = IsfAudioRow(values, i.maxSamples);
        audioOf[i.name] = UploadAudioRow(&tex, &width, row, isWave);
    }
    auto side = [&](const std::string& expr, int full) {
        double v = full;
        std::string why;
        if (!expr.empty() && !EvalIsfExpression(expr, vars, &v, &why)) v = full;   // checked at load; an input made it inf
        return (int)std::clamp(std::round(v), 1.0, double(kMaxSide));
    };
    // Every pass's target first: a pass that reads a later pass's target (last frame's) reads it at
    // its size, never the 1x1 black stand-in, so a chain's first draw (a build's) has the textures
    // every later frame has. On llvmpipe another texture size is another compile of the pass.
    // Each pass's size is evaluated once a frame, here.
    std::vector<std::pair<int, int>> sizes;
    sizes.reserve(f.passes.size());
    for (const IsfPass& pass : f.passes) {
        const auto& [pw, ph] = sizes.emplace_back(side(pass.widthExpr, w), side(pass.heightExpr, h));
        s.buffers[pass.target].Ensure(pw, ph, pass.floatTarget, s.pool, s.keepSizes, pass.persistent);
    }
    unsigned output = input;
    for (size_t pi = 0; pi < f.passes.size(); ++pi) {
        const IsfPass& pass = f.passes[pi];
        const auto [pw, ph] = sizes[pi];
        Buffer& b = s.buffers[pass.target];
        b.Ensure(pw, ph, pass.floatTarget, s.pool, s.keepSizes, pass.persistent);
        glBindFramebuffer(GL_FRAMEBUFFER, b.fbo[b.front ^ 1]);
        glViewport(0, 0, pw, ph);

        auto set1i = [&](const char* n, int v) { if (int l = s.Location(n); l >= 0) glUniform1i(l, v); };
        auto set1f = [&](const char* n, float v) { if (int l = s.Location(n); l >= 0) glUniform1f(l, v); };
        auto set4f = [&](const char* n, const std::array<float, 4>& v) { if (int l = s.Location(n); l >= 0) glUniform4f(l, v[0], v[1], v[2], v[3]); };
        if (f.kind == IsfKind::Shadertoy) {
            if (int l = s.Location("iResolution"); l >= 0) glUniform3f(l, (float)pw, (float)ph, 1.0f);
            if (int l = s.Location("iChannelResolution[0]"); l >= 0) glUniform3f(l, (float)inputW, (float)inputH, 1.0f);
            set1f("iTime", (float)in.time);
            set1f("iTimeDelta", (float)in.timeDelta);
            set1f("iFrameRate", in.timeDelta > 0 ? float(1.0 / in.timeDelta) : 60.0f);
            set1i("iFrame", in.frame);
            set4f("iMouse", in.mouse);
            set1f("u_beat", in.beat);
            set1f("u_bpm", in.bpm);
            set4f("iDate", in.date);
            s.BindImage("iChannel0", input ? input : s.black);
            for (const char* ch : {"iChannel1", "iChannel2", "iChannel3"}) s.BindImage(ch, s.black);
        } else {
            set1i("PASSINDEX", (int)pi);
            if (int l = s.Location("RENDERSIZE"); l >= 0) glUniform2f(l, (float)pw, (float)ph);
            set1f("TIME", (float)in.time);
            set1f("TIMEDELTA", (float)in.timeDelta);
            set4f("DATE", in.date);
            set1i("FRAMEINDEX", in.frame);
            set1f("u_beat", in.beat);
            set1f("u_bpm", in.bpm);
            for (const IsfInput& i : f.inputs) {
                const int l = s.Location(i.name);
                if (i.type == IsfInputType::Image) { s.BindImage(i.name, input ? input : s.black); continue; }
                if (i.type == IsfInputType::Audio || i.type == IsfInputType::AudioFFT) {
                    auto it = audioOf.find(i.name);
                    s.BindImage(i.name, it != audioOf.end() ? it->second : i.type == IsfInputType::Audio ? wave : fft);
                    continue;
                }
                if (l < 0) continue;
                switch (i.type) {
                    case IsfInputType::Float: glUniform1f(l, values[i.name]); break;
                    case IsfInputType::Bool: case IsfInputType::Event: case IsfInputType::Long:
                        glUniform1i(l, (int)std::lround(values[i.name])); break;
                    case IsfInputType::Point2D: glUniform2f(l, values[i.name + "_x"], values[i.name + "_y"]); break;
                    case IsfInputType::Color:
                        glUniform4f(l, values[i.name + "_r"], values[i.name + "_g"], values[i.name + "_b"], values[i.name + "_a"]);
                        break;
                    default: break;
                }
            }
            for (const IsfPass& p : f.passes) {
                if (p.target.empty()) continue;
                auto it = s.buffers.find(p.target);
                s.BindImage(p.target, it != s.buffers.end() && it->second.tex[0] ? it->second.Front() : s.black);
            }
            for (const auto& [name, t] : s.imports) s.BindImage(name, t);
        }
        glDrawArrays(GL_TRIANGLES, 0, 3);
        for (unsigned u : s.boundUnits) glBindSampler(u, 0);   // sampler objects would override others' textures
        s.boundUnits.clear();
        b.front ^= 1;
        output = b.Front();
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glUseProgram(0);
    return output;
}

}  // namespace sdfvj
