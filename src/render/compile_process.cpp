#include "render/compile_process.h"

#include <epoxy/gl.h>
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <memory>

#include "render/compile_worker.h"
#include "render/program_cache.h"
#include "render/render.h"
#include "render/render_wire.h"

extern char** environ;

namespace sdfvj {

using render_wire::Put;
using render_wire::ReadAll;
using render_wire::Take;

namespace {

bool WriteAll(int fd, const std::string& bytes) {
    size_t at = 0;
    while (at < bytes.size()) {
        const ssize_t put = ::send(fd, bytes.data() + at, bytes.size() - at, MSG_NOSIGNAL);
        if (put < 0 && errno == EINTR) continue;
        if (put < 0 && errno == ENOTSOCK) {   // a plain pipe as stdout (run by hand)
            const ssize_t w = ::write(fd, bytes.data() + at, bytes.size() - at);
            if (w <= 0) return false;
            at += (size_t)w;
            continue;
        }
        if (put <= 0) return false;
        at += (size_t)put;
    }
    return true;
}

}  // namespace

CompileProcess::~CompileProcess() {
    if (fd_ >= 0) ::close(fd_);   // EOF on the server's stdin: it finishes its job and exits
    if (pid_ > 0) {
        // A compile of seconds may be running: don't wait for it, the server has nothing to save.
        ::kill(pid_, SIGTERM);
        int status = 0;
        ::waitpid(pid_, &status, 0);
    }
}

bool CompileProcess::Start(std::string* error, const std::string& exe, const std::vector<std::string>& args) {
    GLint formats = 0;
    glGetIntegerv(GL_NUM_PROGRAM_BINARY_FORMATS, &formats);
    if (formats <= 0) {
        *error = "the driver gives no program binaries (GL_NUM_PROGRAM_BINARY_FORMATS 0), so a compile process "
                 "cannot hand programs over";
        return false;
    }
    int sv[2];
    if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv) != 0) {
        *error = std::string("compile process: socketpair: ") + std::strerror(errno);
        return false;
    }
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, sv[1], 0);   // dup2 clears CLOEXEC on 0 and 1
    posix_spawn_file_actions_adddup2(&actions, sv[1], 1);
    std::vector<char*> argv;
    argv.push_back(const_cast<char*>(exe.c_str()));
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    pid_t pid = -1;
    const int rc = posix_spawn(&pid, exe.c_str(), &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    ::close(sv[1]);
    if (rc != 0) {
        ::close(sv[0]);
        *error = "compile process: cannot start " + exe + ": " + std::strerror(rc);
        return false;
    }
    fd_ = sv[0];
    pid_ = pid;
    ::fcntl(fd_, F_SETFL, ::fcntl(fd_, F_GETFL) | O_NONBLOCK);
    return true;
}

uint64_t CompileProcess::Submit(const std::string& text, RenderPath path, bool store) {
    Pump();
    if (!Usable()) return 0;
    const uint64_t ticket = next_++;
    std::string job;
    Put(&job, ticket);
    Put(&job, (uint32_t)path);
    Put(&job, (uint32_t)(store ? 1 : 0));
    Put(&job, (uint32_t)text.size());
    job += text;
    queued_.emplace_back(ticket, std::move(job));
    Pump();
    return ticket;
}

void CompileProcess::MarkDead() {
    dead_ = true;
    std::vector<uint64_t> lost;
    if (inFlight_ && !forgotten_.erase(inFlight_)) lost.push_back(inFlight_);
    for (const auto& [t, job] : queued_) lost.push_back(t);
    for (uint64_t t : lost) {
        Result r;
        r.died = true;
        done_[t] = r;
    }
    inFlight_ = 0;
    queued_.clear();
    outbox_.clear();
}

