#include "render/render_process.h"

#include <epoxy/egl.h>
#include <epoxy/gl.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/mman.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <type_traits>

#include "render/compile_worker.h"
#include "render/shared_image.h"
#include "scene/scene.h"
#include "shader/shader.h"

extern char** environ;

namespace sdfvj {

namespace {

using Clock = std::chrono::steady_clock;
double MsSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

constexpr uint64_t kModInvalid = 0x00ffffffffffffffULL;   // DRM_FORMAT_MOD_INVALID
constexpr uint32_t kMaxPayload = 1u << 20;                 // a frame's inputs or a scene path: far less
static_assert(std::is_trivially_copyable_v<Quality>, "Quality crosses the socket as bytes");

template <typename T>
void Put(std::string* out, T v) {
    out->append(reinterpret_cast<const char*>(&v), sizeof v);
}
void PutText(std::string* out, const std::string& s) {
    Put<uint32_t>(out, (uint32_t)s.size());
    out->append(s);
}
template <typename T>
bool Take(const std::string& in, size_t* at, T* v) {
    if (in.size() < *at + sizeof(T)) return false;
    std::memcpy(v, in.data() + *at, sizeof(T));
    *at += sizeof(T);
    return true;
}
bool TakeText(const std::string& in, size_t* at, std::string* s) {
    uint32_t n = 0;
    if (!Take(in, at, &n) || in.size() - *at < n) return false;
    s->assign(in, *at, n);
    *at += n;
    return true;
}
std::string Message(uint32_t type, const std::string& payload) {
    std::string m;
    Put<uint32_t>(&m, type);
    Put<uint32_t>(&m, (uint32_t)payload.size());
    return m + payload;
}

// Sends all of `bytes`, with `fd` (when >= 0) riding on the first byte.
bool SendAll(int sock, const std::string& bytes, int fd = -1) {
    size_t at = 0;
    while (at < bytes.size()) {
        msghdr msg{};
        iovec iov{const_cast<char*>(bytes.data() + at), bytes.size() - at};
        msg.msg_iov = &iov;
        msg.msg_iovlen = 1;
        alignas(cmsghdr) char control[CMSG_SPACE(sizeof(int))] = {};
        if (fd >= 0 && at == 0) {
            msg.msg_control = control;
            msg.msg_controllen = sizeof control;
            cmsghdr* c = CMSG_FIRSTHDR(&msg);
            c->cmsg_level = SOL_SOCKET;
            c->cmsg_type = SCM_RIGHTS;
            c->cmsg_len = CMSG_LEN(sizeof(int));
            std::memcpy(CMSG_DATA(c), &fd, sizeof(int));
        }
        const ssize_t put = ::sendmsg(sock, &msg, MSG_NOSIGNAL);
        if (put < 0 && (errno == EINTR || errno == EAGAIN)) {
            if (errno == EAGAIN) {
                pollfd p{sock, POLLOUT, 0};
                ::poll(&p, 1, 100);
            }
            continue;
        }
        if (put <= 0) return false;
        at += (size_t)put;
    }
    return true;
}

bool ReadAll(int fd, void* buf, size_t n) {
    char* p = static_cast<char*>(buf);
    while (n > 0) {
        const ssize_t got = ::read(fd, p, n);
        if (got < 0 && errno == EINTR) continue;
        if (got <= 0) return false;
        p += got;
        n -= (size_t)got;
    }
    return true;
}

std::string EncodeInputs(const FrameInputs& in) {
    std::string p;
    Put(&p, in.time);
    Put<int32_t>(&p, in.frame);
    Put(&p, in.beat);
    Put(&p, in.bpm);
    Put(&p, in.quality);
    Put<int32_t>(&p, in.effectsOff);
    Put(&p, in.orbitYaw);
    Put(&p, in.orbitPitch);
    Put<uint32_t>(&p, (uint32_t)in.params.size());
    for (const auto& [name, value] : in.params) {
        PutText(&p, name);
        Put(&p, value);
    }
    return p;
}

bool DecodeInputs(const std::string& p, FrameInputs* in) {
    size_t at = 0;
    int32_t frame = 0, off = 0;
    uint32_t n = 0;
    if (!Take(p, &at, &in->time) || !Take(p, &at, &frame) || !Take(p, &at, &in->beat) || !Take(p, &at, &in->bpm) ||
        !Take(p, &at, &in->quality) || !Take(p, &at, &off) || !Take(p, &at, &in->orbitYaw) ||
        !Take(p, &at, &in->orbitPitch) || !Take(p, &at, &n) || n > 4096)
        return false;
    in->frame = frame;
    in->effectsOff = off;
    in->params.clear();
    for (uint32_t i = 0; i < n; ++i) {
        std::string name;
        float v = 0;
        if (!TakeText(p, &at, &name) || !Take(p, &at, &v)) return false;
        in->params.emplace_back(std::move(name), v);
    }
    return at == p.size();
}

// The server's hand-over target: a dma-buf exported texture, or shared memory.
struct ServerTarget {
    FrameTransport transport = FrameTransport::Shm;
    GLuint tex = 0;
    EGLImageKHR image = EGL_NO_IMAGE_KHR;
    void* shm = nullptr;
    size_t bytes = 0;
    int fd = -1;
    uint32_t fourcc = 0;
    uint64_t modifier = kModInvalid;
    int32_t stride = 0, offset = 0;
    uint64_t memorySize = 0;
    SharedImage shared;
    GLuint memoryObject = 0;
    std::string note;

