#include "render/compile_worker.h"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <epoxy/gl.h>

#include <chrono>

#include "render/gl_stages.h"
#include "render/program_cache.h"
#include "render/render.h"

namespace sdfvj {

unsigned CompileLinkHere(const std::string& text, RenderPath path, std::string* rawLog, bool retrievable) {
    GLuint prog = glCreateProgram();
    if (retrievable) glProgramParameteri(prog, GL_PROGRAM_BINARY_RETRIEVABLE_HINT, GL_TRUE);
    std::vector<GLuint> stages;
    auto stage = [&](GLenum kind, const char* src) {
        GLuint s = glCreateShader(kind);
        glShaderSource(s, 1, &src, nullptr);
        glCompileShader(s);
        GLint ok = 0;
        glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
        if (!ok) *rawLog += ShaderLog(s);
        glAttachShader(prog, s);
        stages.push_back(s);
    };
    if (path == RenderPath::Compute) {
        stage(GL_COMPUTE_SHADER, text.c_str());
    } else {
        stage(GL_VERTEX_SHADER, FullscreenVertexShader());
        stage(GL_FRAGMENT_SHADER, text.c_str());
    }
    GLint linked = 0;
    if (rawLog->empty()) {
        glLinkProgram(prog);
        glGetProgramiv(prog, GL_LINK_STATUS, &linked);
        if (!linked) *rawLog = ProgramLog(prog);
    }
    for (GLuint s : stages) glDeleteShader(s);
    if (!linked) {
        glDeleteProgram(prog);
        if (rawLog->empty()) *rawLog = "shader failed to compile with no message from the driver";
        return 0;
    }
    return prog;
}

void PrimeProgram(unsigned prog, RenderPath path, bool floatImage) {
    // The caller's state the 1x1 use touches is put back (on the render context: the window's
    // framebuffer, viewport and bindings).
    GLint viewport[4], drawFbo = 0, readFbo = 0, current = 0, bound = 0, boundVao = 0;
    glGetIntegerv(GL_VIEWPORT, viewport);
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &drawFbo);
    glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &readFbo);
    glGetIntegerv(GL_CURRENT_PROGRAM, &current);
    glGetIntegerv(GL_TEXTURE_BINDING_2D, &bound);
    glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &boundVao);
    GLuint tex = 0, fbo = 0, vao = 0, cone = 0, state = 0;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexStorage2D(GL_TEXTURE_2D, 1, floatImage ? GL_RGBA32F : GL_RGBA8, 1, 1);
    glUseProgram(prog);
    if (path == RenderPath::Compute) {
        glBindImageTexture(0, tex, 0, GL_FALSE, 0, GL_WRITE_ONLY, floatImage ? GL_RGBA32F : GL_RGBA8);
        // The cone pre-pass's image (main_comp.glsl, unit 1) bound as FrameRenderer binds it: a
        // driver that finishes a program for the state of its first use sees the frame's state.
        glGenTextures(1, &cone);
        glBindTexture(GL_TEXTURE_2D, cone);
        glTexStorage2D(GL_TEXTURE_2D, 1, GL_R32F, 1, 1);
        glBindImageTexture(1, cone, 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32F);
        // And the scene's frame state (FrameRenderer, main_comp.glsl SCENE_STATE_FRAME), as a uniform block.
        state = CreateSceneStateBuffer();
        BindSceneStateBuffer(state);
        glDispatchCompute(1, 1, 1);
    } else {
        glGenFramebuffers(1, &fbo);
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex, 0);
        glGenVertexArrays(1, &vao);
        glBindVertexArray(vao);
        glViewport(0, 0, 1, 1);
        GLboolean blend = glIsEnabled(GL_BLEND);   // put back below, as the rest
        SetOverwriteBlend();   // the state every draw of it has (llvmpipe compiles per state)
        glDrawArrays(GL_TRIANGLES, 0, 3);
        if (blend) glEnable(GL_BLEND);
        else glDisable(GL_BLEND);
    }
    glFinish();
    if (vao) glDeleteVertexArrays(1, &vao);
    if (fbo) glDeleteFramebuffers(1, &fbo);
    glDeleteTextures(1, &tex);
    if (cone) glDeleteTextures(1, &cone);
    if (state) glDeleteBuffers(1, &state);
    glViewport(viewport[0], viewport[1], viewport[2], viewport[3]);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, (GLuint)drawFbo);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, (GLuint)readFbo);
    glUseProgram((GLuint)current);
    glBindTexture(GL_TEXTURE_2D, (GLuint)bound);
    glBindVertexArray((GLuint)boundVao);
}

