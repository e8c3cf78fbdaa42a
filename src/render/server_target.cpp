#include "render/server_target.h"

#include <sys/mman.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "render/render.h"

namespace sdfvj {

ServerTarget::~ServerTarget() {
    if (drawFbo) glDeleteFramebuffers(1, &drawFbo);
    if (tex) glDeleteTextures(1, &tex);
    if (memoryObject) glDeleteMemoryObjectsEXT(1, &memoryObject);
    if (image != EGL_NO_IMAGE_KHR) eglDestroyImageKHR(eglGetCurrentDisplay(), image);
    if (shm) ::munmap(shm, bytes);
    if (fd >= 0) ::close(fd);
}

bool ServerTarget::ShareVulkan(int w, int h, std::string* why) {
    if (!shared.Create(w, h, why)) return false;
    const int mine = shared.ExportFd();
    if (mine < 0) {
        *why = "vkGetMemoryFdKHR failed";
        return false;
    }
    tex = ImportSharedTexture(mine, shared.Size(), w, h, &memoryObject, why);
    fd = tex ? shared.ExportFd() : -1;
    if (!tex || fd < 0) {
        if (why->empty()) *why = "vkGetMemoryFdKHR failed";
        return false;
    }
    memorySize = shared.Size();
    transport = FrameTransport::VkMemory;
    return true;
}

bool ServerTarget::ExportDmaBuf(int w, int h, std::string* why) {
    EGLDisplay dpy = eglGetCurrentDisplay();
    for (const char* ext : {"EGL_KHR_gl_texture_2D_image", "EGL_MESA_image_dma_buf_export"})
        if (!epoxy_has_egl_extension(dpy, ext)) {
            *why = std::string("the driver's EGL has no ") + ext;
            return false;
        }
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, w, h);
    glFinish();
    const EGLint attrs[] = {EGL_GL_TEXTURE_LEVEL_KHR, 0, EGL_NONE};
    image = eglCreateImageKHR(dpy, eglGetCurrentContext(), EGL_GL_TEXTURE_2D_KHR, (EGLClientBuffer)(uintptr_t)tex, attrs);
    int fcc = 0, planes = 0;
    EGLuint64KHR mod = 0;
    if (image == EGL_NO_IMAGE_KHR) *why = "eglCreateImageKHR of the texture failed";
    else if (!eglExportDMABUFImageQueryMESA(dpy, image, &fcc, &planes, &mod)) *why = "eglExportDMABUFImageQueryMESA failed";
    else if (planes != 1) *why = "the texture exports as " + std::to_string(planes) + " planes, expected 1";
    else if (!eglExportDMABUFImageMESA(dpy, image, &fd, &stride, &offset) || fd < 0) *why = "eglExportDMABUFImageMESA failed (EGL error " + std::to_string(eglGetError()) + ")";
    else {
        fourcc = (uint32_t)fcc;
        modifier = mod;
        transport = FrameTransport::DmaBuf;
        return true;
    }
    return false;
}
bool ServerTarget::MakeShm(int w, int h, std::string* why) {
    bytes = (size_t)w * (size_t)h * 4;
    fd = memfd_create("sdfvj-frame", MFD_CLOEXEC);
    if (fd < 0 || ::ftruncate(fd, (off_t)bytes) != 0) {
        *why = std::string("memfd: ") + std::strerror(errno);
        return false;
    }
    shm = ::mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
    if (shm == MAP_FAILED) {
        shm = nullptr;
        *why = std::string("mmap: ") + std::strerror(errno);
        return false;
    }
    transport = FrameTransport::Shm;
    return true;
}
void ServerTarget::HandOver(const FrameRenderer& fr, GLuint postRead) {
    if (transport != FrameTransport::Shm && postRead) {
        if (!drawFbo) {
            glGenFramebuffers(1, &drawFbo);
            glBindFramebuffer(GL_DRAW_FRAMEBUFFER, drawFbo);
            glFramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex, 0);
        }
        glBindFramebuffer(GL_READ_FRAMEBUFFER, postRead);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, drawFbo);
        glBlitFramebuffer(0, 0, fr.Width(), fr.Height(), 0, 0, fr.Width(), fr.Height(), GL_COLOR_BUFFER_BIT, GL_NEAREST);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        glFinish();
        return;
    }
    if (transport != FrameTransport::Shm) {
        glCopyImageSubData(fr.Texture(), GL_TEXTURE_2D, 0, 0, 0, 0, tex, GL_TEXTURE_2D, 0, 0, 0, 0, fr.Width(), fr.Height(), 1);
        glFinish();
        return;
    }
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, postRead ? postRead : fr.Framebuffer());
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, fr.Width(), fr.Height(), GL_RGBA, GL_UNSIGNED_BYTE, shm);   // waits for the frame
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
}

void WarmCompiler() {
    static const char* kText =
        "#version 430\nlayout(local_size_x = 8, local_size_y = 8) in;\n"
        "layout(rgba8, binding = 0) uniform writeonly image2D u_out;\nuniform float u_t;\n"
        "float f(vec3 p) { return length(p) - 1.0 + 0.1 * sin(p.x * u_t); }\n"
        "void main() { vec3 p = vec3(gl_GlobalInvocationID, u_t); float d = 0.0;\n"
        "  for (int i = 0; i < 16; ++i) d += f(p + d);\n"
        "  imageStore(u_out, ivec2(gl_GlobalInvocationID.xy), vec4(d)); }\n";
    const GLuint sh = glCreateShader(GL_COMPUTE_SHADER);
    glShaderSource(sh, 1, &kText, nullptr);
    glCompileShader(sh);
    const GLuint prog = glCreateProgram();
    glAttachShader(prog, sh);
    glLinkProgram(prog);
    GLint linked = 0;
    glGetProgramiv(prog, GL_LINK_STATUS, &linked);
    if (linked) {
        GLuint tex = 0;
        glGenTextures(1, &tex);
        glBindTexture(GL_TEXTURE_2D, tex);
        glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, 8, 8);
        glBindImageTexture(0, tex, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8);
        glUseProgram(prog);
        glDispatchCompute(1, 1, 1);
        glFinish();
        glUseProgram(0);
        glDeleteTextures(1, &tex);
    }
    glDeleteProgram(prog);
    glDeleteShader(sh);
}

}  // namespace sdfvj
