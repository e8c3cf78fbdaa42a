#include "render/render_process.h"

#include <epoxy/egl.h>
#include <epoxy/gl.h>
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <linux/sockios.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <sys/socket.h>
#include <sys/wait.h>

#include <algorithm>

#include "render/render_wire.h"
#include "render/shared_image.h"

extern char** environ;

namespace sdfvj {

using namespace render_wire;

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
    FreeImages();
}

void RenderProcess::FreeImages() {
    if (importing_ && importing_->Abandon()) {   // done: its textures are ours to free (below)
        for (int i = 0; i < 2; ++i) {
            textures_[i] = importing_->textures[i];
            memories_[i] = importing_->memories[i];
        }
    }
    importing_.reset();
    DropReadFramebuffers();   // before the images go: a name freed may come back as another server's image
    if (importer_ && importer_->Settings().freeThere && textures_[0] && transport_ == FrameTransport::VkMemory) {
        // Freed on the import thread once this context's reads of them are done.
        GLsync fence = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
        glFlush();
        importer_->Free(textures_, memories_, fence);
        for (int i = 0; i < 2; ++i) textures_[i] = memories_[i] = 0;
    }
    for (int i = 0; i < 2; ++i) {
        if (reads_[i]) glDeleteSync((GLsync)reads_[i]);
        reads_[i] = nullptr;
        if (textures_[i]) glDeleteTextures(1, &textures_[i]);
        textures_[i] = 0;
        if (memories_[i]) glDeleteMemoryObjectsEXT(1, &memories_[i]);
        memories_[i] = 0;
    }
    texture_ = 0;
    if (image_) eglDestroyImageKHR(eglGetCurrentDisplay(), (EGLImageKHR)image_);
    image_ = nullptr;
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

bool RenderProcess::Start(std::string* error, const std::string& exe, const std::vector<std::string>& env) {
    int sv[2];
    if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv) != 0) {
        *error = std::string("render process: socketpair: ") + std::strerror(errno);
        return false;
    }
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, sv[1], 3);   // dup2 clears CLOEXEC on fd 3
    std::vector<char*> argv{const_cast<char*>(exe.c_str()), const_cast<char*>("render-server"), nullptr};
    // This process's environment, with `env`'s NAME=value entries over it.
    std::vector<char*> envp;
    for (char** e = environ; *e; ++e) {
        const std::string entry(*e);
        const bool replaced = std::any_of(env.begin(), env.end(), [&](const std::string& o) {
            const size_t eq = o.find('=');
            return eq != std::string::npos && entry.compare(0, eq + 1, o, 0, eq + 1) == 0;
        });
        if (!replaced) envp.push_back(*e);
    }
    for (const std::string& o : env) envp.push_back(const_cast<char*>(o.c_str()));
    envp.push_back(nullptr);
    pid_t pid = -1;
    const int rc = posix_spawn(&pid, exe.c_str(), &actions, nullptr, argv.data(), envp.data());
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

namespace {
std::string LoadPayload(const ServerLoad& load, FrameTransport transport, bool quick) {
    std::string p;
    Put<uint32_t>(&p, (uint32_t)load.path);
    Put<int32_t>(&p, load.width);
    Put<int32_t>(&p, load.height);
    Put<uint32_t>(&p, (uint32_t)transport);
    Put<uint32_t>(&p, quick ? 1 : 0);
    PutText(&p, load.scenePath);
    Put<uint32_t>(&p, load.sceneEffects ? 0 : 1);
    if (!load.sceneEffects) Put(&p, load.effects);
    Put<uint32_t>(&p, load.lifted ? 1 : 0);
    PutText(&p, load.morphFrom);
    Put<uint32_t>(&p, (uint32_t)load.post.size());
    for (const std::string& f : load.post) PutText(&p, f);
    return p;
}
}  // namespace

bool RenderProcess::Load(const ServerLoad& load, FrameTransport transport, bool quick) {
    width_ = load.width;
    height_ = load.height;
    return Send(Message(1, LoadPayload(load, transport, quick)));
}

bool RenderProcess::PrepareImages(int width, int height, FrameTransport transport) {
    if (prepareAsked_) return false;
    width_ = width;
    height_ = height;
    prepareAsked_ = true;
    std::string p;
    Put<int32_t>(&p, width);
    Put<int32_t>(&p, height);
    Put<uint32_t>(&p, transport == FrameTransport::Shm ? 0u : 1u);
    return Send(Message(7, p));
}

