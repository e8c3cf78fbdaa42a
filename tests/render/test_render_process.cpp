// The render process (render/render_process.h) on llvmpipe: a scene drawn by `render-server` and
// handed over shows what this process draws from the same inputs; a broken scene comes back with
// its reason; a server that dies fails its frame at once instead of hanging the show; frames go
// over on the GPU (a Vulkan-allocated image both processes import) where the drivers can, by
// shared memory where not, the same image either way. This binary is its own server
// (/proc/self/exe render-server), as sdfvj is. ServerShow, the servers behind a show (spares, a
// variant loaded, a failed build, a dead server replaced, draws timed for "measure costs"), is tested
// here too; the post chain through a server is test_render_process_post.cpp.
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>
#include <epoxy/egl.h>
#include <epoxy/gl.h>
#include <signal.h>
#include <sys/resource.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "app/effect_costs.h"
#include "app/live_servers.h"
#include "gl_fixture.h"
#include "render_process_fixture.h"
#include "render/field_morph.h"
#include "isf/isf.h"
#include "isf/isf_server_post.h"
#include "render/render_process.h"
#include "render/server_show.h"
#include "scene/scene.h"

using namespace sdfvj;
using namespace sdfvj::test;


TEST_CASE("render process: the server draws what this process draws, frame by frame", "[render_process]") {
    const RenderPath path = GENERATE(RenderPath::Fragment, RenderPath::Compute);
    SceneInfo scene;
    std::string error;
    REQUIRE(FindScene("midi", &scene, &error));
    RenderProcess proc;
    const RenderProcess::Ready ready = StartAndLoad(&proc, scene.path, path, FrameTransport::Shm);
    INFO(ready.text);
    REQUIRE(ready.ok);
    CHECK(ready.transport == FrameTransport::Shm);
    CHECK(ready.buildMs > 0);
    Image first;
    for (double time : {1.0, 2.5}) {
        REQUIRE(proc.DrawFrame(Inputs(scene, time)));
        const Image got = ReadTexture(proc.Texture());
        const Image want = RenderScene("midi", scene.effects, path, kW, kH, time);
        const ImageDiff d = CompareImages(got, want, 1);
        INFO("time " << time << ": max channel difference " << d.maxAbs << ", mean " << d.meanAbs);
        CHECK(d.fractionOver == 0.0);   // same driver, same program, same inputs: the same image
        if (first.rgba.empty()) first = got;
        else CHECK(CompareImages(got, first, 8).fractionOver > 0.01);   // the inputs reached it: the frame moved
    }
}

TEST_CASE("render process: a broken scene comes back with its reason", "[render_process]") {
    RenderProcess proc;
    const RenderProcess::Ready ready = StartAndLoad(&proc, "/nonexistent/nosuch.glsl", RenderPath::Fragment, FrameTransport::Shm);
    CHECK_FALSE(ready.ok);
    INFO(ready.text);
    CHECK(ready.text.find("nosuch.glsl") != std::string::npos);
    CHECK_FALSE(proc.DrawFrame(FrameInputs{}, 1000));
}

TEST_CASE("render process: a server that dies fails its frame at once, never hangs the show", "[render_process]") {
    SceneInfo scene;
    std::string error;
    REQUIRE(FindScene("primitives", &scene, &error));
    RenderProcess proc;
    const RenderProcess::Ready ready = StartAndLoad(&proc, scene.path, RenderPath::Fragment, FrameTransport::Shm);
    REQUIRE(ready.ok);
    REQUIRE(proc.DrawFrame(Inputs(scene, 1.0)));
    ::kill(proc.Pid(), SIGKILL);
    const auto t0 = std::chrono::steady_clock::now();
    CHECK_FALSE(proc.DrawFrame(Inputs(scene, 2.0), 30000));
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    CHECK(ms < 10000);   // noticed by the closed socket, not by the 30 s timeout
    CHECK_FALSE(proc.Usable());
    CHECK(proc.Texture() != 0);   // the last frame is still there to show
}

