// The show's side of each frame with a render process (render_process.h): ask for a frame, collect
// it (or find it late), fence the show's reads of the image it arrived in, and the offscreen timing.
#include <epoxy/gl.h>

#include <algorithm>

#include "render/render_process.h"
#include "render/render_wire.h"

namespace sdfvj {

using namespace render_wire;

void RenderProcess::Read() {
    if (!texture_) return;
    if (reads_[shown_]) glDeleteSync((GLsync)reads_[shown_]);
    reads_[shown_] = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
}

bool RenderProcess::Request(const FrameInputs& in) {
    if (outstanding_ || !texture_) return false;
    // The server writes the next frame into this image: what read it must be done on the GPU.
    const int next = (shown_ + 1) % images_;
    if (reads_[next]) {
        glClientWaitSync((GLsync)reads_[next], GL_SYNC_FLUSH_COMMANDS_BIT, 1000000000);
        glDeleteSync((GLsync)reads_[next]);
        reads_[next] = nullptr;
    }
    return SendRequest(in);
}

bool RenderProcess::RequestWhileImporting(const FrameInputs& in) {
    return !outstanding_ && importing_ && SendRequest(in);
}

bool RenderProcess::SendRequest(const FrameInputs& in) {
    if (!Send(Message(2, EncodeInputs(in)))) return false;
    outstanding_ = true;
    requestedAt_ = Clock::now();
    return true;
}

double RenderProcess::OutstandingMs() const { return outstanding_ ? MsSince(requestedAt_) : 0.0; }

double RenderProcess::TimeDraw(const FrameInputs& in, int timeoutMs) {
    if (outstanding_ || !texture_ || !Send(Message(5, EncodeInputs(in)))) return -1;
    uint32_t type = 0;
    std::string payload;
    size_t at = 0;
    double ms = -1;
    if (!Answer(&type, &payload, timeoutMs)) {
        MarkDead();   // not waited for again, as a frame that does not come
        return -1;
    }
    if (type != 5 || !Take(payload, &at, &ms)) {
        MarkDead();
        return -1;
    }
    return ms;
}

bool RenderProcess::Arrived() {
    if (!outstanding_) return false;
    Receive(0);
    size_t at = 0;
    uint32_t type = 0, n = 0;
    return Take(inbox_, &at, &type) && Take(inbox_, &at, &n) && inbox_.size() - at >= n;
}

bool RenderProcess::Collect(int timeoutMs, int deadMs) {
    if (!outstanding_) return false;
    const auto t0 = Clock::now();
    uint32_t type = 0;
    std::string payload;
    while (!TakeMessage(&type, &payload)) {
        const int left = timeoutMs - (int)MsSince(t0);
        if (left <= 0 || !Receive(left)) {
            if (left > 0 || !Usable()) {   // gone
                outstanding_ = false;
                return false;
            }
            if (MsSince(requestedAt_) < std::max(deadMs, timeoutMs)) return false;   // late: still asked for
            outstanding_ = false;
            MarkDead();   // a server that stops answering is not waited for again
            return false;
        }
    }
    outstanding_ = false;
    size_t at = 0;
    uint32_t image = 0;
    if (type != 2 || !Take(payload, &at, &lastServerMs_) || !Take(payload, &at, &image) ||
        image != (uint32_t)((shown_ + 1) % images_)) {   // a server that answers otherwise is not ours
        MarkDead();
        return false;
    }
    shown_ = (int)image;
    texture_ = textures_[shown_];
    if (transport_ == FrameTransport::Shm) UploadShm();
    return true;
}

bool RenderProcess::ShowFirstFrame() {
    if (!texture_ || outstanding_) return false;
    if (transport_ == FrameTransport::Shm) UploadShm();
    return true;
}

void RenderProcess::UploadShm() {
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    glBindTexture(GL_TEXTURE_2D, texture_);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, shm_);
}

unsigned RenderProcess::ReadFramebuffer() {
    if (!texture_) return 0;
    const int i = textures_[1] == texture_ ? 1 : 0;
    if (readTextures_[i] != texture_) {
        if (!readFbos_[i]) glGenFramebuffers(1, &readFbos_[i]);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, readFbos_[i]);
        glFramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture_, 0);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
        readTextures_[i] = texture_;
    }
    return readFbos_[i];
}

void RenderProcess::DropReadFramebuffers() {
    for (int i = 0; i < 2; ++i) {
        if (readFbos_[i]) glDeleteFramebuffers(1, &readFbos_[i]);
        readFbos_[i] = readTextures_[i] = 0;
    }
}

}  // namespace sdfvj