bool RenderProcess::TakePrepared(int timeoutMs) {
    if (!prepareAsked_ || prepareTaken_) return true;
    uint32_t type = 0;
    std::string payload;
    if (!Answer(&type, &payload, timeoutMs)) return false;
    prepareTaken_ = true;
    if (type != 7) {   // a prepare is answered first
        MarkDead();
        return false;
    }
    Ready ignored;
    bool pending = false;
    prepared_ = Import(payload, &ignored, &pending);   // ok 0 (none made): nothing imported, and the load brings them
    return true;
}

bool RenderProcess::SendInputsOfNow(const FrameInputs& in) {
    // The socket's memory of what the server has not read (about 800 bytes a message): 16 KB is some 20
    // frames, a tenth of Linux's default send buffer (208 KB), so a send never waits; a longer build's
    // first frame is asked for. 96 KB (2 s of frames) made `soak.sh --quick --render-process` fail in
    // 2 of 3 runs on llvmpipe (docs/performance.md, "Session 42"): kept at 16 KB.
    int queued = 0;
    if (!Usable() || ::ioctl(fd_, SIOCOUTQ, &queued) != 0 || queued > 16 * 1024) return false;
    std::string p;
    Put<uint32_t>(&p, inputsSeq_ + 1);
    p += EncodeInputs(in);
    if (!Send(Message(8, p))) return false;
    ++inputsSeq_;
    return true;
}

bool RenderProcess::BuildAhead(const ServerLoad& load) { return Send(Message(4, LoadPayload(load, FrameTransport::Shm, false))); }

bool RenderProcess::Answer(uint32_t* type, std::string* payload, int timeoutMs) {
    const auto t0 = Clock::now();
    for (;;) {
        if (TakeMessage(type, payload)) return true;
        const int left = timeoutMs - (int)MsSince(t0);
        if (!Usable()) return false;
        Receive(left > 0 ? left : 0);
        if (TakeMessage(type, payload)) return true;
        if (MsSince(t0) >= timeoutMs) return false;
    }
}

bool RenderProcess::PollBuiltAhead(BuiltAhead* built, int timeoutMs) {
    uint32_t type = 0;
    std::string payload;
    if (!TakePrepared(timeoutMs) || !Answer(&type, &payload, timeoutMs)) {   // a prepare's answer comes first
        if (Usable()) return false;
        built->ok = false;
        built->text = "the render process ended while it built";
        return true;
    }
    size_t at = 0;
    uint32_t ok = 0, cached = 0;
    if (type != 4 || !Take(payload, &at, &ok) || !Take(payload, &at, &cached) || !Take(payload, &at, &built->buildMs) ||
        !TakeText(payload, &at, &built->text)) {
        MarkDead();
        built->ok = false;
        built->text = "the render process answered out of turn";
        return true;
    }
    built->ok = ok != 0;
    built->fromCache = cached != 0;
    return true;
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
    const auto start = Clock::now();
    if (importing_ && loadAnswered_) return FinishImport(ready, timeoutMs);
    uint32_t type = 0;
    std::string payload;
    if (!TakePrepared(timeoutMs) || !Answer(&type, &payload, timeoutMs - (int)MsSince(start))) {
        if (Usable()) return false;
        ready->ok = false;
        ready->text = "the render process ended before its program was ready";
        return true;
    }
    if (type != 1) {
        MarkDead();
        ready->ok = false;
        ready->text = "the render process answered out of turn";
        return true;
    }
    loadAnswered_ = true;
    const auto t0 = Clock::now();
    bool pending = false;
    if (!Import(payload, ready, &pending)) ready->ok = false;
    ready->importMs = MsSince(t0);
    if (!pending) return true;
    importingReady_ = *ready;
    return FinishImport(ready, timeoutMs - (int)MsSince(start));
}

bool RenderProcess::FinishImport(Ready* ready, int timeoutMs) {
    if (!importing_->WaitDone(timeoutMs)) return false;
    const auto t0 = Clock::now();
    ImportThread::Job& job = *importing_;
    *ready = importingReady_;
    ready->importThreadMs = job.ms;
    for (int i = 0; i < 2; ++i) {
        textures_[i] = job.textures[i];
        memories_[i] = job.memories[i];
    }
    importing_.reset();
    DropReadFramebuffers();
    texture_ = textures_[0];
    images_ = textures_[1] ? 2 : 1;
    if (!texture_) {
        ready->ok = false;
        ready->text = "the render process's image could not be imported here: " + job.why;
    }
    ready->importMs += MsSince(t0);
    return true;
}