    bool ShareVulkan(int w, int h, std::string* why) {
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

    bool ExportDmaBuf(int w, int h, std::string* why) {
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
    bool MakeShm(int w, int h, std::string* why) {
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
    // The frame in `fr` handed over; done on the GPU when this returns.
    void HandOver(const FrameRenderer& fr) {
        if (transport != FrameTransport::Shm) {
            glCopyImageSubData(fr.Texture(), GL_TEXTURE_2D, 0, 0, 0, 0, tex, GL_TEXTURE_2D, 0, 0, 0, 0, fr.Width(), fr.Height(), 1);
            glFinish();
            return;
        }
        glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, fr.Framebuffer());
        glPixelStorei(GL_PACK_ALIGNMENT, 4);
        glReadPixels(0, 0, fr.Width(), fr.Height(), GL_RGBA, GL_UNSIGNED_BYTE, shm);   // waits for the frame
        glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    }
};

// The driver's compiler is loaded and set up at a process's first compile (NVIDIA: 100-200 ms):
// a spare server compiles, links and runs a small program first, so a save pays only its own.
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

}  // namespace

const char* FrameTransportName(FrameTransport t) {
    return t == FrameTransport::VkMemory ? "vkmem" : t == FrameTransport::DmaBuf ? "dmabuf" : "shm";
}

RenderProcess::~RenderProcess() {
    Stop();
    if (pid_ > 0) {
        int status = 0;
        ::waitpid(pid_, &status, 0);
    }
}

void RenderProcess::Stop() {
    if (fd_ >= 0) ::close(fd_);   // EOF: the server exits
    fd_ = -1;
    dead_ = true;
    for (int fd : fds_) ::close(fd);
    fds_.clear();
    if (pid_ > 0 && !killed_) ::kill(pid_, SIGTERM);   // it may be in a compile of seconds; it has nothing to save
    killed_ = true;
    if (texture_) glDeleteTextures(1, &texture_);
    texture_ = 0;
    if (image_) eglDestroyImageKHR(eglGetCurrentDisplay(), (EGLImageKHR)image_);
    image_ = nullptr;
    if (memory_) glDeleteMemoryObjectsEXT(1, &memory_);
    memory_ = 0;
    if (shm_) ::munmap(shm_, shmBytes_);
    shm_ = nullptr;
}

bool RenderProcess::TryReap() {
    if (pid_ <= 0) return true;
    int status = 0;
    if (::waitpid(pid_, &status, WNOHANG) == 0) return false;
    pid_ = -1;
    return true;
}

bool RenderProcess::Start(std::string* error, const std::string& exe) {
    int sv[2];
    if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv) != 0) {
        *error = std::string("render process: socketpair: ") + std::strerror(errno);
        return false;
    }
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, sv[1], 3);   // dup2 clears CLOEXEC on fd 3
    std::vector<char*> argv{const_cast<char*>(exe.c_str()), const_cast<char*>("render-server"), nullptr};
    pid_t pid = -1;
    const int rc = posix_spawn(&pid, exe.c_str(), &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    ::close(sv[1]);
    if (rc != 0) {
        ::close(sv[0]);
        *error = "render process: cannot start " + exe + ": " + std::strerror(rc);
        return false;
    }
    fd_ = sv[0];
    pid_ = pid;
    ::fcntl(fd_, F_SETFL, ::fcntl(fd_, F_GETFL) | O_NONBLOCK);
    return true;
}

void RenderProcess::MarkDead() { dead_ = true; }

bool RenderProcess::Send(const std::string& message) {
    if (!Usable()) return false;
    if (!SendAll(fd_, message)) MarkDead();
    return Usable();
}

bool RenderProcess::Load(const std::string& scenePath, RenderPath path, int width, int height, FrameTransport transport, bool quick) {
    std::string p;
    Put<uint32_t>(&p, (uint32_t)path);
    Put<int32_t>(&p, width);
    Put<int32_t>(&p, height);
    Put<uint32_t>(&p, (uint32_t)transport);
    Put<uint32_t>(&p, quick ? 1 : 0);
    PutText(&p, scenePath);
    width_ = width;
    height_ = height;
    return Send(Message(1, p));
}

bool RenderProcess::Receive(int timeoutMs) {
    if (!Usable()) return false;
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, timeoutMs) <= 0) return true;   // nothing yet
    for (;;) {
        char buf[65536];
        iovec iov{buf, sizeof buf};
        alignas(cmsghdr) char control[CMSG_SPACE(sizeof(int) * 4)];
        msghdr msg{};
        msg.msg_iov = &iov;
        msg.msg_iovlen = 1;
        msg.msg_control = control;
        msg.msg_controllen = sizeof control;
        const ssize_t got = ::recvmsg(fd_, &msg, MSG_CMSG_CLOEXEC);
        if (got < 0 && errno == EINTR) continue;
        if (got < 0 && errno == EAGAIN) return true;
        if (got <= 0) {
            MarkDead();
            return false;
        }
        for (cmsghdr* c = CMSG_FIRSTHDR(&msg); c; c = CMSG_NXTHDR(&msg, c))
            if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SCM_RIGHTS) {
                const size_t n = (c->cmsg_len - CMSG_LEN(0)) / sizeof(int);
                for (size_t i = 0; i < n; ++i) {
                    int fd = -1;
                    std::memcpy(&fd, CMSG_DATA(c) + i * sizeof(int), sizeof(int));
                    fds_.push_back(fd);
                }
            }
        inbox_.append(buf, (size_t)got);
        if ((size_t)got < sizeof buf) return true;
    }
}

