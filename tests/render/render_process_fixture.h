// What the render-process tests share (test_render_process*.cpp): servers started and loaded, a
// scene's inputs at a time, a texture or read framebuffer of this context read back, a show polled
// until its server on screen changes.
#pragma once
#include <catch2/catch.hpp>
#include <epoxy/gl.h>
#include <unistd.h>

#include <algorithm>
#include <string>
#include <vector>

#include "gl_fixture.h"
#include "render/render_process.h"
#include "render/server_show.h"
#include "scene/scene.h"

namespace sdfvj::test {

constexpr int kW = 64, kH = 48;

// A shipped scene by name, with the GL context the tests draw references in.
inline SceneInfo ShippedScene(const char* name) {
    RequireGl();
    SceneInfo scene;
    std::string error;
    const bool found = FindScene(name, &scene, &error);
    INFO(name << ": " << error);
    REQUIRE(found);
    return scene;
}

inline FrameInputs Inputs(const SceneInfo& scene, double time) {
    FrameInputs in;
    in.time = time;
    for (const ParamDecl& d : scene.params) in.params.emplace_back(d.name, d.defaultValue);
    return in;
}

// What framebuffer `fbo` reads (w x h), top row first (as FrameRenderer::ReadPixels).
inline Image ReadFramebufferImage(unsigned fbo, int w = kW, int h = kH) {
    glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
    std::vector<uint8_t> raw((size_t)w * h * 4);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, raw.data());
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    Image img{w, h, std::vector<uint8_t>(raw.size())};
    for (int y = 0; y < h; ++y)
        std::copy_n(raw.begin() + (long)y * w * 4, w * 4, img.rgba.begin() + (long)(h - 1 - y) * w * 4);
    return img;
}

// The render process's frame as this context sees it, through a framebuffer of its own.
inline Image ReadTexture(unsigned texture, int w = kW, int h = kH) {
    GLuint fbo = 0;
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    Image img = ReadFramebufferImage(fbo, w, h);
    glDeleteFramebuffers(1, &fbo);
    return img;
}

// Polls the show until the server on screen changes or a build fails (*error), up to 120 s.
inline bool PollUntilChange(ServerShow* show, std::string* error) {
    for (int i = 0; i < 60000; ++i) {
        if (show->Poll(error)) return true;
        if (!error->empty()) return false;
        ::usleep(2000);
    }
    *error = "nothing changed in 120 s";
    return false;
}

// post: the load's post chain (ServerLoad::post).
inline RenderProcess::Ready StartAndLoad(RenderProcess* proc, const std::string& scenePath, RenderPath path, FrameTransport t,
                                  const std::vector<std::string>& env = {}, const std::vector<std::string>& post = {}) {
    RequireGl();
    std::string error;
    INFO(error);
    REQUIRE(proc->Start(&error, "/proc/self/exe", env));
    ServerLoad load{scenePath, true, {}, path, kW, kH};
    load.post = post;
    REQUIRE(proc->Load(load, t));
    RenderProcess::Ready ready;
    REQUIRE(proc->PollReady(&ready, 120000));
    return ready;
}

// A load of `path` with its own effects at the tests' size.
inline ServerLoad OwnEffects(const std::string& path) { return ServerLoad{path, true, {}, RenderPath::Fragment, kW, kH}; }

// `show` started on scene `name` (its own effects, fragment path); returns the scene.
inline SceneInfo StartShow(ServerShow* show, const char* name) {
    RequireGl();
    SceneInfo scene;
    std::string error;
    REQUIRE(FindScene(name, &scene, &error));
    INFO(error);
    REQUIRE(show->Start(OwnEffects(scene.path), &error));
    return scene;
}

}  // namespace sdfvj::test
