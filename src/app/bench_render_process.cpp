#include "app/bench_render_process.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "app/bench_support.h"
#include "isf/isf.h"

namespace sdfvj {

namespace {
double Largest(const std::vector<double>& v) { return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()); }
}  // namespace

BenchPostSaves::BenchPostSaves(const std::string& list, const std::filesystem::path& root, uint64_t runNonce) : nonce(runNonce) {
    namespace fs = std::filesystem;
    for (const std::string& f : list.empty() ? std::vector<std::string>{} : SplitIsfList(list)) {
        const fs::path there = fs::path(ResolveIsfPath(f));
        const fs::path here = root / "shaders" / "isf" / there.filename();
        std::error_code ec;
        if (!fs::exists(here)) fs::copy_file(there, here, ec);   // a missing file: the server says so at the load
        paths.push_back(here.string());
    }
    if (paths.empty()) return;
    std::ifstream in(paths.back(), std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    original = ss.str();
}

void BenchPostSaves::Save(int round) const {
    SaveLikeAnEditor(paths.back(), original + "\nfloat benchReloadSave" + std::to_string(nonce) + "_" + std::to_string(round) + "() { return " +
                                       std::to_string(round) + ".0; }\n");
}

RenderProcessRun::~RenderProcessRun() { present_.reset(); }   // the render context is current (the bench ends on it)

bool RenderProcessRun::Start(HeadlessContext& gl, const std::string& scenePath, RenderPath path, int width, int height, std::string* error) {
    w_ = width;
    h_ = height;
    if (importThread_ && servers_.Transport() != FrameTransport::Shm) {
        importContext_ = std::make_unique<HeadlessContext>();
        if (!importContext_->CreateShared(gl, error, true)) return false;
        HeadlessContext* c = importContext_.get();
        importer_ = std::make_unique<ImportThread>([c] { return c->MakeCurrent(); }, [c] { c->ReleaseCurrent(); }, importOptions_);
        if (!importer_->Ok()) {
            *error = "the import thread's context could not be made current";
            return false;
        }
        servers_.SetImporter(importer_.get());
    }
    if (!servers_.Start(LoadOf(scenePath, path), error)) return false;
    if (!servers_.Texture()) {
        *error = "the render process gave no frame: " + servers_.Note();
        return false;
    }
    gl.MakeCurrent();
    present_ = std::make_unique<PresentTarget>();
    present_->Create(w_, h_);
    return true;
}

bool RenderProcessRun::Update(const std::vector<std::string>& changed, const std::string& scenePath, RenderPath path, std::string* error) {
    const auto t0 = Clock::now();
    if (!changed.empty() && !servers_.Load(LoadOf(scenePath, path), error)) return false;
    const bool swapped = servers_.Poll(error);
    pollMs_.push_back(MsSince(t0));
    if (!swapped) return false;
    justSwapped_ = true;
    const RenderProcess::Ready& r = servers_.Shown().back();
    lastMs_ = r.buildMs + r.useMs + r.firstFrameMs;
    return true;
}

void RenderProcessRun::Draw(const FrameInputs& in) {
    auto t0 = Clock::now();
    const bool ok = servers_.Frame(in, 5000);
    collectMs_.push_back(MsSince(t0));
    if (!ok) return;   // the last frame stays on screen
    t0 = Clock::now();
    if (reattach_) {
        present_->Blit(servers_.Texture());
    } else {
        const auto a0 = Clock::now();
        const unsigned fbo = servers_.ReadFramebuffer();   // kept per image: attached at its first read only
        present_->Blit(servers_.Texture(), fbo, MsSince(a0));
    }
    const double blit = MsSince(t0);
    servers_.AfterRead(in);
    blitMs_.push_back(MsSince(t0));
    if (justSwapped_) {
        firstAttachMs_.push_back(present_->LastAttachMs());
        firstBlitMs_.push_back(blit - present_->LastAttachMs());
        firstRequestMs_.push_back(blitMs_.back() - blit);
        justSwapped_ = false;
    }
}

std::string RenderProcessRun::Details() const {
    const FrameTransport t = servers_.Transport();
    std::string line = std::string("render processes: ") + (pipelined_ ? "pipelined (the frame shown is the one asked for a frame before)" : "synchronous") + "; frames handed over by " +
                       (t == FrameTransport::VkMemory ? "a Vulkan-allocated image both import (on the GPU)"
                        : t == FrameTransport::DmaBuf ? "dma-buf (on the GPU)" : "shared memory (a copy each way)") +
                       (servers_.Note().empty() ? "" : "; " + servers_.Note()) + "; " + (tiered_ ? "tiered (a quick build in one process, the optimized one in another)" : "untiered") +
                       "; images imported " +
                       (importer_ ? std::string("on a thread of their own") + (importOptions_.touch ? ", used once there" : "") +
                                        (importOptions_.freeThere ? ", freed there" : ", freed on the render thread")
                                  : std::string("and freed on the render thread")) +
                       (servers_.StandbyUsed() > 0 ? "; " + std::to_string(servers_.StandbyUsed()) + " loads taken by a standby holding the program (only the chain built)" : "") +
                       "; each one on screen: compile + link / first use / first frame / hand-over set-up ms (\"ahead\": its images made while it waited, the first frame's copy left), the render thread's part of taking it ms" +
                       (importer_ ? " (+ the import thread's ms)" : "") + ":";
    char buf[200];
    for (size_t i = 1; i < servers_.Shown().size(); ++i) {   // [0]: the first program, before the rounds
        const RenderProcess::Ready& r = servers_.Shown()[i];
        std::snprintf(buf, sizeof buf, " %s%.1f / %.1f / %.1f / %.1f%s, %.2f", servers_.ShownQuick()[i] ? "quick " : "", r.buildMs, r.useMs,
                      r.firstFrameMs, r.shareMs, r.imagesAhead ? " ahead" : "", r.importMs);
        line += buf;
        if (r.importThreadMs >= 0) {
            std::snprintf(buf, sizeof buf, " (+%.2f)", r.importThreadMs);
            line += buf;
        }
        line += ";";
    }
    if (servers_.FailedFrames()) line += " frames the server did not deliver: " + std::to_string(servers_.FailedFrames());
    std::snprintf(buf, sizeof buf, "\nthe show's frames, medians: poll %.3f ms, collect %.3f ms, blit + request %.3f ms (then glFinish); largest: %.3f, %.3f, %.3f ms",
                  MedianMs(pollMs_), MedianMs(collectMs_), MedianMs(blitMs_), Largest(pollMs_), Largest(collectMs_), Largest(blitMs_));
    line += buf;
    std::snprintf(buf, sizeof buf, "\nthe first frame after each swap, medians: attach %.3f ms, blit %.3f ms, read fence + request %.3f ms; largest: %.3f, %.3f, %.3f ms",
                  MedianMs(firstAttachMs_), MedianMs(firstBlitMs_), MedianMs(firstRequestMs_), Largest(firstAttachMs_), Largest(firstBlitMs_),
                  Largest(firstRequestMs_));
    line += buf;
    return line;
}

}  // namespace sdfvj
