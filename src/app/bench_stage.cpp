#include "app/bench_stage.h"

#include <atomic>
#include <chrono>
#include <cstdio>

#include "render/compile_worker.h"
#include "render/program_cache.h"
#include "scene/scene.h"
#include "shader/shader.h"

namespace sdfvj {

GlThread::GlThread(HeadlessContext* context) {
    thread_ = std::thread([this, context] { Loop(context); });
    Run([] {});   // started, the context current (or not: Ok() says)
}

GlThread::~GlThread() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        quit_ = true;
    }
    wake_.notify_all();
    thread_.join();
}

void GlThread::Post(std::function<void()> task) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        tasks_.push_back(std::move(task));
        ++posted_;
    }
    wake_.notify_all();
}

void GlThread::Run(std::function<void()> task) {
    uint64_t mine = 0;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        tasks_.push_back(std::move(task));
        mine = ++posted_;
    }
    wake_.notify_all();
    std::unique_lock<std::mutex> lock(mutex_);
    done_.wait(lock, [&] { return finished_ >= mine; });
}

void GlThread::Loop(HeadlessContext* context) {
    ok_ = context->MakeCurrent();
    for (;;) {
        std::function<void()> task;
        {
            std::unique_lock<std::mutex> lock(mutex_);
            wake_.wait(lock, [&] { return quit_ || !tasks_.empty(); });
            if (tasks_.empty()) break;   // quit, and nothing left to run
            task = std::move(tasks_.front());
            tasks_.pop_front();
        }
        if (ok_) task();
        {
            std::lock_guard<std::mutex> lock(mutex_);
            ++finished_;
        }
        done_.notify_all();
    }
    context->ReleaseCurrent();
}

StageRun::~StageRun() {
    auto end = [](std::unique_ptr<Stage>& s) {
        if (!s) return;
        if (s->thread) s->thread->Run([&s] { s->renderer.reset(); s->program.reset(); });
        s->thread.reset();
    };
    end(onScreen_);
    end(next_);
    for (auto& s : retired_) end(s);
    if (main_) {
        main_->MakeCurrent();
        present_.reset();
    }
}

std::string StageRun::Details() const {
    std::string line = "stages on screen, on their own threads: load (or compile) + first use / first real frame ms:";
    char buf[64];
    for (const auto& [use, frame] : stageTimes_) {
        std::snprintf(buf, sizeof buf, " %.1f / %.1f;", use, frame);
        line += buf;
    }
    return line;
}

bool StageRun::NewStage(std::unique_ptr<Stage>* out, std::string* error) {
    auto s = std::make_unique<Stage>();
    if (!s->context.CreateShared(*main_, error, true)) return false;
    s->thread = std::make_unique<GlThread>(&s->context);
    if (!s->thread->Ok()) {
        *error = "cannot make a stage's context current on its thread";
        return false;
    }
    *out = std::move(s);
    return true;
}

bool StageRun::Start(HeadlessContext& gl, const std::string& scenePath, RenderPath path, int width, int height, std::string* error) {
    main_ = &gl;
    w_ = width;
    h_ = height;
    ShaderSource src;
    SceneInfo scene;
    if (!LoadScene(scenePath, &scene, error) || !AssembleProgram(scene, VariantKey{scenePath, scene.effects, path}, &src, error))
        return false;
    if (!NewStage(&onScreen_, error)) return false;
    Stage* s = onScreen_.get();
    s->scene = scene;
    bool ok = false;
    s->thread->Run([&] {
        s->program = std::make_unique<Program>();
        s->renderer = std::make_unique<FrameRenderer>();
        ok = s->program->Build(src, path, error) && s->renderer->Resize(w_, h_, error);
        if (ok) s->renderer->Draw(*s->program, s->scene, lastInputs_);
        glFinish();
    });
    if (!ok) return false;
    main_->MakeCurrent();
    present_ = std::make_unique<PresentTarget>();
    present_->Create(w_, h_);
    return true;
}