TEST_CASE("render process: frames handed over on the GPU where it can, by shared memory where not, the same image", "[render_process]") {
    SceneInfo scene;
    std::string error;
    REQUIRE(FindScene("midi", &scene, &error));
    RenderProcess proc;
    const RenderProcess::Ready ready = StartAndLoad(&proc, scene.path, RenderPath::Compute, FrameTransport::VkMemory);
    INFO("transport " << FrameTransportName(ready.transport) << ": " << ready.text);
    REQUIRE(ready.ok);
    // scripts/setup.sh installs lavapipe (Mesa's Vulkan on the CPU): with it and llvmpipe's
    // GL_EXT_memory_object_fd the Vulkan-allocated image is what runs here.
    const bool lavapipe = std::ifstream("/usr/share/vulkan/icd.d/lvp_icd.x86_64.json").good();
    if (lavapipe && epoxy_has_gl_extension("GL_EXT_memory_object_fd")) CHECK(ready.transport == FrameTransport::VkMemory);
    if (ready.transport == FrameTransport::Shm) CHECK(ready.text.find("shared memory instead") != std::string::npos);   // says why
    for (double time : {1.0, 3.0}) {
        REQUIRE(proc.DrawFrame(Inputs(scene, time)));
        const ImageDiff d = CompareImages(ReadTexture(proc.Texture()), RenderScene("midi", scene.effects, RenderPath::Compute, kW, kH, time), 1);
        INFO("time " << time << ": max channel difference " << d.maxAbs);
        CHECK(d.fractionOver == 0.0);
    }
}

TEST_CASE("render process: on the GPU frames come in two images by turns, the frame before untouched while the next is drawn", "[render_process]") {
    SceneInfo scene;
    std::string error;
    REQUIRE(FindScene("midi", &scene, &error));
    const Image at1 = RenderScene("midi", scene.effects, RenderPath::Compute, kW, kH, 1.0);
    const Image at3 = RenderScene("midi", scene.effects, RenderPath::Compute, kW, kH, 3.0);
    REQUIRE(CompareImages(at1, at3, 1).fractionOver > 0.01);   // the two times draw different pictures
    for (const bool oneImage : {false, true}) {
        INFO((oneImage ? "SDFVJ_SERVER_IMAGES=1" : "two images"));
        RenderProcess proc;
        const RenderProcess::Ready ready = StartAndLoad(&proc, scene.path, RenderPath::Compute, FrameTransport::VkMemory,
                                                        oneImage ? std::vector<std::string>{"SDFVJ_SERVER_IMAGES=1"} : std::vector<std::string>{});
        INFO("transport " << FrameTransportName(ready.transport) << ": " << ready.text);
        REQUIRE(ready.ok);
        if (std::ifstream("/usr/share/vulkan/icd.d/lvp_icd.x86_64.json").good() && epoxy_has_gl_extension("GL_EXT_memory_object_fd"))
            REQUIRE(ready.transport == FrameTransport::VkMemory);   // as CI has it (scripts/setup.sh: lavapipe)
        if (ready.transport != FrameTransport::VkMemory) {
            WARN("no Vulkan-allocated image here: frames go one at a time, nothing to test");
            return;
        }
        // As the pipelined show runs it: the frame read (fenced), the next one asked for at once.
        REQUIRE(proc.Request(Inputs(scene, 1.0)));
        REQUIRE(proc.Collect());
        const unsigned first = proc.Texture();
        CHECK(CompareImages(ReadTexture(first), at1, 1).fractionOver == 0.0);
        proc.Read();
        REQUIRE(proc.Request(Inputs(scene, 3.0)));
        REQUIRE(proc.Collect());
        const unsigned second = proc.Texture();
        CHECK(CompareImages(ReadTexture(second), at3, 1).fractionOver == 0.0);
        // Two images: the next frame went into the other one and the frame before is still whole
        // there; one image: the next frame replaced it.
        CHECK((second != first) == !oneImage);
        if (!oneImage) CHECK(CompareImages(ReadTexture(first), at1, 1).fractionOver == 0.0);
        // and by turns: the third frame is back in the first image
        proc.Read();
        REQUIRE(proc.DrawFrame(Inputs(scene, 1.0)));
        CHECK(proc.Texture() == first);
        CHECK(CompareImages(ReadTexture(proc.Texture()), at1, 1).fractionOver == 0.0);
    }
}

