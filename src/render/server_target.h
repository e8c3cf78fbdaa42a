// The render server's side of a frame's hand-over (render_server.cpp, `sdfvj render-server`): the
// image a frame is handed over in (a Vulkan-allocated image, a dma-buf or shared memory) and the
// compiler warmed while a spare waits. The server's own: the show's side is render_process.h.
#pragma once
#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <cstddef>
#include <cstdint>
#include <string>

#include "render/render.h"
#include "render/render_process.h"
#include "render/render_wire.h"
#include "render/shared_image.h"

namespace sdfvj {

// One image the server hands its frames over in, and what the show needs to import it (fd, and a
// dma-buf's layout). Its GL objects are freed with it (the server's context current).
struct ServerTarget {
    FrameTransport transport = FrameTransport::Shm;
    GLuint tex = 0;
    EGLImageKHR image = EGL_NO_IMAGE_KHR;
    void* shm = nullptr;
    size_t bytes = 0;
    int fd = -1;
    uint32_t fourcc = 0;
    uint64_t modifier = render_wire::kModInvalid;
    int32_t stride = 0, offset = 0;
    uint64_t memorySize = 0;
    SharedImage shared;
    GLuint memoryObject = 0;
    GLuint drawFbo = 0;   // tex attached: what a post chain's output is blitted into
    std::string note;

    ServerTarget() = default;
    ServerTarget(const ServerTarget&) = delete;
    ServerTarget& operator=(const ServerTarget&) = delete;
    ~ServerTarget();   // GL's objects first (the context is current), then the Vulkan image they import

    bool ShareVulkan(int w, int h, std::string* why);   // a Vulkan-allocated image, imported here too
    bool ExportDmaBuf(int w, int h, std::string* why);  // a texture exported as a dma-buf
    bool MakeShm(int w, int h, std::string* why);       // shared memory (a memfd)
    // The frame in `fr` handed over, or where a post chain drew it over the frame, its output
    // (postRead: a framebuffer reading it, of the frame's size; RGBA8 or RGBA32F, so blitted, not
    // copied); done on the GPU when this returns.
    void HandOver(const FrameRenderer& fr, GLuint postRead = 0);
};

// The driver's compiler is loaded and set up at a process's first compile (NVIDIA: 100-200 ms):
// a spare server compiles, links and runs a small program first, so a save pays only its own.
void WarmCompiler();

}  // namespace sdfvj