bool RenderProcess::TakeMessage(uint32_t* type, std::string* payload) {
    size_t at = 0;
    uint32_t n = 0;
    if (!Take(inbox_, &at, type) || !Take(inbox_, &at, &n)) return false;
    if (n > kMaxPayload) {   // not our server: stop listening to it
        MarkDead();
        return false;
    }
    if (inbox_.size() - at < n) return false;
    payload->assign(inbox_, at, n);
    inbox_.erase(0, at + n);
    return true;
}

bool RenderProcess::PollReady(Ready* ready, int timeoutMs) {
    const auto t0 = Clock::now();
    uint32_t type = 0;
    std::string payload;
    for (;;) {
        if (TakeMessage(&type, &payload)) break;
        const int left = timeoutMs - (int)MsSince(t0);
        if (!Usable()) {
            ready->ok = false;
            ready->text = "the render process ended before its program was ready";
            return true;
        }
        Receive(left > 0 ? left : 0);
        if (TakeMessage(&type, &payload)) break;
        if (MsSince(t0) >= timeoutMs) return false;
    }
    if (type != 1) {
        MarkDead();
        ready->ok = false;
        ready->text = "the render process answered out of turn";
        return true;
    }
    if (!Import(payload, ready)) ready->ok = false;
    return true;
}