TEST_CASE("render process: with SDFVJ_SERVER_NICE a server's own thread builds at a lower priority, the renderer's threads it draws with keep theirs", "[render_process]") {
    // On a machine's shared cores a spare's compile (and llvmpipe's JIT at its first use) may yield
    // to the frames of the server on screen and of the show (measured: a trade, so not by default).
    SceneInfo scene;
    std::string error;
    REQUIRE(FindScene("midi", &scene, &error));
    const int base = ::getpriority(PRIO_PROCESS, 0);
    auto niceOf = [](pid_t pid, const std::string& tid) {   // field 19 of /proc/PID/task/TID/stat
        std::ifstream in("/proc/" + std::to_string(pid) + "/task/" + tid + "/stat");
        std::string line((std::istreambuf_iterator<char>(in)), {});
        std::istringstream rest(line.substr(line.rfind(')') + 2));
        std::string field;
        for (int i = 3; i <= 19 && rest >> field;) ++i;
        return std::atoi(field.c_str());
    };
    for (const bool off : {false, true}) {
        INFO((off ? "default" : "SDFVJ_SERVER_NICE=10"));
        RenderProcess proc;
        REQUIRE(StartAndLoad(&proc, scene.path, RenderPath::Fragment, FrameTransport::Shm,
                             off ? std::vector<std::string>{} : std::vector<std::string>{"SDFVJ_SERVER_NICE=10"}).ok);
        int own = -100, others = 0, lowest = 100;
        for (const auto& task : std::filesystem::directory_iterator("/proc/" + std::to_string(proc.Pid()) + "/task")) {
            const std::string tid = task.path().filename().string();
            const int n = niceOf(proc.Pid(), tid);
            if (tid == std::to_string(proc.Pid())) own = n;
            else ++others, lowest = std::min(lowest, n);
        }
        CHECK(own == (off ? base : std::min(base + 10, 19)));
        REQUIRE(others > 0);   // the renderer's threads (llvmpipe's, a driver's)
        CHECK(lowest == base);
    }
}

TEST_CASE("render process: a server makes its Vulkan device before a load asks, so the load's hand-over costs only its images", "[render_process]") {
    SceneInfo scene;
    std::string error;
    REQUIRE(FindScene("midi", &scene, &error));
    double shareMs[2] = {0, 0};
    for (const bool prepared : {true, false}) {
        RenderProcess proc;
        const RenderProcess::Ready ready = StartAndLoad(&proc, scene.path, RenderPath::Compute, FrameTransport::VkMemory,
                                                        prepared ? std::vector<std::string>{} : std::vector<std::string>{"SDFVJ_SERVER_PREPARE=0"});
        INFO("transport " << FrameTransportName(ready.transport) << ": " << ready.text);
        REQUIRE(ready.ok);
        if (ready.transport != FrameTransport::VkMemory) {
            WARN("no Vulkan-allocated image here: nothing to make ahead");
            return;
        }
        shareMs[prepared ? 0 : 1] = ready.shareMs;
        REQUIRE(proc.DrawFrame(Inputs(scene, 1.0)));   // and the frames come over as before
        CHECK(CompareImages(ReadTexture(proc.Texture()), RenderScene("midi", scene.effects, RenderPath::Compute, kW, kH, 1.0), 1).fractionOver == 0.0);
    }
    // lavapipe: 1.4 against 39 ms; the H200: 0.7-5 against 87-113 ms (docs/performance.md, session 19)
    INFO("hand-over set-up: " << shareMs[0] << " ms with the device made ahead, " << shareMs[1] << " ms without");
    CHECK(shareMs[0] < 0.5 * shareMs[1]);
}

// ServerShow (render/server_show.h): the servers behind a show.

