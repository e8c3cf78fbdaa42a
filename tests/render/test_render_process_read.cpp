// The show reads a render process's frame through a framebuffer kept per image
// (RenderProcess::ReadFramebuffer, ServerShow::ReadFramebuffer): `live --render-process` and bench
// reload's render-process mode blit from it instead of attaching the image each frame. On llvmpipe,
// with the import thread as `live` has it (its frees let GL give a freed texture's name to the next
// server's image). This binary is its own server (/proc/self/exe render-server), as sdfvj is.
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>
#include <epoxy/gl.h>

#include <string>

#include "gl_fixture.h"
#include "render/import_thread.h"
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

}  // namespace

TEST_CASE("render process read: one framebuffer kept per image reads that image's latest frame, and a new server's images never read through the last one's", "[render_process]") {
    RequireGl();
    SceneInfo midi, primitives;
    std::string error;
    REQUIRE(FindScene("midi", &midi, &error));
    REQUIRE(FindScene("primitives", &primitives, &error));
    // never destroyed (Mesa once crashed a later draw after a shared context went: test_render_process.cpp)
    static HeadlessContext* importContext = [] {
        auto* c = new HeadlessContext;
        std::string why;
        return c->CreateShared(*TestContext(), &why, true) ? c : nullptr;
    }();
    REQUIRE(importContext);
    TestContext()->MakeCurrent();
    ImportThread importer([] { return importContext->MakeCurrent(); }, [] { importContext->ReleaseCurrent(); });
    REQUIRE(importer.Ok());
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
        CHECK_FALSE(glIsFramebuffer(before[0]));
        CHECK_FALSE(glIsFramebuffer(before[1]));
        before[0] = CheckFrame(&show, *next, 2.0);
        before[1] = CheckFrame(&show, *next, 4.0);
        CHECK(CheckFrame(&show, *next, 6.0) == before[0]);
    }
    CHECK(importer.Imported() == 4);
}

int main(int argc, char** argv) {
    if (argc == 2 && std::string(argv[1]) == "render-server") return RunRenderServer(3);
    return Catch::Session().run(argc, argv);
}
