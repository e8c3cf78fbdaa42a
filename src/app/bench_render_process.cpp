#include "app/bench_render_process.h"

#include <epoxy/gl.h>

#include <cstdio>

namespace sdfvj {

RenderProcessRun::~RenderProcessRun() {
    // The render context is current (the bench ends on it): textures and images are freed here.
    onScreen_.reset();
    next_.process.reset();
    quick_.process.reset();
    spares_.clear();
    retired_.clear();
    present_.reset();
}

std::unique_ptr<RenderProcess> RenderProcessRun::Spawn(std::string* error) {
    auto p = std::make_unique<RenderProcess>();
    if (!p->Start(error)) return nullptr;
    return p;
}

void RenderProcessRun::Retire(std::unique_ptr<RenderProcess> p) {
    if (!p) return;
    p->Stop();
    retired_.push_back(std::move(p));
}

bool RenderProcessRun::Start(HeadlessContext& gl, const std::string& scenePath, RenderPath path, int width, int height, std::string* error) {
    w_ = width;
    h_ = height;
    for (int attempt = 0; attempt < 2; ++attempt) {
        onScreen_ = Spawn(error);
        if (!onScreen_ || !onScreen_->Load(scenePath, path, w_, h_, transport_)) {
            if (error->empty()) *error = "the render process did not start";
            return false;
        }
        RenderProcess::Ready r;
        if (!onScreen_->PollReady(&r, 120000)) {
            *error = "the render process did not answer in 120 s";
            return false;
        }
        if (!r.text.empty()) note_ = r.text;
        if (r.ok) {
            transport_ = r.transport;
            break;
        }
        if (r.transport == FrameTransport::Shm) {   // the program itself failed
            *error = r.text;
            return false;
        }
        // The server shared an image this context could not import: shared memory from now on.
        note_ = std::string(FrameTransportName(r.transport)) + " import refused here (" + r.text + "): shared memory instead";
        transport_ = FrameTransport::Shm;
        Retire(std::move(onScreen_));
    }
    if (!onScreen_ || !onScreen_->Texture()) {
        *error = "the render process gave no frame: " + note_;
        return false;
    }
    gl.MakeCurrent();
    present_ = std::make_unique<PresentTarget>();
    present_->Create(w_, h_);
    for (int i = 0; i < (tiered_ ? 2 : 1); ++i) {   // spares open their contexts now, off the save's path
        spares_.push_back(Spawn(error));
        if (!spares_.back()) return false;
    }
    return true;
}

std::unique_ptr<RenderProcess> RenderProcessRun::TakeSpare(std::string* error) {
    if (spares_.empty()) return Spawn(error);
    auto p = std::move(spares_.back());
    spares_.pop_back();
    return p;
}

bool RenderProcessRun::Promote(Candidate& c, std::string* error) {
    if (!c.process) return false;
    if (!c.asked) {
        RenderProcess::Ready r;
        if (!c.process->PollReady(&r, 0)) return false;
        if (!r.ok) {
            *error = r.text;
            Retire(std::move(c.process));
            return false;
        }
        lastMs_ = r.buildMs + r.useMs + r.firstFrameMs;
        shown_.push_back(r);
        shownQuick_.push_back(c.quick);
        if (pipelined_) {   // its first frame with the inputs of now, drawn while the one on screen goes on
            c.asked = c.process->Request(lastInputs_);
            if (c.asked) return false;
        }
    } else {
        if (!c.process->Arrived()) return false;
        c.asked = false;
        fresh_ = c.process->Collect(0);
    }
    Retire(std::move(onScreen_));
    onScreen_ = std::move(c.process);
    onScreenQuick_ = c.quick;
    return true;
}

bool RenderProcessRun::Update(const std::vector<std::string>& changed, const std::string& scenePath, RenderPath path, std::string* error) {
    for (size_t i = 0; i < retired_.size();)
        if (retired_[i]->TryReap()) retired_.erase(retired_.begin() + (long)i);
        else ++i;
    if (!changed.empty()) {
        for (Candidate* c : {&next_, &quick_}) {   // superseded before they were shown
            Retire(std::move(c->process));
            c->asked = false;
        }
        for (Candidate* c : {&next_, &quick_}) {
            if (c == &quick_ && !tiered_) break;
            c->process = TakeSpare(error);
            if (!c->process || !c->process->Load(scenePath, path, w_, h_, transport_, c->quick)) {
                if (error->empty()) *error = "the render process for the save did not start";
                return false;
            }
        }
        while ((int)spares_.size() < (tiered_ ? 2 : 1)) {   // for the next save, opening their contexts now
            auto p = Spawn(error);
            if (!p) break;
            spares_.push_back(std::move(p));
        }
    }
    if (Promote(next_, error)) {
        Retire(std::move(quick_.process));   // the optimized program came first or follows: the quick one is done
        quick_.asked = false;
        return true;
    }
    return Promote(quick_, error);
}

void RenderProcessRun::Draw(const FrameInputs& in) {
    RenderProcess& p = *onScreen_;
    lastInputs_ = in;
    // A server just put on screen: its first frame is here already (pipelined), or drawn now.
    const bool ok = fresh_ || (p.Outstanding() ? p.Collect() : p.DrawFrame(in));
    fresh_ = false;
    if (!ok) {
        ++failedFrames_;   // the last frame stays on screen
        return;
    }
    present_->Blit(p.Texture());
    if (!pipelined_) return;
    // The blit must have read the shared image before the server writes the next frame into it.
    GLsync read = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    glClientWaitSync(read, GL_SYNC_FLUSH_COMMANDS_BIT, 1000000000);
    glDeleteSync(read);
    if (!p.Request(in)) ++failedFrames_;
}

std::string RenderProcessRun::Details() const {
    std::string line = std::string("render processes: ") + (pipelined_ ? "pipelined (the frame shown is the one asked for a frame before)" : "synchronous") + "; frames handed over by " +
                       (transport_ == FrameTransport::VkMemory ? "a Vulkan-allocated image both import (on the GPU)"
                        : transport_ == FrameTransport::DmaBuf ? "dma-buf (on the GPU)" : "shared memory (a copy each way)") +
                       (note_.empty() ? "" : "; " + note_) + "; " + (tiered_ ? "tiered (a quick build in one process, the optimized one in another)" : "untiered") +
                       "; each one on screen: compile + link / first use / first frame ms:";
    char buf[80];
    for (size_t i = 0; i < shown_.size(); ++i) {
        const RenderProcess::Ready& r = shown_[i];
        std::snprintf(buf, sizeof buf, " %s%.1f / %.1f / %.1f;", shownQuick_[i] ? "quick " : "", r.buildMs, r.useMs, r.firstFrameMs);
        line += buf;
    }
    if (failedFrames_) line += " frames the server did not deliver: " + std::to_string(failedFrames_);
    return line;
}

}  // namespace sdfvj