TEST_CASE("render process: a new server's images are imported on a thread of their own, the render thread only takes the textures", "[render_process]") {
    // `live --render-process` and bench reload's render-process: the frame that takes a new server's
    // answer does not import its images (0.6-0.8 ms of a frame on the H200, session 19).
    RequireGl();
    SceneInfo midi, primitives;
    std::string error;
    REQUIRE(FindScene("midi", &midi, &error));
    REQUIRE(FindScene("primitives", &primitives, &error));
    // Never destroyed: this process's tests share the render context, and Mesa once crashed a later
    // draw after a shared context went (cmd_bench_reload.cpp keeps its own to the end, too).
    static HeadlessContext* shared = [] {
        auto* c = new HeadlessContext;
        std::string why;
        return c->CreateShared(*TestContext(), &why, true) ? c : nullptr;
    }();
    REQUIRE(shared);
    TestContext()->MakeCurrent();
    ImportThread importer([] { return shared->MakeCurrent(); }, [] { shared->ReleaseCurrent(); });
    REQUIRE(importer.Ok());
    {
        ServerShow show(FrameTransport::VkMemory, false, false);
        show.SetImporter(&importer);
        INFO(error);
        REQUIRE(show.Start(ServerLoad{midi.path, true, {}, RenderPath::Compute, kW, kH}, &error));
        if (show.Transport() != FrameTransport::VkMemory) {
            WARN("no Vulkan-allocated image here (" << show.Note() << "): nothing to import on a thread");
            return;
        }
        CHECK(importer.Imported() == 1);
        CHECK(show.Shown().back().importThreadMs >= 0.0);
        REQUIRE(show.Frame(Inputs(midi, 1.0)));
        CHECK(CompareImages(ReadTexture(show.Texture()), RenderScene("midi", midi.effects, RenderPath::Compute, kW, kH, 1.0), 1).fractionOver == 0.0);

        // A save's server: its images too, while the one on screen goes on.
        REQUIRE(show.Load(ServerLoad{primitives.path, true, {}, RenderPath::Compute, kW, kH}, &error));
        REQUIRE(PollUntilChange(&show, &error));
        CHECK(importer.Imported() == 2);
        REQUIRE(show.Frame(Inputs(primitives, 1.0)));
        CHECK(CompareImages(ReadTexture(show.Texture()), RenderScene("primitives", primitives.effects, RenderPath::Compute, kW, kH, 1.0), 1)
                  .fractionOver == 0.0);
    }
    // Both servers' images, the one a save replaced and the one on screen at the end, were freed on
    // the thread (after the render context's reads of them), not by this one.
    for (int i = 0; i < 5000 && importer.Freed() < 2; ++i) ::usleep(1000);
    CHECK(importer.Freed() == 2);
    // A server stopped while its images may still be on the thread: abandoned, freed there, and
    // the next server's import works.
    {
        RenderProcess proc;
        proc.SetImporter(&importer);
        REQUIRE(proc.Start(&error));
        REQUIRE(proc.Load(ServerLoad{midi.path, true, {}, RenderPath::Compute, kW, kH}, FrameTransport::VkMemory));
        RenderProcess::Ready ready;
        bool taken = false;
        while (proc.Usable() && !(taken = proc.PollReady(&ready, 0)) && !proc.Importing()) ::usleep(200);
        CHECK(proc.Usable());
        CHECK((taken || proc.Importing()));   // the answer came: stopped (below) with its import on the thread, or done
    }
    RenderProcess proc;
    proc.SetImporter(&importer);
    const RenderProcess::Ready ready = StartAndLoad(&proc, midi.path, RenderPath::Compute, FrameTransport::VkMemory);
    REQUIRE(ready.ok);
    CHECK(ready.importThreadMs >= 0.0);
    CHECK(importer.Imported() == 4);
    REQUIRE(proc.DrawFrame(Inputs(midi, 2.0)));
    CHECK(CompareImages(ReadTexture(proc.Texture()), RenderScene("midi", midi.effects, RenderPath::Compute, kW, kH, 2.0), 1).fractionOver == 0.0);
}

