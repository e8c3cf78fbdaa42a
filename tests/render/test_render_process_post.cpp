// The render process's post chain (render/render_process.h, ServerLoad::post) on llvmpipe: each
// frame a server draws through a load's ISF chain is the frame this process draws through it;
// live's servers rebuild for a post effect's save; a standby holds the program on screen; the
// chain's audio inputs; a chain that does not build fails its load with its file and line. Its
// own server as test_render_process is (/proc/self/exe render-server).
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>
#include <epoxy/gl.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "app/live_servers.h"
#include "gl_fixture.h"
#include "isf/isf.h"
#include "isf/isf_server_post.h"
#include "render/render_process.h"
#include "render/server_show.h"
#include "render_process_fixture.h"
#include "scene/scene.h"

using namespace sdfvj;
using namespace sdfvj::test;

namespace {

// `img` (top row first) through the ISF chain of `paths` in this process, as a server's post chain
// draws a frame: the same inputs (time, the time since the frame before, the frame's parameters).
std::vector<Image> ChainHere(const std::vector<std::string>& paths, const std::vector<Image>& frames, const std::vector<FrameInputs>& inputs) {
    IsfChain chain;
    std::string error;
    INFO(error);
    REQUIRE(chain.Load(paths, &error));
    GLuint tex = 0;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, kW, kH);
    std::vector<Image> out;
    for (size_t i = 0; i < frames.size(); ++i) {
        std::vector<uint8_t> rows(frames[i].rgba.size());   // GL's order: bottom row first
        for (int y = 0; y < kH; ++y)
            std::copy_n(frames[i].rgba.begin() + (long)(kH - 1 - y) * kW * 4, kW * 4, rows.begin() + (long)y * kW * 4);
        glBindTexture(GL_TEXTURE_2D, tex);
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, kW, kH, GL_RGBA, GL_UNSIGNED_BYTE, rows.data());
        IsfFrameInputs in;
        in.time = inputs[i].time;
        in.timeDelta = i == 0 ? 0.0 : inputs[i].time - inputs[i - 1].time;
        in.frame = inputs[i].frame;
        in.params = inputs[i].params;
        out.push_back(ReadTexture(chain.Render(tex, kW, kH, in)));
    }
    glDeleteTextures(1, &tex);
    return out;
}

}  // namespace

TEST_CASE("render process: a load with a post chain hands over each frame drawn through it, as this process draws it", "[render_process]") {
    const FrameTransport t = GENERATE(FrameTransport::Shm, FrameTransport::VkMemory);
    SceneInfo scene;
    std::string error;
    REQUIRE(FindScene("midi", &scene, &error));
    const std::vector<std::string> post = {ResolveIsfPath("bloom"), ResolveIsfPath("kaleidoscope")};
    RenderProcess proc;
    const RenderProcess::Ready ready = StartAndLoad(&proc, scene.path, RenderPath::Compute, t, {}, post);
    INFO(ready.text);
    REQUIRE(ready.ok);
    std::vector<FrameInputs> inputs;
    std::vector<Image> got, plain;
    for (double time : {1.0, 2.5}) {
        inputs.push_back(Inputs(scene, time));
        REQUIRE(proc.DrawFrame(inputs.back()));
        got.push_back(ReadTexture(proc.Texture()));
        plain.push_back(RenderScene("midi", scene.effects, RenderPath::Compute, kW, kH, time));
    }
    const std::vector<Image> want = ChainHere(post, plain, inputs);
    for (size_t i = 0; i < got.size(); ++i) {
        const ImageDiff d = CompareImages(got[i], want[i], 1);
        INFO("frame " << i << " (" << FrameTransportName(ready.transport) << "): max channel difference " << d.maxAbs << ", mean " << d.meanAbs);
        CHECK(d.fractionOver == 0.0);   // the same driver, programs and inputs: the same image, within rounding
        CHECK(CompareImages(got[i], plain[i], 8).fractionOver > 0.2);   // and the chain is in it: not the scene's frame
    }
}