bool RenderProcess::Import(const std::string& payload, Ready* ready) {
    size_t at = 0;
    uint32_t ok = 0, transport = 0, fourcc = 0;
    uint64_t modifier = 0, memorySize = 0;
    int32_t stride = 0, offset = 0;
    if (!Take(payload, &at, &ok) || !Take(payload, &at, &transport) || !Take(payload, &at, &ready->buildMs) ||
        !Take(payload, &at, &ready->useMs) || !Take(payload, &at, &ready->firstFrameMs) || !Take(payload, &at, &fourcc) ||
        !Take(payload, &at, &modifier) || !Take(payload, &at, &stride) || !Take(payload, &at, &offset) ||
        !Take(payload, &at, &memorySize) || !TakeText(payload, &at, &ready->text)) {
        ready->text = "the render process's answer is malformed";
        return false;
    }
    ready->transport = transport_ = transport == 2 ? FrameTransport::VkMemory : transport == 1 ? FrameTransport::DmaBuf : FrameTransport::Shm;
    ready->ok = ok != 0;
    if (!ready->ok) return false;
    if (fds_.empty()) {
        ready->text = "the render process sent no frame buffer";
        return false;
    }
    const int fd = fds_.front();
    fds_.erase(fds_.begin());
    if (transport_ == FrameTransport::VkMemory) {
        std::string why;
        texture_ = ImportSharedTexture(fd, memorySize, width_, height_, &memory_, &why);
        if (!texture_) ready->text = "the render process's image could not be imported here: " + why;
        return texture_ != 0;
    }
    glGenTextures(1, &texture_);
    glBindTexture(GL_TEXTURE_2D, texture_);
    if (transport_ == FrameTransport::Shm) {
        shmBytes_ = (size_t)width_ * (size_t)height_ * 4;
        void* p = ::mmap(nullptr, shmBytes_, PROT_READ, MAP_SHARED, fd, 0);
        ::close(fd);
        if (p == MAP_FAILED) {
            ready->text = std::string("mmap of the frame: ") + std::strerror(errno);
            return false;
        }
        shm_ = p;
        glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, width_, height_);
        return true;
    }
    EGLDisplay dpy = eglGetCurrentDisplay();
    if (!epoxy_has_egl_extension(dpy, "EGL_EXT_image_dma_buf_import")) {
        ::close(fd);
        ready->text = "this EGL cannot import a dma-buf (no EGL_EXT_image_dma_buf_import)";
        return false;
    }
    std::vector<EGLint> attrs{EGL_WIDTH, width_, EGL_HEIGHT, height_, EGL_LINUX_DRM_FOURCC_EXT, (EGLint)fourcc,
                              EGL_DMA_BUF_PLANE0_FD_EXT, fd, EGL_DMA_BUF_PLANE0_OFFSET_EXT, offset,
                              EGL_DMA_BUF_PLANE0_PITCH_EXT, stride};
    if (modifier != kModInvalid && epoxy_has_egl_extension(dpy, "EGL_EXT_image_dma_buf_import_modifiers")) {
        attrs.insert(attrs.end(), {EGL_DMA_BUF_PLANE0_MODIFIER_LO_EXT, (EGLint)(modifier & 0xffffffffu),
                                   EGL_DMA_BUF_PLANE0_MODIFIER_HI_EXT, (EGLint)(modifier >> 32)});
    }
    attrs.push_back(EGL_NONE);
    EGLImageKHR image = eglCreateImageKHR(dpy, EGL_NO_CONTEXT, EGL_LINUX_DMA_BUF_EXT, nullptr, attrs.data());
    ::close(fd);   // the image holds the buffer
    if (image == EGL_NO_IMAGE_KHR) {
        ready->text = "eglCreateImageKHR of the dma-buf failed (EGL error " + std::to_string(eglGetError()) + ")";
        return false;
    }
    image_ = image;
    glEGLImageTargetTexture2DOES(GL_TEXTURE_2D, image);
    if (glGetError() != GL_NO_ERROR) {
        ready->text = "glEGLImageTargetTexture2DOES refused the dma-buf";
        return false;
    }
    return true;
}

bool RenderProcess::Request(const FrameInputs& in) {
    if (outstanding_ || !texture_ || !Send(Message(2, EncodeInputs(in)))) return false;
    outstanding_ = true;
    return true;
}

bool RenderProcess::Arrived() {
    if (!outstanding_) return false;
    Receive(0);
    size_t at = 0;
    uint32_t type = 0, n = 0;
    return Take(inbox_, &at, &type) && Take(inbox_, &at, &n) && inbox_.size() - at >= n;
}

bool RenderProcess::Collect(int timeoutMs) {
    if (!outstanding_) return false;
    outstanding_ = false;
    const auto t0 = Clock::now();
    uint32_t type = 0;
    std::string payload;
    while (!TakeMessage(&type, &payload)) {
        const int left = timeoutMs - (int)MsSince(t0);
        if (left <= 0 || !Receive(left)) {
            if (left <= 0) MarkDead();   // a server that stops answering is not waited for again
            return false;
        }
    }
    size_t at = 0;
    if (type != 2 || !Take(payload, &at, &lastServerMs_)) {
        MarkDead();
        return false;
    }
    if (transport_ == FrameTransport::Shm) {
        glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
        glBindTexture(GL_TEXTURE_2D, texture_);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, shm_);
    }
    return true;
}

