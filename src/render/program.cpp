#include <epoxy/gl.h>

#include "render/render.h"
#include "render/compile_process.h"
#include "render/compile_worker.h"
#include "render/gl_stages.h"
#include "render/live_program.h"
#include "render/program_cache.h"

#include <chrono>
#include <cstdlib>
#include <thread>

namespace sdfvj {


Program::~Program() {
    if (id_) glDeleteProgram(id_);
    if (evalCode_) glDeleteBuffers(1, &evalCode_);
    if (evalConst_) glDeleteBuffers(1, &evalConst_);
}

namespace {
double NowMs() {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
}  // namespace

bool Program::Build(const ShaderSource& src, RenderPath path, std::string* log) {
    PendingProgram pending;
    if (!pending.BeginFromCache(src, path)) pending.Begin(src, path);
    return pending.Finish(this, log);
}

void Program::Adopt(unsigned id, RenderPath path, const ShaderSource& src, const ProgramOrigin& origin) {
    if (id_) glDeleteProgram(id_);
    id_ = id;
    path_ = path;
    source_ = src;
    origin_ = origin;
    literals_ = src.literals;
    uniforms_.clear();
    group_[0] = group_[1] = 8;
    group_[2] = 1;
    if (path == RenderPath::Compute) glGetProgramiv(id, GL_COMPUTE_WORK_GROUP_SIZE, group_);
    frameState_ = path == RenderPath::Compute &&
                  glGetProgramResourceIndex(id, GL_SHADER_STORAGE_BLOCK, "SceneStateOut") != GL_INVALID_INDEX;
    quadReflections_ = path == RenderPath::Compute && glGetUniformLocation(id, "u_quadReflections") >= 0;
    quadDefer_ = quadReflections_ && glGetProgramResourceIndex(id, GL_SHADER_STORAGE_BLOCK, "QuadDeferred") != GL_INVALID_INDEX;
    GLint count = 0;
    glGetProgramiv(id, GL_ACTIVE_UNIFORMS, &count);
    for (GLint i = 0; i < count; ++i) {
        char name[256];
        GLint size = 0;
        GLenum type = 0;
        glGetActiveUniform(id, (GLuint)i, sizeof name, nullptr, &size, &type, name);
        uniforms_[name] = Slot{glGetUniformLocation(id, name), type};
    }
}

namespace {
CompileWorker* g_worker = nullptr;   // set by the render thread before any PendingProgram runs
CompileWorker* g_loader = nullptr;   // likewise; its context shares objects with the render thread's
}  // namespace

void PendingProgram::SetWorker(CompileWorker* worker) { g_worker = worker; }
void PendingProgram::SetLoader(CompileWorker* loader) { g_loader = loader; }
CompileWorker* PendingProgram::Loader() { return g_loader; }
CompileWorker* PendingProgram::Worker() { return g_worker; }

bool PendingProgram::StartLoad(unsigned format, std::vector<uint8_t> binary) const {
    loadDone_ = false;
    loadProgram_ = 0;
    loadTicket_ = g_loader->SubmitLoad(format, std::move(binary), path_, source_.text.find("rgba32f") != std::string::npos);
    return PollLoad();
}

bool PendingProgram::PollLoad() const {
    if (!loadDone_ && g_loader) {
        CompileWorker::Result r;
        loadDone_ = g_loader->Poll(loadTicket_, &r);
        if (loadDone_) {
            loadProgram_ = r.program;
            loadMs_ = r.buildMs;
        }
    }
    if (loadDone_ && !loadProgram_) {
        // The driver refused the binary on the loader's context (a driver update since the cache
        // stored it, or a binary it cannot take): built again as if there were no binary, with
        // nothing said. The object is never const (a member of LiveProgram), only this query is.
        auto* self = const_cast<PendingProgram*>(this);
        const BuildTier tier = origin_.quickTier ? BuildTier::Quick : BuildTier::Optimized;
        loadTicket_ = 0;
        loadDone_ = false;
        if (loadFromCache_) {
            ForgetCachedProgram(source_.text, path_);
            self->Begin(source_, path_, tier);
        } else {
            CompileProcess* process = self->process_;   // its binary would be refused again
            self->process_ = nullptr;
            self->Begin(source_, path_, tier);
            self->process_ = process;
        }
        return Ready();
    }
    return loadDone_;
}

PendingProgram::~PendingProgram() { Cancel(); }

void PendingProgram::Cancel() {
    if (loadTicket_) {
        if (loadDone_) {
            if (loadProgram_) glDeleteProgram(loadProgram_);   // shared with the loader's context
        } else if (g_loader) {
            g_loader->Forget(loadTicket_);
        }
        loadTicket_ = 0;
        loadDone_ = false;
        loadProgram_ = 0;
    }
    if (procTicket_) {
        if (!procDone_ && process_) process_->Forget(procTicket_);
        procTicket_ = 0;
        procDone_ = false;
        procDied_ = false;
        workerBinary_.clear();
    }
    if (ticket_) {
        if (workerDone_) {
            if (workerProgram_) glDeleteProgram(workerProgram_);
        } else if (g_worker) {
            g_worker->Forget(ticket_);
        }
        ticket_ = 0;
        workerDone_ = false;
        workerProgram_ = 0;
    }
    for (unsigned s : stages_) glDeleteShader(s);
    stages_.clear();
    if (id_) glDeleteProgram(id_);
    id_ = 0;
}

bool PendingProgram::ParallelCompileAvailable() {
    static const bool available = epoxy_has_gl_extension("GL_KHR_parallel_shader_compile") ||
                                  epoxy_has_gl_extension("GL_ARB_parallel_shader_compile");
    return available;
}

bool PendingProgram::BeginFromCache(const ShaderSource& src, RenderPath path) {
    Cancel();
    const double t0 = NowMs();
    if (g_loader) {
        // The loader loads it and uses it once; the render thread only reads the file here.
        unsigned format = 0;
        std::vector<uint8_t> binary;
        if (!ReadCachedBinary(src.text, path, &format, &binary)) return false;
        source_ = src;
        path_ = path;
        origin_ = ProgramOrigin{};
        origin_.fromCache = true;
        beganAt_ = t0;
        loadFromCache_ = true;
        StartLoad(format, std::move(binary));
        origin_.beginCallMs = NowMs() - t0;
        return true;
    }
    const unsigned id = LoadCachedProgram(src.text, path);
    if (!id) return false;
    source_ = src;
    path_ = path;
    id_ = id;
    origin_ = ProgramOrigin{};
    origin_.fromCache = true;
    origin_.buildMs = NowMs() - t0;
    return true;
}

void PendingProgram::Begin(const ShaderSource& src, RenderPath path, BuildTier tier) {
    Cancel();
    source_ = src;
    path_ = path;
    origin_ = ProgramOrigin{};
    origin_.quickTier = tier == BuildTier::Quick;
    beganAt_ = NowMs();
    // Only optimized programs go to the disk cache: a quick tier from there would run slower forever.
    const bool store = tier == BuildTier::Optimized && ProgramCacheEnabled();
    const std::string quickText = tier == BuildTier::Quick ? QuickTierText(src.text) : std::string();
    const std::string& text = tier == BuildTier::Quick ? quickText : source_.text;
    if (process_ && process_->Usable()) {
        procTicket_ = process_->Submit(text, path, store);
        if (procTicket_) {
            origin_.beginCallMs = NowMs() - beganAt_;
            return;
        }
    }
    if (g_worker) {
        ticket_ = g_worker->Submit(text, path, store);
        origin_.beginCallMs = NowMs() - beganAt_;
        return;
    }
    if (ParallelCompileAvailable()) glMaxShaderCompilerThreadsKHR(0xFFFFFFFFu);   // driver's choice
    id_ = glCreateProgram();
    if (store || retrievable_) glProgramParameteri(id_, GL_PROGRAM_BINARY_RETRIEVABLE_HINT, GL_TRUE);
    auto stage = [&](GLenum kind, const char* stageText) {
        GLuint s = glCreateShader(kind);
        glShaderSource(s, 1, &stageText, nullptr);
        glCompileShader(s);   // returns at once where the driver compiles in parallel
        glAttachShader(id_, s);
        stages_.push_back(s);
    };
    if (path == RenderPath::Compute) {
        stage(GL_COMPUTE_SHADER, text.c_str());
    } else {
        stage(GL_VERTEX_SHADER, FullscreenVertexShader());
        stage(GL_FRAGMENT_SHADER, text.c_str());
    }
    glLinkProgram(id_);
    origin_.beginCallMs = NowMs() - beganAt_;
}

bool PendingProgram::Ready() const {
    if (loadTicket_) return PollLoad();
    if (procTicket_) {
        if (!procDone_ && process_) {
            CompileProcess::Result r;
            procDone_ = process_->Poll(procTicket_, &r);
            if (procDone_) {
                procDied_ = r.died || (r.linked && r.noBinary);
                workerLog_ = std::move(r.log);
                workerBinary_ = std::move(r.binary);
                workerFormat_ = r.format;
                workerMs_ = r.buildMs;
                workerNoBinary_ = !r.linked;   // here: the compile failed, the log says why
            }
        }
        if (procDone_ && procDied_) {
            // The server died before answering: this build starts again in this process, the
            // way it would have without a server (never a frame blocked for the whole compile).
            // The object is never const (a member of LiveProgram), only this query is.
            auto* self = const_cast<PendingProgram*>(this);
            CompileProcess* process = self->process_;
            self->process_ = nullptr;
            self->Begin(source_, path_, origin_.quickTier ? BuildTier::Quick : BuildTier::Optimized);
            self->process_ = process;
            return Ready();
        }
        if (procDone_ && !workerNoBinary_ && process_ && process_->HandOverSource()) {
            // Source hand-over: built in the server (and in the driver's disk cache); compiled
            // here from the same text, as the server did (retrievable), for that cache to serve.
            auto* self = const_cast<PendingProgram*>(this);
            CompileProcess* process = self->process_;
            self->process_ = nullptr;
            self->procTicket_ = 0;
            procDone_ = false;
            self->workerBinary_.clear();
            self->retrievable_ = true;
            self->Begin(source_, path_, origin_.quickTier ? BuildTier::Quick : BuildTier::Optimized);
            self->retrievable_ = false;
            self->process_ = process;
            self->origin_.fromProcess = true;
            return Ready();
        }
        if (procDone_ && g_loader && !workerNoBinary_ && !workerBinary_.empty()) {
            // The server's binary goes to the loader, which loads it and uses it once.
            auto* self = const_cast<PendingProgram*>(this);
            self->procTicket_ = 0;
            procDone_ = false;
            self->origin_.buildMs = workerMs_;
            self->origin_.fromProcess = true;
            loadFromCache_ = false;
            return StartLoad(workerFormat_, std::move(workerBinary_));
        }
        return procDone_;
    }
    if (ticket_) {
        if (!workerDone_ && g_worker) {
            CompileWorker::Result r;
            workerDone_ = g_worker->Poll(ticket_, &r);
            if (workerDone_) {
                workerProgram_ = r.program;
                workerLog_ = std::move(r.log);
                workerBinary_ = std::move(r.binary);
                workerFormat_ = r.format;
                workerMs_ = r.buildMs;
                workerNoBinary_ = r.noBinary;
            }
        }
        return workerDone_;
    }
    if (!id_) return false;
    if (!ParallelCompileAvailable()) return true;
    GLint done = GL_TRUE;
    glGetProgramiv(id_, GL_COMPLETION_STATUS_KHR, &done);
    return done == GL_TRUE;
}

// The compile process could not serve this program (it died, gave no binary, or the driver
// refused the binary): compiled here instead, with nothing said to the performer.
bool PendingProgram::FinishInProcess(Program* into, std::string* log) {
    CompileProcess* process = process_;
    CompileWorker* worker = g_worker;
    process_ = nullptr;
    g_worker = nullptr;
    const bool quick = origin_.quickTier;
    Begin(source_, path_, quick ? BuildTier::Quick : BuildTier::Optimized);
    g_worker = worker;
    process_ = process;
    return Finish(into, log);
}

bool PendingProgram::Finish(Program* into, std::string* log) {
    const double finishAt = NowMs();
    // Each Ready() may move the build on (server -> loader; a refused binary -> a compile).
    while ((procTicket_ || loadTicket_) && !Ready()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    if (loadTicket_) {   // loaded and used once on the loader's context
        loadTicket_ = 0;
        loadDone_ = false;
        if (loadFromCache_) origin_.buildMs = loadMs_;
        origin_.usedBeforeHandOver = true;
        origin_.loadMs = loadMs_;
        origin_.finishCallMs = NowMs() - finishAt;
        into->Adopt(loadProgram_, path_, source_, origin_);
        loadProgram_ = 0;
        return true;
    }
    if (procTicket_) {   // (a server that died has become an in-process build by now)
        procTicket_ = 0;
        procDone_ = false;
        if (procDied_) {
            procDied_ = false;
            return FinishInProcess(into, log);
        }
        if (workerNoBinary_) {   // the compile failed in the server
            workerNoBinary_ = false;
            *log = MapCompileLog(workerLog_, source_);
            if (log->empty()) *log = "shader failed to compile with no message from the driver";
            return false;
        }
        const GLuint prog = LoadProgramBinary(workerFormat_, workerBinary_.data(), workerBinary_.size());
        workerBinary_.clear();
        if (!prog) return FinishInProcess(into, log);   // refused: compiled here
        origin_.buildMs = workerMs_;
        origin_.fromProcess = true;
        origin_.finishCallMs = NowMs() - finishAt;
        into->Adopt(prog, path_, source_, origin_);
        return true;
    }
    if (ticket_) {
        while (!Ready()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
        ticket_ = 0;
        workerDone_ = false;
        origin_.buildMs = workerMs_;
        if (workerNoBinary_) {
            // Binary hand-over, but the driver gave no binary: compile here instead (this frame
            // waits for it, a reload still happens).
            workerNoBinary_ = false;
            CompileWorker* worker = g_worker;
            g_worker = nullptr;
            const ProgramOrigin origin = origin_;
            Begin(source_, path_, origin.quickTier ? BuildTier::Quick : BuildTier::Optimized);
            g_worker = worker;
            return Finish(into, log);
        }
        if (!workerProgram_ && !workerBinary_.empty()) {
            // Binary hand-over: load what the worker's own context compiled and linked.
            const GLuint prog = LoadProgramBinary(workerFormat_, workerBinary_.data(), workerBinary_.size());
            workerBinary_.clear();
            if (!prog) {
                *log = "the driver rejected the compile thread's program binary";
                return false;
            }
            origin_.finishCallMs = NowMs() - finishAt;
            into->Adopt(prog, path_, source_, origin_);
            return true;
        }
        if (!workerProgram_) {
            *log = MapCompileLog(workerLog_, source_);
            return false;
        }
        // The worker's glFinish happened before it reported, so the program is complete.
        origin_.finishCallMs = NowMs() - finishAt;
        into->Adopt(workerProgram_, path_, source_, origin_);
        workerProgram_ = 0;
        return true;
    }
    if (!id_) {
        *log = "no program was being built";
        return false;
    }
    std::string raw;
    for (unsigned s : stages_) {
        GLint ok = 0;
        glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
        if (!ok) raw += ShaderLog(s);
    }
    GLint linked = 0;
    glGetProgramiv(id_, GL_LINK_STATUS, &linked);
    if (raw.empty() && !linked) raw = ProgramLog(id_);
    const bool compiled = !stages_.empty();   // not from the cache
    for (unsigned s : stages_) glDeleteShader(s);
    stages_.clear();
    if (!linked || !raw.empty()) {
        glDeleteProgram(id_);
        id_ = 0;
        *log = MapCompileLog(raw, source_);
        if (log->empty()) *log = "shader failed to compile with no message from the driver";
        return false;   // `into` keeps the program it had
    }
    if (compiled) {
        origin_.buildMs = NowMs() - beganAt_;
        if (!origin_.quickTier) StoreCachedProgram(id_, source_.text, path_);
    }
    origin_.finishCallMs = NowMs() - finishAt;
    into->Adopt(id_, path_, source_, origin_);
    id_ = 0;
    return true;
}

std::vector<std::string> Program::ActiveUniforms() const {
    std::vector<std::string> names;
    for (const auto& [n, _] : uniforms_) names.push_back(n);
    return names;
}

void Program::Set(const std::string& name, float x) const {
    auto it = uniforms_.find(name);
    if (it == uniforms_.end() || it->second.location < 0) return;
    if (it->second.type == GL_INT || it->second.type == GL_BOOL) glProgramUniform1i(id_, it->second.location, (int)x);
    else if (it->second.type == GL_FLOAT) glProgramUniform1f(id_, it->second.location, x);
}

void Program::Set(const std::string& name, float x, float y) const {
    auto it = uniforms_.find(name);
    if (it != uniforms_.end() && it->second.type == GL_FLOAT_VEC2) glProgramUniform2f(id_, it->second.location, x, y);
}

void Program::Set(const std::string& name, float x, float y, float z) const {
    auto it = uniforms_.find(name);
    if (it != uniforms_.end() && it->second.type == GL_FLOAT_VEC3) glProgramUniform3f(id_, it->second.location, x, y, z);
}

void Program::SetFloats(const std::string& name, const std::vector<float>& values) const {
    auto it = uniforms_.find(name + "[0]");
    if (it == uniforms_.end() || it->second.location < 0 || it->second.type != GL_FLOAT || values.empty()) return;
    glProgramUniform1fv(id_, it->second.location, (GLsizei)values.size(), values.data());   // past the active size: ignored
}

}  // namespace sdfvj