CompileWorker::CompileWorker(std::function<bool()> bindContext, bool handOverBinary, std::function<void()> releaseContext)
    : handOverBinary_(handOverBinary) {
    thread_ = std::thread([this, bindContext, releaseContext] { Loop(bindContext, releaseContext); });
}

CompileWorker::~CompileWorker() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
    }
    wake_.notify_all();
    if (thread_.joinable()) thread_.join();
}

bool CompileWorker::Ok() {
    std::unique_lock<std::mutex> lock(mutex_);
    started_.wait(lock, [&] { return state_ != 0; });
    return state_ == 1;
}

uint64_t CompileWorker::Submit(const std::string& text, RenderPath path, bool store) {
    std::lock_guard<std::mutex> lock(mutex_);
    uint64_t t = next_++;
    jobs_.push_back(Job{t, text, path, store});
    wake_.notify_all();
    return t;
}

uint64_t CompileWorker::SubmitLoad(unsigned format, std::vector<uint8_t> binary, RenderPath path, bool floatImage) {
    std::lock_guard<std::mutex> lock(mutex_);
    uint64_t t = next_++;
    Job job{t, std::string(), path, false};
    job.load = true;
    job.format = format;
    job.binary = std::move(binary);
    job.floatImage = floatImage;
    jobs_.push_back(std::move(job));
    wake_.notify_all();
    return t;
}

bool CompileWorker::Poll(uint64_t ticket, Result* result) {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = done_.find(ticket);
    if (it == done_.end()) return false;
    *result = std::move(it->second);
    done_.erase(it);
    return true;
}

void CompileWorker::Forget(uint64_t ticket) {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = done_.find(ticket);
    if (it != done_.end()) {
        forgotten_[ticket] = true;   // delete on the worker's context
        wake_.notify_all();
    } else {
        forgotten_[ticket] = true;
    }
}

void CompileWorker::TrimSoon() {
    if (trimAfterJobs_.load()) trimAt_ = std::chrono::steady_clock::now() + std::chrono::milliseconds(kTrimDelayMs);
}