void CompileProcess::Pump() {
    if (fd_ < 0 || dead_) return;
    if (!inFlight_ && !queued_.empty()) {
        inFlight_ = queued_.front().first;
        outbox_ = std::move(queued_.front().second);
        queued_.pop_front();
    }
    while (!outbox_.empty()) {
        const ssize_t put = ::send(fd_, outbox_.data(), outbox_.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
        if (put > 0) {
            outbox_.erase(0, (size_t)put);
            continue;
        }
        if (put < 0 && errno == EINTR) continue;
        if (put < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) break;
        MarkDead();   // EPIPE: the server is gone
        return;
    }
    char buf[1 << 16];
    for (;;) {
        const ssize_t got = ::recv(fd_, buf, sizeof buf, MSG_DONTWAIT);
        if (got > 0) {
            inbox_.append(buf, (size_t)got);
            continue;
        }
        if (got < 0 && errno == EINTR) continue;
        if (got < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) break;
        // EOF or error: take the replies that did arrive, then the rest died with the server.
        dead_ = true;
        break;
    }
    // Whole replies only; a partial one waits for the next call.
    for (;;) {
        size_t at = 0;
        uint64_t ticket = 0, binaryLength = 0;
        uint32_t status = 0, format = 0, logLength = 0;
        double ms = 0;
        if (!Take(inbox_, &at, &ticket) || !Take(inbox_, &at, &status) || !Take(inbox_, &at, &format) ||
            !Take(inbox_, &at, &binaryLength) || inbox_.size() < at + binaryLength)
            break;
        const size_t binaryAt = at;
        at += binaryLength;
        if (!Take(inbox_, &at, &logLength) || inbox_.size() < at + logLength + sizeof(double)) break;
        const size_t logAt = at;
        at += logLength;
        Take(inbox_, &at, &ms);
        if (ticket == inFlight_) inFlight_ = 0;
        if (!forgotten_.erase(ticket)) {
            Result r;
            r.linked = status != 1;
            r.noBinary = status == 2;
            r.format = format;
            r.binary.assign(inbox_.begin() + (long)binaryAt, inbox_.begin() + (long)(binaryAt + binaryLength));
            r.log = inbox_.substr(logAt, logLength);
            r.buildMs = ms;
            done_[ticket] = std::move(r);
        }
        inbox_.erase(0, at);
    }
    if (dead_) {
        MarkDead();
        return;
    }
    if (!inFlight_ && !queued_.empty()) Pump();   // the next job, now that the server is free
}

bool CompileProcess::Poll(uint64_t ticket, Result* result) {
    Pump();
    auto it = done_.find(ticket);
    if (it == done_.end()) return false;
    *result = std::move(it->second);
    done_.erase(it);
    return true;
}

void CompileProcess::Forget(uint64_t ticket) {
    if (done_.erase(ticket)) return;
    for (auto it = queued_.begin(); it != queued_.end(); ++it)
        if (it->first == ticket) {
            queued_.erase(it);   // never sent: no compile at all
            return;
        }
    if (ticket == inFlight_) forgotten_[ticket] = true;   // its reply is dropped when it comes
}

CompileProcess* SharedCompileProcess() {
    static std::unique_ptr<CompileProcess> shared;
    static bool tried = false;
    if (!tried) {
        tried = true;
        auto p = std::make_unique<CompileProcess>();
        std::string error;
        if (p->Start(&error)) shared = std::move(p);
        else std::fprintf(stderr, "sdfvj: %s; shaders compile in this process\n", error.c_str());
    }
    return shared.get();
}

int RunCompileServer(int in, int out) {
    // Compiles yield the CPU to the show's frames (the same machine's cores; see CompileWorker).
    setpriority(PRIO_PROCESS, 0, 10);
    // Descriptors the show had open (an OSC port, JACK's sockets, files) are not the server's:
    // posix_spawn passes on every one not marked close-on-exec.
    for (int fd = 3; fd < 1024; ++fd)
        if (fd != in && fd != out) ::close(fd);
    HeadlessContext gl;
    std::string error;
    if (!gl.Create(&error)) {
        std::fprintf(stderr, "sdfvj compile-server: %s\n", error.c_str());
        return 1;
    }
    for (;;) {
        uint64_t ticket = 0;
        uint32_t path = 0, store = 0, length = 0;
        if (!ReadAll(in, &ticket, sizeof ticket) || !ReadAll(in, &path, sizeof path) || !ReadAll(in, &store, sizeof store) ||
            !ReadAll(in, &length, sizeof length))
            return 0;   // the parent closed the socket: done
        std::string text(length, '\0');
        if (length && !ReadAll(in, text.data(), length)) return 0;
        const RenderPath rp = path == (uint32_t)RenderPath::Compute ? RenderPath::Compute : RenderPath::Fragment;
        const auto t0 = std::chrono::steady_clock::now();
        std::string log;
        const unsigned prog = CompileLinkHere(text, rp, &log, true);
        uint32_t status = 1, format = 0;
        std::vector<uint8_t> binary;
        if (prog) {
            PrimeProgram(prog, rp, text.find("rgba32f") != std::string::npos);
            GLint len = 0;
            glGetProgramiv(prog, GL_PROGRAM_BINARY_LENGTH, &len);
            binary.resize(len > 0 ? (size_t)len : 0);
            GLsizei got = 0;
            GLenum fmt = 0;
            if (len > 0) glGetProgramBinary(prog, len, &got, &fmt, binary.data());
            binary.resize(got > 0 ? (size_t)got : 0);
            format = fmt;
            status = binary.empty() ? 2 : 0;
            glDeleteProgram(prog);
        }
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        // Into the disk cache before the reply (a few ms): the program is there by the time the show
        // has it, even when the show quits right after (the server is then terminated mid-job).
        if (store && status == 0) StoreCachedBinary(format, binary, text, rp);
        std::string reply;
        Put(&reply, ticket);
        Put(&reply, status);
        Put(&reply, format);
        Put(&reply, (uint64_t)binary.size());
        reply.append(binary.begin(), binary.end());
        Put(&reply, (uint32_t)log.size());
        reply += log;
        Put(&reply, ms);
        if (!WriteAll(out, reply)) return 0;
    }
}

}  // namespace sdfvj