TEST_CASE("render process: live's servers rebuild for a post effect's save, with no quick tier when the scene's program is the one on screen", "[render_process]") {
    RequireGl();
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("sdfvj_post_servers_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const std::string fs = (dir / "rgb_split.fs").string();
    std::filesystem::copy_file(ResolveIsfPath("rgb_split"), fs, std::filesystem::copy_options::overwrite_existing);
    SceneInfo scene;
    std::string error;
    REQUIRE(FindScene("midi", &scene, &error));
    const VariantKey key{scene.path, scene.effects, RenderPath::Fragment};
    LiveServers servers(true, false);   // tiered, as on NVIDIA
    servers.SetPost({fs});
    INFO(error);
    REQUIRE(servers.Start(key, kW, kH, &error));
    CHECK(servers.PostOnScreen());
    std::vector<std::string> say;
    // The effect saved: one build, the optimized program only.
    std::ofstream(fs, std::ios::app) << "\nfloat testSave() { return 1.0; }\n";
    servers.Update(key, {fs}, kW, kH, &say);
    CHECK(servers.Building());
    CHECK_FALSE(servers.Servers().BuildingQuick());
    // Then the scene's own variant (once the save's build is on screen: a newer load waits for the
    // one in flight): its quick tier builds beside it.
    for (int i = 0; i < 60000 && servers.Building(); ++i) {
        servers.Update(key, {}, kW, kH, &say);
        ::usleep(2000);
    }
    REQUIRE_FALSE(servers.Building());
    const VariantKey none{scene.path, EffectSet{}, RenderPath::Fragment};
    servers.Update(none, {}, kW, kH, &say);
    CHECK(servers.Servers().BuildingQuick());
    // A header that does not parse: said as file:line, nothing built.
    std::ofstream(fs) << "/*{ \"INPUTS\": [ }\n*/\nvoid main() { gl_FragColor = vec4(1.0); }\n";
    say.clear();
    servers.Update(none, {fs}, kW, kH, &say);
    INFO((say.empty() ? std::string() : say.back()));
    REQUIRE(!say.empty());
    CHECK(say.back().find("rgb_split.fs:1:") != std::string::npos);
    std::filesystem::remove_all(dir);
}

TEST_CASE("render process: a standby holds the program on screen, so a load of it with a post chain or at another size builds nothing", "[render_process]") {
    ServerShow show(FrameTransport::VkMemory, false, false);
    show.SetStandby(true);
    const SceneInfo scene = StartShow(&show, "midi");
    const RenderProcess::Ready first = show.Shown().back();
    CHECK_FALSE(first.fromStandby);
    std::string error;
    auto untilStandby = [&] {
        for (int i = 0; i < 60000 && !show.StandbyReady(); ++i) {
            show.Poll(&error);
            ::usleep(2000);
        }
        return show.StandbyReady();
    };
    REQUIRE(untilStandby());   // a spare built, used and drew the program on screen, and waits
    // A post chain over the same program: the standby takes it, and only the chain is new there.
    ServerLoad load = show.OnScreenLoad();
    load.post = {ResolveIsfPath("rgb_split")};
    REQUIRE(show.Load(load, &error));
    REQUIRE(PollUntilChange(&show, &error));
    const RenderProcess::Ready taken = show.Shown().back();
    INFO("first load: build " << first.buildMs << " ms, first use " << first.useMs << " ms; through the standby: build " << taken.buildMs
                              << " ms (the chain), first use " << taken.useMs << " ms");
    CHECK(taken.fromStandby);
    CHECK(show.StandbyUsed() == 1);
    CHECK(taken.useMs < 0.5 * first.useMs + 1.0);   // nothing first used (a ratio, not a time)
    const FrameInputs in = Inputs(scene, 1.0);
    REQUIRE(show.Frame(in));
    const Image want = ChainHere(load.post, {RenderScene("midi", scene.effects, RenderPath::Fragment, kW, kH, 1.0)}, {in})[0];
    CHECK(CompareImages(ReadTexture(show.Texture()), want, 1).fractionOver == 0.0);   // the same frame as built from scratch
    // Another standby follows for the program on screen; another size takes it too.
    REQUIRE(untilStandby());
    load.width = kW / 2;
    load.height = kH / 2;
    REQUIRE(show.Load(load, &error));
    REQUIRE(PollUntilChange(&show, &error));
    CHECK(show.Shown().back().fromStandby);
    CHECK(show.StandbyUsed() == 2);
    // Another variant is another program: a spare builds it.
    REQUIRE(untilStandby());
    REQUIRE(show.Load(ServerLoad{scene.path, false, EffectSet{}, RenderPath::Fragment, kW, kH}, &error));
    REQUIRE(PollUntilChange(&show, &error));
    CHECK_FALSE(show.Shown().back().fromStandby);
    CHECK(show.StandbyUsed() == 2);
}

TEST_CASE("render process: the post chain's audio inputs read the sound the show sends, silence before it", "[render_process]") {
    // audio_view.fs draws its audioFFT input in red and its audio wave in green (0.5 + 0.5 s).
    SceneInfo scene;
    std::string error;
    REQUIRE(FindScene("midi", &scene, &error));
    RenderProcess proc;
    const RenderProcess::Ready ready = StartAndLoad(&proc, scene.path, RenderPath::Fragment, FrameTransport::Shm, {},
                                                    {std::string(SDFVJ_SOURCE_DIR) + "/tests/audio/files/audio_view.fs"});
    INFO(ready.text);
    REQUIRE(ready.ok);
    auto centre = [&](int channel) {
        REQUIRE(proc.DrawFrame(Inputs(scene, 1.0)));
        const Image img = ReadTexture(proc.Texture());
        return (int)img.rgba[((size_t)(kH / 2) * kW + kW / 2) * 4 + (size_t)channel];
    };
    CHECK(centre(0) == 0);                    // silence: no spectrum,
    CHECK(std::abs(centre(1) - 128) <= 1);    // the wave at rest
    REQUIRE(proc.SetAudio(std::vector<float>(64, -0.5f), std::vector<float>(64, 0.75f)));
    CHECK(std::abs(centre(0) - 191) <= 1);
    CHECK(std::abs(centre(1) - 64) <= 1);
    REQUIRE(proc.SetAudio(std::vector<float>(512, 0.5f), std::vector<float>(512, 0.25f)));   // another size
    CHECK(std::abs(centre(0) - 64) <= 1);
    CHECK(std::abs(centre(1) - 191) <= 1);
}

TEST_CASE("render process: a post chain that does not build fails the load with its file and line", "[render_process]") {
    SceneInfo scene;
    std::string error;
    REQUIRE(FindScene("midi", &scene, &error));
    RenderProcess proc;
    const RenderProcess::Ready ready = StartAndLoad(&proc, scene.path, RenderPath::Fragment, FrameTransport::Shm, {},
                                                    {ResolveIsfPath("bloom"), std::string(SDFVJ_SOURCE_DIR) + "/tests/isf/files/syntax_error.fs"});
    INFO(ready.text);
    CHECK_FALSE(ready.ok);
    CHECK(ready.text.find("syntax_error.fs:") != std::string::npos);
}

int main(int argc, char** argv) {
    if (argc == 2 && std::string(argv[1]) == "render-server") return RunRenderServer(3, MakeIsfServerPost);
    return Catch::Session().run(argc, argv);
}