bool RenderProcess::Import(const std::string& payload, Ready* ready, bool* pending) {
    size_t at = 0;
    uint32_t ok = 0, transport = 0, fourcc = 0, cached = 0, images = 0, standby = 0, optimized = 0, ahead = 0, seq = 0;
    uint64_t modifier = 0, memorySize = 0;
    int32_t stride = 0, offset = 0;
    if (!Take(payload, &at, &ok) || !Take(payload, &at, &transport) || !Take(payload, &at, &ready->buildMs) ||
        !Take(payload, &at, &ready->useMs) || !Take(payload, &at, &ready->firstFrameMs) || !Take(payload, &at, &fourcc) ||
        !Take(payload, &at, &modifier) || !Take(payload, &at, &stride) || !Take(payload, &at, &offset) ||
        !Take(payload, &at, &memorySize) || !TakeText(payload, &at, &ready->text) || !Take(payload, &at, &cached) ||
        !Take(payload, &at, &images) || images < 1 || images > 2 || (images == 2 && transport != 2) || !Take(payload, &at, &ready->shareMs) ||
        !Take(payload, &at, &standby) || !Take(payload, &at, &optimized) || !Take(payload, &at, &ahead) || !Take(payload, &at, &seq)) {
        ready->text = "the render process's answer is malformed";
        return false;
    }
    ready->transport = transport_ = transport == 2 ? FrameTransport::VkMemory : transport == 1 ? FrameTransport::DmaBuf : FrameTransport::Shm;
    ready->ok = ok != 0;
    ready->fromCache = cached != 0;
    ready->fromStandby = standby != 0;
    ready->optimized = optimized != 0;
    ready->imagesAhead = ahead != 0;
    ready->firstSeq = seq;
    if (!ready->ok) return false;
    if (ahead) {   // the images came with the prepare's answer (TakePrepared): imported, or still importing
        if (!prepared_) {
            ready->text = "the render process made its images ahead, but they could not be imported here";
            return false;
        }
        shown_ = 0;
        *pending = importing_ != nullptr;
        return texture_ != 0 || *pending;
    }
    if (prepared_) {   // made ahead for another size: this load brings its own
        FreeImages();
        prepared_ = false;
    }
    if (fds_.empty()) {
        ready->text = "the render process sent no frame buffer";
        return false;
    }
    if (fds_.size() < images) {
        ready->text = "the render process sent " + std::to_string(fds_.size()) + " frame buffers, expected " + std::to_string(images);
        return false;
    }
    const int fd = fds_.front();
    fds_.erase(fds_.begin());
    int fd2 = -1;   // the second Vulkan image (images is 2 only on vkmem)
    if (images == 2) {
        fd2 = fds_.front();
        fds_.erase(fds_.begin());
    }
    shown_ = 0;
    if (transport_ == FrameTransport::VkMemory && importer_) {
        importing_ = importer_->Import(fd, fd2, (int)images, memorySize, width_, height_);
        *pending = true;
        return true;
    }
    if (transport_ == FrameTransport::VkMemory) {
        std::string why;
        DropReadFramebuffers();
        textures_[0] = ImportSharedTexture(fd, memorySize, width_, height_, &memories_[0], &why);
        if (fd2 >= 0 && textures_[0]) textures_[1] = ImportSharedTexture(fd2, memorySize, width_, height_, &memories_[1], &why);
        else if (fd2 >= 0) ::close(fd2);
        texture_ = textures_[0];
        images_ = textures_[1] ? 2 : 1;
        if (!textures_[0] || (images == 2 && !textures_[1])) {
            ready->text = "the render process's image could not be imported here: " + why;
            texture_ = 0;
        }
        return texture_ != 0;
    }
    glGenTextures(1, &texture_);
    DropReadFramebuffers();
    textures_[0] = texture_;
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

bool RenderProcess::SetLiterals(const std::vector<float>& values) {
    std::string p;
    Put<uint32_t>(&p, (uint32_t)values.size());
    for (float v : values) Put(&p, v);
    return Send(Message(3, p));
}

bool RenderProcess::SetAudio(const std::vector<float>& wave, const std::vector<float>& spectrum) {
    std::string p;
    for (const std::vector<float>* v : {&wave, &spectrum}) {
        const size_t n = std::min<size_t>(v->size(), kMaxAudioValues);
        Put<uint32_t>(&p, (uint32_t)n);
        p.append(reinterpret_cast<const char*>(v->data()), n * sizeof(float));
    }
    return Send(Message(6, p));
}

}  // namespace sdfvj