void CompileWorker::Loop(std::function<bool()> bind, std::function<void()> release) {
    // Compiles yield the CPU to the frame: on llvmpipe both share the same few cores, and a
    // stream of reloads or effect toggles must not starve drawing (the stage soak measured
    // frame gaps of over a second while compiles ran at the render thread's priority).
    setpriority(PRIO_PROCESS, (id_t)syscall(SYS_gettid), 10);
    lastTrim_ = std::chrono::steady_clock::now();
    const bool ok = bind();
    {
        std::lock_guard<std::mutex> lock(mutex_);
        state_ = ok ? 1 : -1;
    }
    started_.notify_all();
    if (!ok) {
        if (release) release();
        return;
    }
    for (;;) {
        Job job;
        {
            std::unique_lock<std::mutex> lock(mutex_);
            // Programs nobody wants any more are deleted here, on a context that shares them.
            for (auto it = forgotten_.begin(); it != forgotten_.end();) {
                auto d = done_.find(it->first);
                if (d != done_.end()) {
                    if (d->second.program) glDeleteProgram(d->second.program);
                    done_.erase(d);
                    it = forgotten_.erase(it);
                } else {
                    ++it;
                }
            }
            auto ready = [&] { return stop_ || !jobs_.empty(); };
            if (trimAt_) {
                // A trim is due once no job came for kTrimDelayMs, or between two jobs when the last
                // trim is kTrimEveryMs old (a storm of toggles never leaves the queue that long).
                const auto due = std::min(*trimAt_, lastTrim_ + std::chrono::milliseconds(kTrimEveryMs));
                if (std::chrono::steady_clock::now() >= due || !wake_.wait_until(lock, due, ready)) {
                    trimAt_.reset();
                    lock.unlock();
#if defined(__GLIBC__)
                    malloc_trim(0);
#endif
                    ++trims_;
                    lastTrim_ = std::chrono::steady_clock::now();
                    continue;
                }
            } else {
                wake_.wait(lock, ready);
            }
            if (stop_) {
                // Programs linked here that nobody took: deleted on this context, then the
                // context is let go before the thread ends.
                for (auto& [ticket, done] : done_)
                    if (done.program) glDeleteProgram(done.program);
                done_.clear();
                lock.unlock();
                if (release) release();
                return;
            }
            job = std::move(jobs_.front());
            jobs_.pop_front();
            // A job nobody waits for any more (the performer toggled on before it started) is
            // dropped unbuilt: only the newest request costs a compile.
            if (auto f = forgotten_.find(job.ticket); f != forgotten_.end()) {
                forgotten_.erase(f);
                continue;
            }
        }
        std::string log;
        Done done;
        const auto t0 = std::chrono::steady_clock::now();
        auto elapsedMs = [t0] { return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count(); };
        if (job.load) {
            // A binary to load and use once here (the driver finishes a loaded program at its first
            // use): the render thread adopts a program that has already run.
            done.program = LoadProgramBinary(job.format, job.binary.data(), job.binary.size());
            done.refused = !done.program;
            if (done.program) {
                PrimeProgram(done.program, job.path, job.floatImage);
                done.used = true;
            }
            done.buildMs = elapsedMs();
            std::lock_guard<std::mutex> lock(mutex_);
            done_[job.ticket] = std::move(done);
            TrimSoon();
            continue;
        }
        unsigned prog = CompileLinkHere(job.text, job.path, &log, handOverBinary_ || job.store);
        if (prog && handOverBinary_) {
            // Primed here too: Mesa keys its disk cache on the shader, not the context, so the
            // render context's first draw of the handed-over binary finds this JIT there.
            PrimeProgram(prog, job.path, job.text.find("rgba32f") != std::string::npos);
            GLint length = 0;
            glGetProgramiv(prog, GL_PROGRAM_BINARY_LENGTH, &length);
            done.binary.resize(length > 0 ? (size_t)length : 0);
            GLenum format = 0;
            GLsizei got = 0;
            if (length > 0) glGetProgramBinary(prog, length, &got, &format, done.binary.data());
            done.binary.resize((size_t)got);
            done.format = format;
            glDeleteProgram(prog);
            prog = 0;
            // The driver cannot hand a program over (Mesa gives binaries only with its disk cache
            // on): the render thread compiles this one itself rather than failing the reload.
            done.noBinary = done.binary.empty();
            done.buildMs = elapsedMs();
            if (job.store && !done.noBinary) StoreCachedBinary(done.format, done.binary, job.text, job.path);
        } else if (prog) {
            PrimeProgram(prog, job.path, job.text.find("rgba32f") != std::string::npos);
            done.buildMs = elapsedMs();   // the cache store below is not part of the compile
            if (job.store) StoreCachedProgram(prog, job.text, job.path);
        }
        if (!prog && !done.noBinary && done.binary.empty()) done.buildMs = elapsedMs();   // failed
        done.program = prog;
        done.log = log;
        std::lock_guard<std::mutex> lock(mutex_);
        done_[job.ticket] = std::move(done);
        TrimSoon();
    }
}

}  // namespace sdfvj