int RunRenderServer(int fd) {
    ::signal(SIGPIPE, SIG_IGN);
    HeadlessContext gl;
    std::string glError;
    const bool glOk = gl.Create(&glError);
    if (glOk) WarmCompiler();   // a spare does this while it waits, off the save's path
    SceneInfo scene;
    Program program;
    FrameRenderer fr;
    ServerTarget target;
    bool loaded = false;
    for (;;) {
        uint32_t header[2];
        if (!ReadAll(fd, header, sizeof header) || header[1] > kMaxPayload) return 0;
        std::string payload(header[1], '\0');
        if (!ReadAll(fd, payload.data(), payload.size())) return 0;
        if (header[0] == 2 && loaded) {
            FrameInputs in;
            if (!DecodeInputs(payload, &in)) return 3;
            const auto t0 = Clock::now();
            fr.Draw(program, scene, in);
            target.HandOver(fr);
            std::string p;
            Put(&p, MsSince(t0));
            if (!SendAll(fd, Message(2, p))) return 0;
            continue;
        }
        if (header[0] != 1 || loaded) return 3;   // out of turn: the show is not ours
        size_t at = 0;
        uint32_t path = 0, transport = 0, quick = 0;
        int32_t w = 0, h = 0;
        std::string scenePath, error;
        if (!Take(payload, &at, &path) || !Take(payload, &at, &w) || !Take(payload, &at, &h) ||
            !Take(payload, &at, &transport) || !Take(payload, &at, &quick) || !TakeText(payload, &at, &scenePath))
            return 3;
        const RenderPath rp = path == (uint32_t)RenderPath::Compute ? RenderPath::Compute : RenderPath::Fragment;
        double buildMs = 0, useMs = 0, frameMs = 0;
        bool ok = glOk;
        if (!glOk) error = glError;
        ShaderSource src;
        if (ok) ok = LoadScene(scenePath, &scene, &error) && AssembleProgram(scene, VariantKey{scenePath, scene.effects, rp}, &src, &error);
        if (ok && quick) src.text = QuickTierText(src.text);
        auto t0 = Clock::now();
        if (ok) ok = program.Build(src, rp, &error);
        buildMs = MsSince(t0);
        FrameInputs in;
        for (const ParamDecl& d : scene.params) in.params.emplace_back(d.name, d.defaultValue);
        if (ok) ok = fr.Resize(w, h, &error);
        if (ok) {
            t0 = Clock::now();
            PrimeProgram(program.Id(), rp, false);   // the driver's first use, here
            glFinish();
            useMs = MsSince(t0);
            t0 = Clock::now();
            fr.Draw(program, scene, in);
            glFinish();
            frameMs = MsSince(t0);
            std::string why, why2;
            if (transport != 0 && !target.ShareVulkan(w, h, &why) && !target.ExportDmaBuf(w, h, &why2))
                target.note = "GPU hand-over refused (Vulkan image: " + why + "; dma-buf: " + why2 + "): shared memory instead";
            else if (transport != 0 && target.transport == FrameTransport::DmaBuf)
                target.note = "Vulkan image refused (" + why + "): dma-buf";
            if (target.transport == FrameTransport::Shm && !target.MakeShm(w, h, &error)) ok = false;
            if (ok) target.HandOver(fr);
        }
        std::string p;
        Put<uint32_t>(&p, ok ? 1 : 0);
        Put<uint32_t>(&p, (uint32_t)target.transport);
        Put(&p, buildMs);
        Put(&p, useMs);
        Put(&p, frameMs);
        Put<uint32_t>(&p, target.fourcc);
        Put<uint64_t>(&p, target.modifier);
        Put<int32_t>(&p, target.stride);
        Put<int32_t>(&p, target.offset);
        Put<uint64_t>(&p, target.memorySize);
        PutText(&p, ok ? target.note : error);
        if (!SendAll(fd, Message(1, p), ok ? target.fd : -1)) return 0;
        if (!ok) return 1;
        if (target.transport != FrameTransport::Shm) {
            ::close(target.fd);   // the show holds it now
            target.fd = -1;
        }
        loaded = true;
    }
}

}  // namespace sdfvj
