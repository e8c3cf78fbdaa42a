#include "app/bench_adopt.h"

#include <chrono>

#include "scene/scene.h"
#include "shader/shader.h"

namespace sdfvj {

PresentTarget::~PresentTarget() {
    if (readFbo_) glDeleteFramebuffers(1, &readFbo_);
    if (fbo_) glDeleteFramebuffers(1, &fbo_);
    if (tex_) glDeleteTextures(1, &tex_);
}

void PresentTarget::Create(int width, int height) {
    w_ = width;
    h_ = height;
    glGenTextures(1, &tex_);
    glBindTexture(GL_TEXTURE_2D, tex_);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, w_, h_);
    glGenFramebuffers(1, &fbo_);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex_, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

void PresentTarget::Blit(unsigned sharedTexture) {
    attachMs_ = 0;
    if (readTex_ != sharedTexture) {   // a framebuffer here that reads the other context's texture
        const auto t0 = std::chrono::steady_clock::now();
        if (!readFbo_) glGenFramebuffers(1, &readFbo_);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, readFbo_);
        glFramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, sharedTexture, 0);
        glCheckFramebufferStatus(GL_READ_FRAMEBUFFER);   // its validation here, timed with the attach
        readTex_ = sharedTexture;
        attachMs_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    }
    Blit(sharedTexture, readFbo_, attachMs_);
}

void PresentTarget::Blit(unsigned, unsigned readFbo, double attachMs) {
    attachMs_ = attachMs;
    glBindFramebuffer(GL_READ_FRAMEBUFFER, readFbo);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo_);
    glBlitFramebuffer(0, 0, w_, h_, 0, 0, w_, h_, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

AdoptRun::~AdoptRun() {
    worker_.reset();
    for (auto& [context, renderer] : renderers_) {   // container objects belong to their context
        context->MakeCurrent();
        renderer.reset();
    }
    if (main_) {
        main_->MakeCurrent();
        present_.reset();
    }
    program_.reset();
}

bool AdoptRun::Start(HeadlessContext& gl, const std::string& scenePath, RenderPath path, int width, int height, std::string* error) {
    main_ = &gl;
    w_ = width;
    h_ = height;
    ShaderSource src;
    if (!LoadScene(scenePath, &scene_, error) || !AssembleProgram(scene_, VariantKey{scenePath, scene_.effects, path}, &src, error))
        return false;
    program_ = std::make_unique<Program>();
    if (!program_->Build(src, path, error) || !UseContext(&gl, error)) return false;
    present_ = std::make_unique<PresentTarget>();
    present_->Create(w_, h_);
    return true;
}

bool AdoptRun::UseContext(HeadlessContext* c, std::string* error) {
    if (!c->MakeCurrent()) {
        *error = "cannot make the program's context current";
        return false;
    }
    renderers_.emplace_back(c, std::make_unique<FrameRenderer>());
    return renderers_.back().second->Resize(w_, h_, error);
}

bool AdoptRun::StartWorker(std::string* error) {
    contexts_.push_back(std::make_unique<HeadlessContext>());
    HeadlessContext* c = contexts_.back().get();
    if (!c->CreateShared(*main_, error, true)) return false;
    worker_ = std::make_unique<CompileWorker>([c] { return c->MakeCurrent(); }, false, [c] { c->ReleaseCurrent(); });
    workerCtx_ = c;
    return true;
}

bool AdoptRun::Update(const std::vector<std::string>& changed, const std::string& scenePath, RenderPath path, std::string* error) {
    if (!changed.empty()) {
        SceneInfo sc;
        ShaderSource src;
        if (LoadScene(scenePath, &sc, error) && AssembleProgram(sc, VariantKey{scenePath, sc.effects, path}, &src, error)) {
            worker_.reset();   // a newer save supersedes a build still running
            if (processTicket_) process_->Forget(processTicket_);
            processTicket_ = 0;
            pendingSrc_ = src;
            pendingScene_ = sc;
            if (process_ && process_->Usable()) processTicket_ = process_->Submit(src.text, path, false);
            if (!processTicket_) {   // adopt, or a process that cannot take it: compile on the new context
                if (!StartWorker(error)) return false;
                ticket_ = worker_->Submit(src.text, path);
            }
        }
    }
    if (processTicket_) {   // adopt-process: the binary goes to a new context's thread to load and use
        CompileProcess::Result pr;
        if (!process_->Poll(processTicket_, &pr)) return false;
        processTicket_ = 0;
        if (!pr.linked && !pr.died && !pr.noBinary) {
            *error = pr.log;
            return false;
        }
        if (!StartWorker(error)) return false;
        if (pr.linked && !pr.noBinary && !pr.died) ticket_ = worker_->SubmitLoad(pr.format, std::move(pr.binary), path, false);
        else ticket_ = worker_->Submit(pendingSrc_.text, path);   // the process cannot serve: compile there
        return false;
    }
    CompileWorker::Result r;
    if (!worker_ || !worker_->Poll(ticket_, &r)) return false;
    worker_.reset();   // its thread ends and lets go of the context
    if (!r.program) {
        *error = r.log;
        return false;
    }
    if (!UseContext(workerCtx_, error)) return false;
    ProgramOrigin origin;
    origin.buildMs = r.buildMs;
    program_ = std::make_unique<Program>();
    program_->Adopt(r.program, path, pendingSrc_, origin);
    scene_ = pendingScene_;
    main_->MakeCurrent();
    return true;
}

void AdoptRun::Draw(const FrameInputs& in) {
    auto& [context, renderer] = renderers_.back();
    if (context != main_) context->MakeCurrent();
    renderer->Draw(*program_, scene_, in);
    GLsync done = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    glFlush();
    if (context != main_) main_->MakeCurrent();
    glWaitSync(done, 0, GL_TIMEOUT_IGNORED);
    glDeleteSync(done);
    present_->Blit(renderer->Texture());
}

}  // namespace sdfvj