TEST_CASE("render process: a show's servers draw the variant a load asks for, and a failed build leaves the one on screen", "[render_process]") {
    ServerShow show(FrameTransport::VkMemory, false, false);
    const SceneInfo scene = StartShow(&show, "midi");
    std::string error;
    REQUIRE(show.Frame(Inputs(scene, 1.0)));
    const Image own = ReadTexture(show.Texture());
    CHECK(CompareImages(own, RenderScene("midi", scene.effects, RenderPath::Fragment, kW, kH, 1.0), 1).fractionOver == 0.0);

    // Effects "none": that variant, built by a spare while the first one stays on screen.
    REQUIRE(show.Load(ServerLoad{scene.path, false, EffectSet{}, RenderPath::Fragment, kW, kH}, &error));
    CHECK(show.Building());
    REQUIRE(show.Frame(Inputs(scene, 1.0)));   // the one on screen still draws
    REQUIRE(PollUntilChange(&show, &error));
    REQUIRE(show.Frame(Inputs(scene, 1.0)));
    const Image none = ReadTexture(show.Texture());
    CHECK(CompareImages(none, RenderScene("midi", EffectSet{}, RenderPath::Fragment, kW, kH, 1.0), 1).fractionOver == 0.0);
    CHECK(CompareImages(none, own, 8).fractionOver > 0.01);   // no shadows, no AO: another picture

    // A scene that does not build: its reason, and the variant before stays on screen.
    const std::string broken = (std::filesystem::temp_directory_path() / "sdfvj_broken_scene.glsl").string();
    {
        std::ofstream out(broken);
        out << "/*{\"DESCRIPTION\": \"broken\"}*/\nvec4 map(vec3 p) { return fBx(p); }\n";
    }
    REQUIRE(show.Load(OwnEffects(broken), &error));
    CHECK_FALSE(PollUntilChange(&show, &error));
    CHECK(error.find("sdfvj_broken_scene.glsl:2:") != std::string::npos);
    REQUIRE(show.Frame(Inputs(scene, 1.0)));
    CHECK(CompareImages(ReadTexture(show.Texture()), none, 1).fractionOver == 0.0);
}

TEST_CASE("render process: a show's server that dies is replaced by one building the same program, its last frame shown meanwhile", "[render_process]") {
    ServerShow show(FrameTransport::Shm, false, false);
    const SceneInfo scene = StartShow(&show, "primitives");
    std::string error;
    REQUIRE(show.Frame(Inputs(scene, 1.0)));
    const Image last = ReadTexture(show.Texture());
    ::kill(show.OnScreenPid(), SIGKILL);
    CHECK_FALSE(show.Frame(Inputs(scene, 2.0)));
    REQUIRE(show.Texture() != 0);
    CHECK(CompareImages(ReadTexture(show.Texture()), last, 0).fractionOver == 0.0);   // the last frame stays
    CHECK_FALSE(show.Poll(&error));
    CHECK(error.find("ended") != std::string::npos);
    CHECK(show.Replaced() == 1);
    CHECK(CompareImages(ReadTexture(show.Texture()), last, 0).fractionOver == 0.0);
    error.clear();
    REQUIRE(PollUntilChange(&show, &error));
    REQUIRE(show.Frame(Inputs(scene, 2.0)));
    CHECK(CompareImages(ReadTexture(show.Texture()), RenderScene("primitives", scene.effects, RenderPath::Fragment, kW, kH, 2.0), 1).fractionOver == 0.0);
}

TEST_CASE("render process: the server on screen times its program's draws offscreen, each effect's cost measured there, its frames untouched", "[render_process][timed]") {
    // `live --render-process`'s "measure costs": the draws the overlay asks for are timed by the
    // server (glFinish + wall clock on llvmpipe), into a target of its own, not the one it hands over.
    RequireGl();
    SceneInfo scene;
    std::string error;
    REQUIRE(FindScene("midi", &scene, &error));
    EffectSet heavy;
    heavy.shadows = 2;   // soft
    heavy.ao = heavy.specular = heavy.fog = true;
    ServerShow show(FrameTransport::Shm, false, false);
    INFO(error);
    const int w = 320, h = 180;   // large enough that the wall clock sees the shadows' cost
    REQUIRE(show.Start(ServerLoad{scene.path, false, heavy, RenderPath::Fragment, w, h}, &error));
    const FrameInputs in = Inputs(scene, 1.0);
    REQUIRE(show.Frame(in));
    const Image before = ReadTexture(show.Texture(), w, h);

    // A wall-clock measure: ctest runs this test alone ([timed], RUN_SERIAL), and a measurement
    // that a busy machine still turned upside down is taken again, up to three times.
    EffectCosts costs;
    double shadowsMs = 0.0;
    std::string table;
    for (int attempt = 0; attempt < 3 && shadowsMs <= 0.0; ++attempt) {
        costs = EffectCosts{};
        StartEffectCosts(costs, heavy, 7, true);
        REQUIRE(costs.rows.size() == 4);
        int steps = 0;
        while (!costs.Done() && steps < 1000) {
            StepEffectCostsTimed(costs, in, [&](const FrameInputs& f) { return show.TimeDraw(f); }, "timed in the render process on screen");
            ++steps;
        }
        REQUIRE(costs.Done());
        CHECK(steps == 7 * 5);   // every draw answered: all on + 4 one-off variants per round
        table += "attempt " + std::to_string(attempt + 1) + ":\n";
        for (const EffectCostRow& r : costs.rows) {
            CHECK(r.diffs.size() == 7);
            table += r.name + " " + EffectCostText(r, costs) + "\n";
        }
        shadowsMs = EffectCostMs(costs.rows[0], costs);
    }
    INFO(table << EffectCostNote(costs));
    CHECK(shadowsMs > 0.0);   // soft shadows cost more than nothing
    CHECK(EffectCostNote(costs).find("timed in the render process on screen") != std::string::npos);

    // The frame handed over is still the program's own with every effect on.
    REQUIRE(show.Frame(in));
    CHECK(CompareImages(ReadTexture(show.Texture(), w, h), before, 0).fractionOver == 0.0);
    CHECK(show.Replaced() == 0);
}

