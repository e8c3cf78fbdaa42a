// The render process's wire (render_process.h has the format): framing, the values it carries,
// and socket reads and writes with a file descriptor riding along. Internal to render_process.cpp
// (the show's side) and render_server.cpp (the server's); compile_process.cpp shares its helpers.
#pragma once
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>

#include "render/render.h"

namespace sdfvj::render_wire {

using Clock = std::chrono::steady_clock;
inline double MsSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

constexpr uint64_t kModInvalid = 0x00ffffffffffffffULL;   // DRM_FORMAT_MOD_INVALID
constexpr uint32_t kMaxPayload = 1u << 20;                 // a frame's inputs or a scene path: far less
constexpr uint32_t kMaxAudioValues = 16384;                // each of the post chain's audio rows (wire type 6)
constexpr uint32_t kMaxPostFiles = 16;                     // a load's post chain
static_assert(std::is_trivially_copyable_v<Quality>, "Quality crosses the socket as bytes");
static_assert(std::is_trivially_copyable_v<EffectSet>, "EffectSet crosses the socket as bytes (both ends are one binary)");

template <typename T>
inline void Put(std::string* out, T v) {
    out->append(reinterpret_cast<const char*>(&v), sizeof v);
}
inline void PutText(std::string* out, const std::string& s) {
    Put<uint32_t>(out, (uint32_t)s.size());
    out->append(s);
}
template <typename T>
inline bool Take(const std::string& in, size_t* at, T* v) {
    if (in.size() < *at + sizeof(T)) return false;
    std::memcpy(v, in.data() + *at, sizeof(T));
    *at += sizeof(T);
    return true;
}
inline bool TakeText(const std::string& in, size_t* at, std::string* s) {
    uint32_t n = 0;
    if (!Take(in, at, &n) || in.size() - *at < n) return false;
    s->assign(in, *at, n);
    *at += n;
    return true;
}
inline std::string Message(uint32_t type, const std::string& payload) {
    std::string m;
    Put<uint32_t>(&m, type);
    Put<uint32_t>(&m, (uint32_t)payload.size());
    return m + payload;
}

// Sends all of `bytes`, with `fd` and then `fd2` (each when >= 0) riding on the first byte.
inline bool SendAll(int sock, const std::string& bytes, int fd = -1, int fd2 = -1) {
    size_t at = 0;
    int fds[2];
    int nfds = 0;
    for (int f : {fd, fd2})
        if (f >= 0) fds[nfds++] = f;
    while (at < bytes.size()) {
        msghdr msg{};
        iovec iov{const_cast<char*>(bytes.data() + at), bytes.size() - at};
        msg.msg_iov = &iov;
        msg.msg_iovlen = 1;
        alignas(cmsghdr) char control[CMSG_SPACE(sizeof fds)] = {};
        if (nfds > 0 && at == 0) {
            msg.msg_control = control;
            msg.msg_controllen = CMSG_SPACE(sizeof(int) * (size_t)nfds);
            cmsghdr* c = CMSG_FIRSTHDR(&msg);
            c->cmsg_level = SOL_SOCKET;
            c->cmsg_type = SCM_RIGHTS;
            c->cmsg_len = CMSG_LEN(sizeof(int) * (size_t)nfds);
            std::memcpy(CMSG_DATA(c), fds, sizeof(int) * (size_t)nfds);
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

inline bool ReadAll(int fd, void* buf, size_t n) {
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

inline std::string EncodeInputs(const FrameInputs& in) {
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

inline bool DecodeInputs(const std::string& p, FrameInputs* in) {
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


}  // namespace sdfvj::render_wire