bool StageRun::Update(const std::vector<std::string>& changed, const std::string& scenePath, RenderPath path, std::string* error) {
    if (!changed.empty()) {
        SceneInfo sc;
        ShaderSource src;
        if (LoadScene(scenePath, &sc, error) && AssembleProgram(sc, VariantKey{scenePath, sc.effects, path}, &src, error)) {
            if (ticket_) process_->Forget(ticket_);
            ticket_ = process_ && process_->Usable() ? process_->Submit(src.text, path, false) : 0;
            pendingSrc_ = src;
            pendingScene_ = sc;
            // No compile process (Mesa with its disk cache off gives no binaries): the new stage's
            // thread compiles it on its own context, which holds no lock of the render thread's there.
            if (!ticket_ && !StartStage(0, {}, path, error)) return false;
        }
    }
    if (ticket_) {
        CompileProcess::Result r;
        if (!process_->Poll(ticket_, &r)) return false;
        ticket_ = 0;
        if (!r.linked && !r.died && !r.noBinary) {
            *error = r.log;
            return false;
        }
        // A server that died or gave no binary: the stage compiles it.
        const bool binary = r.linked && !r.noBinary && !r.died;
        if (!StartStage(binary ? r.format : 0, binary ? std::move(r.binary) : std::vector<uint8_t>(), path, error)) return false;
        return false;
    }
    if (!next_ || !next_->ready) return false;
    if (!next_->error.empty()) {
        *error = next_->error;
        retired_.push_back(std::move(next_));
        return false;
    }
    lastStageMs_ = next_->ms;
    stageTimes_.emplace_back(next_->useMs, next_->firstFrameMs);
    Stage* old = onScreen_.get();
    old->thread->Post([old] { old->renderer.reset(); old->program.reset(); });
    retired_.push_back(std::move(onScreen_));
    onScreen_ = std::move(next_);
    return true;
}

bool StageRun::StartStage(unsigned format, std::vector<uint8_t> binaryBytes, RenderPath path, std::string* error) {
    if (next_) retired_.push_back(std::move(next_));   // superseded before it was shown
    if (!NewStage(&next_, error)) return false;
    Stage* s = next_.get();
    s->scene = pendingScene_;
    const ShaderSource src = pendingSrc_;
    const FrameInputs in = lastInputs_;
    const int w = w_, h = h_;
    auto binary = std::make_shared<std::vector<uint8_t>>(std::move(binaryBytes));
    s->thread->Post([s, src, in, w, h, binary, format, path] {
        const auto t0 = std::chrono::steady_clock::now();
        s->program = std::make_unique<Program>();
        if (binary->empty()) {
            if (!s->program->Build(src, path, &s->error)) s->program.reset();
        } else {
            const unsigned id = LoadProgramBinary(format, binary->data(), binary->size());
            if (id) {
                PrimeProgram(id, path, src.text.find("rgba32f") != std::string::npos);
                s->program->Adopt(id, path, src, ProgramOrigin{});
            } else if (!s->program->Build(src, path, &s->error)) {   // refused: compiled here
                s->program.reset();
            }
        }
        glFinish();
        s->useMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        if (s->program) {
            s->renderer = std::make_unique<FrameRenderer>();
            if (!s->renderer->Resize(w, h, &s->error)) s->error = "stage target: " + s->error;
            else s->renderer->Draw(*s->program, s->scene, in);   // its first real frame, here
            glFinish();
        } else if (s->error.empty()) {
            s->error = "the stage could not build the program";
        }
        s->ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        s->firstFrameMs = s->ms - s->useMs;
        s->ready = true;
    });
    return true;
}

void StageRun::Draw(const FrameInputs& in) {
    lastInputs_ = in;
    Stage* s = onScreen_.get();
    GLsync done = nullptr;
    s->thread->Run([s, &in, &done] {
        s->renderer->Draw(*s->program, s->scene, in);
        done = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
        glFlush();
    });
    glWaitSync(done, 0, GL_TIMEOUT_IGNORED);
    glDeleteSync(done);
    present_->Blit(s->renderer->Texture());
}

}  // namespace sdfvj
