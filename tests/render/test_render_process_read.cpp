// The show reads a render process's frame through a framebuffer kept per image
// (RenderProcess::ReadFramebuffer, ServerShow::ReadFramebuffer): `live --render-process` and bench
// reload's render-process mode blit from it instead of attaching the image each frame. On llvmpipe,
// with the import thread as `live` has it (its frees let GL give a freed texture's name to the next
// server's image). This binary is its own server (/proc/self/exe render-server), as sdfvj is.
// Also the gap between frames (ServerShow::FrameDone): a server a swap replaced ends after the
// frame, and a new server's images are imported after the frame they arrived in.
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>
#include <epoxy/gl.h>

#include <unistd.h>

#include <chrono>
#include <fstream>
#include <memory>
#include <string>

#include "gl_fixture.h"
#include "render/import_thread.h"
#include "isf/isf_server_post.h"
#include "render/render_process.h"
#include "render/server_show.h"
#include "render_process_fixture.h"
#include "scene/scene.h"

using namespace sdfvj;
using namespace sdfvj::test;

namespace {

// The texture `fbo`'s colour attachment holds.
GLint Attached(unsigned fbo) {
    GLint name = 0;
    glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
    glGetFramebufferAttachmentParameteriv(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME, &name);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    return name;
}

// The frame on screen read through the show's framebuffer, against the scene drawn here; returns
// that framebuffer.
unsigned CheckFrame(ServerShow* show, const SceneInfo& scene, double time) {
    REQUIRE(show->Frame(Inputs(scene, time)));
    const unsigned fbo = show->ReadFramebuffer();
    REQUIRE(fbo != 0);
    CHECK(Attached(fbo) == (GLint)show->Texture());
    CHECK(CompareImages(ReadFramebufferImage(fbo), RenderScene(scene.name, scene.effects, RenderPath::Compute, kW, kH, time), 1).fractionOver == 0.0);
    return fbo;
}

// The shared context the import thread draws on. Never destroyed (Mesa once crashed a later draw
// after a shared context went: test_render_process.cpp).
HeadlessContext* ImportContext() {
    static HeadlessContext* c = [] {
        auto* made = new HeadlessContext;
        std::string why;
        return made->CreateShared(*TestContext(), &why, true) ? made : nullptr;
    }();
    return c;
}

// A process that is there and not a zombie (/proc/PID/stat's state letter).
bool Running(pid_t pid) {
    std::ifstream f("/proc/" + std::to_string(pid) + "/stat");
    std::string line;
    std::getline(f, line);
    const size_t close = line.rfind(')');
    if (close == std::string::npos || close + 2 >= line.size()) return false;
    return line[close + 2] != 'Z' && line[close + 2] != 'X';
}

struct Scenes {
    SceneInfo midi, primitives;
};
// The two scenes the saves switch between; the import thread's context made, the render context current.
Scenes TwoScenes() {
    RequireGl();
    Scenes s;
    std::string error;
    REQUIRE(FindScene("midi", &s.midi, &error));
    REQUIRE(FindScene("primitives", &s.primitives, &error));
    REQUIRE(ImportContext());
    TestContext()->MakeCurrent();
    return s;
}

// An import thread on ImportContext(), as `live` has one.
std::unique_ptr<ImportThread> ImportOnContext() {
    auto t = std::make_unique<ImportThread>([] { return ImportContext()->MakeCurrent(); }, [] { ImportContext()->ReleaseCurrent(); });
    REQUIRE(t->Ok());
    return t;
}

// A new server loading `scene` on the GPU, polled until its answer came: true when it was taken
// whole (*ready filled), false while its images are on the import thread.
bool LoadUntilImporting(RenderProcess* proc, ImportThread* importer, const SceneInfo& scene, RenderProcess::Ready* ready) {
    std::string error;
    proc->SetImporter(importer);
    INFO(error);
    REQUIRE(proc->Start(&error));
    REQUIRE(proc->Load(ServerLoad{scene.path, true, {}, RenderPath::Compute, kW, kH}, FrameTransport::VkMemory));
    bool taken = false;
    while (proc->Usable() && !(taken = proc->PollReady(ready, 0)) && !proc->Importing()) ::usleep(200);
    return taken;
}

double MsSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

TEST_CASE("render process read: one framebuffer kept per image reads that image's latest frame, and a new server's images never read through the last one's", "[render_process]") {
    const Scenes scenes = TwoScenes();
    const SceneInfo &midi = scenes.midi, &primitives = scenes.primitives;
    std::string error;
    const std::unique_ptr<ImportThread> thread = ImportOnContext();
    ImportThread& importer = *thread;
    ServerShow show(FrameTransport::VkMemory, false, false);
    show.SetImporter(&importer);
    INFO(error);
    REQUIRE(show.Start(ServerLoad{midi.path, true, {}, RenderPath::Compute, kW, kH}, &error));
    const bool twoImages = show.Transport() == FrameTransport::VkMemory;
    if (!twoImages) WARN("no Vulkan-allocated image here (" << show.Note() << "): one image, read through one framebuffer");

    // The images alternate frame by frame: each read through its own framebuffer, attached once.
    const unsigned first = CheckFrame(&show, midi, 1.0);
    const unsigned second = CheckFrame(&show, midi, 3.0);
    CHECK((second != first) == twoImages);
    CHECK(CheckFrame(&show, midi, 5.0) == first);   // the same framebuffer again, its image's new frame read through it
    CHECK(CheckFrame(&show, midi, 7.0) == second);

    // Saves: each new server's frames read through framebuffers of its own; the last server's go
    // with it (with its images), so a texture name GL hands out again never reads through them.
    unsigned before[2] = {first, second};
    for (const SceneInfo* next : {&primitives, &midi, &primitives}) {
        REQUIRE(show.Load(ServerLoad{next->path, true, {}, RenderPath::Compute, kW, kH}, &error));
        REQUIRE(PollUntilChange(&show, &error));
        show.DropPrevious();
        show.FrameDone();   // the frame that swapped is done: the server it replaced ends now
        CHECK_FALSE(glIsFramebuffer(before[0]));
        CHECK_FALSE(glIsFramebuffer(before[1]));
        before[0] = CheckFrame(&show, *next, 2.0);
        before[1] = CheckFrame(&show, *next, 4.0);
        CHECK(CheckFrame(&show, *next, 6.0) == before[0]);
    }
    CHECK(importer.Imported() == 4);
}

TEST_CASE("render process gap: a new server's images are imported after the frame they arrived in (or within 100 ms without one), and the server a swap replaced ends once the frame is done", "[render_process]") {
    // On the H200 the import beside a frame made it 1.2-1.8 ms against 0.53 (two frames before the
    // swap), and the replaced server's end 1.3-1.5 ms (the swap's frame): docs/performance.md, "Session 24".
    const Scenes scenes = TwoScenes();
    const SceneInfo &midi = scenes.midi, &primitives = scenes.primitives;
    std::string error;
    const std::unique_ptr<ImportThread> thread = ImportOnContext();
    ImportThread& importer = *thread;
    INFO(error);
    {   // The import thread alone: held for the frame's end once frames are told.
        importer.FrameDone();   // a show's frame ended: from now on imports wait for the next end
        RenderProcess proc;
        RenderProcess::Ready ready;
        const bool taken = LoadUntilImporting(&proc, &importer, midi, &ready);
        if (taken && ready.transport != FrameTransport::VkMemory) {
            WARN("no Vulkan-allocated image here (" << ready.text << "): nothing to import on a thread");
            return;
        }
        REQUIRE_FALSE(taken);   // imported before any frame ended: not held
        REQUIRE(proc.Importing());
        const auto seen = std::chrono::steady_clock::now();
        const int before = importer.Imported();
        ::usleep(30000);
        if (MsSince(seen) < 80) {   // still inside the hold (a loaded machine may oversleep past it)
            CHECK_FALSE(proc.PollReady(&ready, 0));
            CHECK(importer.Imported() == before);
        }
        importer.FrameDone();
        REQUIRE(proc.PollReady(&ready, 5000));
        CHECK(ready.ok);
        CHECK(importer.Imported() == before + 1);
    }
    {   // No frame ends: the import still comes, after the 100 ms hold.
        RenderProcess proc;
        RenderProcess::Ready ready;
        LoadUntilImporting(&proc, &importer, primitives, &ready);
        REQUIRE(proc.Importing());
        const auto seen = std::chrono::steady_clock::now();
        REQUIRE(proc.PollReady(&ready, 5000));
        CHECK(ready.ok);
        CHECK(MsSince(seen) >= 50.0);     // held (queued at most a poll before `seen`)
        CHECK(MsSince(seen) < 3000.0);    // but not for long
    }
    // A show: the server a swap replaced runs on until the frame is done, then ends.
    ServerShow show(FrameTransport::VkMemory, false, false);
    show.SetImporter(&importer);
    REQUIRE(show.Start(ServerLoad{midi.path, true, {}, RenderPath::Compute, kW, kH}, &error));
    CheckFrame(&show, midi, 1.0);
    show.FrameDone();
    const pid_t old = show.OnScreenPid();
    REQUIRE(old > 0);
    REQUIRE(show.Load(ServerLoad{primitives.path, true, {}, RenderPath::Compute, kW, kH}, &error));
    REQUIRE(PollUntilChange(&show, &error));   // no frame ends meanwhile: the import comes after the hold
    CHECK(show.OnScreenPid() != old);
    ::usleep(100000);
    CHECK(Running(old));   // retired in that Poll, not ended: the frame is not done
    CheckFrame(&show, primitives, 2.0);
    show.FrameDone();
    const auto t0 = std::chrono::steady_clock::now();
    while (Running(old) && MsSince(t0) < 5000) ::usleep(1000);
    CHECK_FALSE(Running(old));
}

TEST_CASE("render process swap: a new server's first frame, drawn with the frame's inputs streamed while it built, goes on screen in the frame that reads its answer, and without images made ahead in the frame after", "[render_process]") {
    // Pipelined, as `live --render-process` runs: the frame shown is the one asked for a frame
    // before. A swap once took three frames from the server's answer: the answer read (its images
    // queued for the import thread), the images taken and the first frame asked for, that frame
    // collected. Session 41 asked for the first frame with the answer (two frames). Now a spare's
    // images are made and imported before the save, and the show streams each frame's inputs to
    // the server that builds: it draws its first frame with the last ones and answers with it, so
    // the frame that reads the answer shows it (when no frame's inputs came after that draw: else
    // it is asked for, as before). Frames are paced 150 ms apart, room for a small frame under ASan.
    const Scenes scenes = TwoScenes();
    const SceneInfo &midi = scenes.midi, &primitives = scenes.primitives;
    std::string error;
    const std::unique_ptr<ImportThread> thread = ImportOnContext();
    INFO(error);
    enum Way { kShipped, kNoImagesAhead, kAfterImport };
    for (const Way way : {kShipped, kNoImagesAhead, kAfterImport}) {
        INFO((way == kShipped        ? "as shipped"
              : way == kNoImagesAhead ? "no images made ahead: the first frame asked for with the answer (session 41)"
                                      : "no images made ahead, first frame asked for after the import (before session 41)"));
        ServerShow show(FrameTransport::VkMemory, true, false);
        show.SetImporter(thread.get());
        show.SetFirstFrameAfterImport(way == kAfterImport);
        if (way != kShipped) show.SetServerEnv({"SDFVJ_SERVER_PREPARE_IMAGES=0"});
        REQUIRE(show.Start(ServerLoad{midi.path, true, {}, RenderPath::Compute, kW, kH}, &error));
        if (show.Transport() != FrameTransport::VkMemory) {
            WARN("no Vulkan-allocated image here (" << show.Note() << "): nothing is imported on a thread");
            return;
        }
        double time = 1.0;
        const double kStep = 0.25;   // show seconds a frame (paced 150 ms apart in wall time)
        // One paced frame as the show runs it; true when the Poll put a new server on screen.
        auto frame = [&](const SceneInfo& scene) {
            const bool swapped = show.Poll(&error);
            REQUIRE(show.Frame(Inputs(scene, time)));
            REQUIRE(show.ReadFramebuffer() != 0);
            ReadFramebufferImage(show.ReadFramebuffer());   // the show's read of the frame
            show.AfterRead(Inputs(scene, time));
            show.FrameDone();
            ::usleep(150000);
            return swapped;
        };
        for (int i = 0; i < 3; ++i) frame(midi), time += kStep;
        int atTheAnswer = 0;   // swaps in the frame that read the answer
        for (int load = 0; load < (way == kShipped ? 4 : 1); ++load) {
            const SceneInfo& scene = load % 2 == 0 ? primitives : midi;
            for (int i = 0; i < 30 && show.SparesReady() == 0; ++i) frame(load % 2 == 0 ? midi : primitives), time += kStep;
            REQUIRE(show.Load(ServerLoad{scene.path, true, {}, RenderPath::Compute, kW, kH}, &error));
            bool swapped = false;
            double swapTime = 0;
            for (int i = 0; i < 600 && !swapped; ++i) {
                swapTime = time;
                swapped = frame(scene);   // the old server draws these inputs too: only the new one's frames are checked
                time += kStep;
            }
            REQUIRE(swapped);
            INFO(scene.name << ": polls from the answer to the swap: " << show.LastSwapPolls() << ", images made ahead "
                            << show.Shown().back().imagesAhead << ", first frame drawn with streamed inputs #" << show.Shown().back().firstSeq);
            if (way == kShipped) {
                CHECK(show.Shown().back().imagesAhead);
                CHECK(show.LastSwapPolls() <= 1);   // 1: a frame's inputs came after the server drew its first frame
                atTheAnswer += show.LastSwapPolls() == 0 ? 1 : 0;
            } else {
                CHECK_FALSE(show.Shown().back().imagesAhead);
                if (way == kAfterImport) CHECK(show.LastSwapPolls() >= 2);   // asked for only once the images are taken
                else CHECK(show.LastSwapPolls() == 1);                       // drawn while they are imported
            }
            // The frame it went on screen with: the new scene a frame behind, as every pipelined frame
            // is, every way. A Poll comes before its frame's inputs: the first frame is drawn with the
            // last frame's (streamed), or asked for one frame on (ServerShow::FirstFrameInputs); asked
            // for with the last ones, it showed the frame before's time again (a stall at every swap).
            const Image shown = ReadFramebufferImage(show.ReadFramebuffer());
            CHECK(CompareImages(shown, RenderScene(scene.name, scene.effects, RenderPath::Compute, kW, kH, swapTime - kStep), 1).fractionOver == 0.0);
            CHECK(CompareImages(shown, RenderScene(scene.name, scene.effects, RenderPath::Compute, kW, kH, swapTime - 2 * kStep), 1)
                      .fractionOver > 0.0);   // the times differ on screen: this check can tell them apart
            // And it goes on drawing the new scene, frame by frame (pipelined: the one asked for a frame before).
            const double asked = time;
            frame(scene);
            time += kStep;
            REQUIRE(show.Poll(&error) == false);
            REQUIRE(show.Frame(Inputs(scene, time)));
            CHECK(CompareImages(ReadFramebufferImage(show.ReadFramebuffer()), RenderScene(scene.name, scene.effects, RenderPath::Compute, kW, kH, asked), 1)
                      .fractionOver == 0.0);
            show.AfterRead(Inputs(scene, time));
            show.FrameDone();
            time += kStep;
        }
        // A swap at the answer needs no frame's inputs between the server's first draw and the answer's
        // Poll (150 ms apart here): with four swaps, at least one.
        if (way == kShipped) CHECK(atTheAnswer >= 1);
    }
}

int main(int argc, char** argv) {
    if (argc == 2 && std::string(argv[1]) == "render-server") return RunRenderServer(3, MakeIsfServerPost);
    return Catch::Session().run(argc, argv);
}
