// RenderProcessRun: `sdfvj bench reload --modes render-process[-shm]` (issue 12, session 16): each
// program drawn by a process of its own (render/render_process.h), its frames shown here.
//
// A save goes to the spare render server (started ahead, its GL context already open), which
// compiles the scene, uses the program once and draws its first frame while the server on screen
// goes on drawing; then the new server goes on screen and the old one is ended (reaped later, never
// waited for on a frame). Every frame: the server on screen draws with this frame's inputs and
// hands the frame over (an image both processes import, allocated through Vulkan; a dma-buf; or
// shared memory with -shm or where the drivers offer neither), and the render thread blits it into
// the target it presents, as `live` would on its window. Pipelined (render-process and -shm; not
// render-process-sync): the frame presented is the one asked for the frame before, so the server
// draws while this thread waits for the display.
// Render thread only.
#pragma once
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "app/bench_adopt.h"
#include "render/server_show.h"

namespace sdfvj {

// bench reload --post A,B: the servers' post chain, copied into the run's root (its shaders/isf)
// where missing; each Save gives the last file a new function (a program no cache has seen) and
// leaves the scene as it is.
struct BenchPostSaves {
    std::vector<std::string> paths;   // in the run's root; empty without --post
    std::string original;             // the last file's text
    uint64_t nonce = 0;               // new programs every run
    BenchPostSaves(const std::string& list, const std::filesystem::path& root, uint64_t runNonce);
    void Save(int round) const;
};

class RenderProcessRun : public HandOverRun {
public:
    // pipelined: the server draws frame N+1 while this thread paces and presents frame N (the frame
    // on screen one behind its inputs); otherwise every frame waits for the server's round trip.
    // tiered: every save also goes to a second server that builds the quick tier (QuickTierText),
    // on screen until the optimized program's server is ready.
    // serverEnv: NAME=value entries for the servers' environment (SDFVJ_SERVER_IMAGES=1: frames
    // handed over in one image, not two by turns; SDFVJ_SERVER_PREPARE=0: no Vulkan device made ahead).
    // inTurn: tiered, the optimized build starts once the quick tier is on screen (ServerShow::SetTiersInTurn).
    // importThread: a new server's images are imported on a thread of their own (render/import_thread.h),
    // as `live` does; false (render-process-import-here): on the render thread, in the frame that
    // takes the server's answer. importOptions: what else that thread does (render-process-no-touch,
    // render-process-free-here).
    RenderProcessRun(FrameTransport transport, bool pipelined, bool tiered, std::vector<std::string> serverEnv = {}, bool inTurn = false,
                     bool importThread = true, ImportOptions importOptions = {})
        : servers_(transport, pipelined, tiered), pipelined_(pipelined), tiered_(tiered), importThread_(importThread),
          importOptions_(importOptions) {
        servers_.SetServerEnv(std::move(serverEnv));
        servers_.SetTiersInTurn(inTurn);
    }
    ~RenderProcessRun() override;
    RenderProcessRun(const RenderProcessRun&) = delete;
    RenderProcessRun& operator=(const RenderProcessRun&) = delete;
    bool Start(HeadlessContext& gl, const std::string& scenePath, RenderPath path, int width, int height, std::string* error) override;
    bool Update(const std::vector<std::string>& changed, const std::string& scenePath, RenderPath path, std::string* error) override;
    void Draw(const FrameInputs& in) override;
    void FrameDone() override { servers_.FrameDone(); }
    double LastBuildMs() const override { return lastMs_; }
    std::string Details() const override;
    bool OnScreenQuick() const override { return servers_.OnScreenQuick(); }
    FrameTransport Transport() const { return servers_.Transport(); }
    // render-process-reattach: each frame's image attached to one read framebuffer, as before session
    // 22 (the two images alternate, so every frame attaches), not read through the one kept per image.
    void SetReattach(bool on) { reattach_ = on; }
    ServerShow& Show() { return servers_; }   // the way before, measured (SetRetireAtOnce)
    // The post chain every load draws its frames through (ServerLoad::post). Before Start.
    void SetPost(std::vector<std::string> paths) { post_ = std::move(paths); }

private:
    // Declared before servers_: its servers are stopped (jobs abandoned) before the thread ends,
    // and the thread ends before its context goes.
    std::unique_ptr<HeadlessContext> importContext_;
    std::unique_ptr<ImportThread> importer_;
    ServerShow servers_;
    bool pipelined_, tiered_, importThread_;
    ImportOptions importOptions_;
    std::unique_ptr<PresentTarget> present_;
    int w_ = 0, h_ = 0;
    double lastMs_ = 0;
    std::vector<double> pollMs_, collectMs_, blitMs_;   // each frame's parts on the render thread
    // The first frame after each swap, on the render thread: the new image's attach, the blit's
    // submission, the read fence + next request (what makes a reload's longest frame, session 21)
    std::vector<double> firstAttachMs_, firstBlitMs_, firstRequestMs_;
    bool justSwapped_ = false;
    bool reattach_ = false;
    std::vector<std::string> post_;
    ServerLoad LoadOf(const std::string& scenePath, RenderPath path) const {
        ServerLoad load{scenePath, true, {}, path, w_, h_};
        load.post = post_;
        return load;
    }
};

}  // namespace sdfvj
