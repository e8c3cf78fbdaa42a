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

TEST_CASE("render process swap: a new server's first frame is drawn while its images are imported, so it goes on screen in the frame after its answer, a refresh sooner than asked for after the import", "[render_process]") {
    // Pipelined, as `live --render-process` runs: the frame shown is the one asked for a frame
    // before. A swap used to take three frames from the server's answer: the answer read (its images
    // queued for the import thread), the images taken and the first frame asked for, that frame
    // collected. Now the first frame is asked for with the answer, so the frame that takes the
    // images takes it too. Frames are paced 150 ms apart here, room for the import and a small frame under ASan.
    const Scenes scenes = TwoScenes();
    const SceneInfo &midi = scenes.midi, &primitives = scenes.primitives;
    std::string error;
    const std::unique_ptr<ImportThread> thread = ImportOnContext();
    INFO(error);
    for (const bool afterImport : {false, true}) {
        INFO((afterImport ? "first frame asked for after the import (the way before)" : "first frame asked for with the answer"));
        ServerShow show(FrameTransport::VkMemory, true, false);
        show.SetImporter(thread.get());
        show.SetFirstFrameAfterImport(afterImport);
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
        REQUIRE(show.Load(ServerLoad{primitives.path, true, {}, RenderPath::Compute, kW, kH}, &error));
        bool swapped = false;
        double swapTime = 0;
        for (int i = 0; i < 600 && !swapped; ++i) {
            swapTime = time;
            swapped = frame(primitives);   // the old server draws these inputs too: only the new one's frames are checked
            time += kStep;
        }
        REQUIRE(swapped);
        INFO("polls from the answer to the swap: " << show.LastSwapPolls());
        if (afterImport) CHECK(show.LastSwapPolls() >= 2);   // asked for only once the images are taken: never the next Poll
        else CHECK(show.LastSwapPolls() == 1);
        // The frame it went on screen with: the new scene a frame behind, as every pipelined frame
        // is, either way. A Poll comes before its frame's inputs, so the last ones are two frames
        // behind the swap: asked for with those, the first frame showed the frame before's time
        // again (a stall at every swap); it is asked for one frame on (ServerShow::FirstFrameInputs).
        const Image shown = ReadFramebufferImage(show.ReadFramebuffer());
        CHECK(CompareImages(shown, RenderScene(primitives.name, primitives.effects, RenderPath::Compute, kW, kH, swapTime - kStep), 1)
                  .fractionOver == 0.0);
        CHECK(CompareImages(shown, RenderScene(primitives.name, primitives.effects, RenderPath::Compute, kW, kH, swapTime - 2 * kStep), 1)
                  .fractionOver > 0.0);   // the times differ on screen: this check can tell them apart
        // And it goes on drawing the new scene, frame by frame (pipelined: the one asked for a frame before).
        const double asked = time;
        frame(primitives);
        REQUIRE(show.Frame(Inputs(primitives, asked + kStep)));
        CHECK(CompareImages(ReadFramebufferImage(show.ReadFramebuffer()),
                            RenderScene(primitives.name, primitives.effects, RenderPath::Compute, kW, kH, asked), 1)
                  .fractionOver == 0.0);
    }
}

int main(int argc, char** argv) {
    if (argc == 2 && std::string(argv[1]) == "render-server") return RunRenderServer(3, MakeIsfServerPost);
    return Catch::Session().run(argc, argv);
}