TEST_CASE("render process: a field morph held by a server draws the first scene at 0, the second at 1, a third picture half way", "[render_process]") {
    // `live --render-process`'s field morph (ServerLoad::morphFrom, ServerShow::Held::Morph): the
    // server builds both fields' program and draws it with the morph's inputs; the show's own
    // server on screen is not touched.
    RequireGl();
    SceneInfo a, b;
    std::string error;
    REQUIRE(FindScene("midi", &a, &error));
    REQUIRE(FindScene("primitives", &b, &error));
    const EffectSet fx = UnionEffects(a.effects, b.effects);
    const int w = 160, h = 90;
    ServerShow show(FrameTransport::Shm, false, false);
    INFO(error);
    REQUIRE(show.Start(ServerLoad{a.path, true, {}, RenderPath::Fragment, w, h}, &error));
    ServerLoad morph{b.path, false, fx, RenderPath::Fragment, w, h};
    morph.morphFrom = a.path;
    REQUIRE(show.Prepare(morph, &error, ServerShow::Held::Morph));
    for (int i = 0; i < 60000 && show.HasPrepared(ServerShow::Held::Morph) && !show.PreparedReady(ServerShow::Held::Morph); ++i) ::usleep(2000);
    INFO(show.PreparedError(ServerShow::Held::Morph));
    REQUIRE(show.PreparedReady(ServerShow::Held::Morph));
    auto at = [&](float t) {
        FrameInputs in = Inputs(b, 1.0);
        in.params = MorphParamValues(Inputs(a, 1.0).params, in.params, t);
        REQUIRE(show.HeldFrame(ServerShow::Held::Morph, in));
        return ReadTexture(show.HeldTexture(ServerShow::Held::Morph), w, h);
    };
    const Image ia = RenderScene("midi", fx, RenderPath::Fragment, w, h), ib = RenderScene("primitives", fx, RenderPath::Fragment, w, h);
    const Image m0 = at(0.0f), half = at(0.5f), m1 = at(1.0f);
    // The ends, as test_field_morph's in-process morph: one bounding sphere around both scenes, so the
    // last bits of soft shadows may differ.
    CHECK(CompareImages(ia, m0, 8).meanAbs < 1.0);
    CHECK(CompareImages(ia, m0, 8).fractionOver < 0.01);
    CHECK(CompareImages(ib, m1, 8).meanAbs < 1.0);
    CHECK(CompareImages(ib, m1, 8).fractionOver < 0.01);
    CHECK(CompareImages(ia, half, 8).fractionOver > 0.05);
    CHECK(CompareImages(ib, half, 8).fractionOver > 0.05);
    // Dropped, it is gone; the server on screen still draws its own scene.
    show.DropHeld(ServerShow::Held::Morph);
    CHECK_FALSE(show.HasPrepared(ServerShow::Held::Morph));
    REQUIRE(show.Frame(Inputs(a, 1.0)));
    CHECK(CompareImages(ReadTexture(show.Texture(), w, h), RenderScene("midi", a.effects, RenderPath::Fragment, w, h), 1).fractionOver == 0.0);
}

int main(int argc, char** argv) {
    if (argc == 2 && std::string(argv[1]) == "render-server") return RunRenderServer(3, MakeIsfServerPost);
    return Catch::Session().run(argc, argv);
}
