// CompileProcess: shader programs compiled and linked in a child process, `sdfvj compile-server`,
// and handed back as program binaries, so a save never stalls a frame on NVIDIA. Measured there
// (issue 12): the driver serializes compiles process-wide, so a worker thread stalls the render
// thread for the whole compile (0.9 s midi, 2.6-3.6 s character) whatever its context, and the
// driver's parallel compile blocks 210-260 ms inside glCompileShader/glLinkProgram. Another process
// holds no lock of ours; loading its binary (glProgramBinary) takes 5-14 ms.
//
//   CompileProcess proc;
//   if (proc.Start(&error)) pending.SetProcess(&proc);   // /proc/self/exe compile-server
//   ... PendingProgram::Begin() queues there, Ready() polls the pipe, Finish() loads the binary.
//
// The server is the show's helper, never its dependency: when it cannot start, dies, or the
// driver refuses its binary, PendingProgram compiles in-process instead and says nothing.
// Drivers without program binaries (GL_NUM_PROGRAM_BINARY_FORMATS 0: Mesa with its disk cache off)
// cannot use it: Usable() is false there.
//
// Wire format (a stream socket as the server's stdin and stdout, native byte order):
//   job:   u64 ticket, u32 path (RenderPath), u32 store (cache the binary), u32 length, program text
//   reply: u64 ticket, u32 status (0 linked, 1 failed, 2 linked but no binary), u32 format,
//          u64 length, binary, u32 length, raw driver log, f64 compile ms
// Render thread only, except RunCompileServer (the child's main).
#pragma once
#include <sys/types.h>

#include <cstdint>
#include <deque>
#include <map>
#include <utility>
#include <string>
#include <vector>

#include "shader/shader.h"

namespace sdfvj {

class CompileProcess {
public:
    // What a finished ticket gives back.
    struct Result {
        bool died = false;               // the server went away before answering: compile in-process
        bool linked = false;             // binary/format hold the program
        bool noBinary = false;           // linked, but the driver gave no binary: compile in-process
        unsigned format = 0;
        std::vector<uint8_t> binary;
        std::string log;                 // the driver's raw messages on failure
        double buildMs = 0.0;            // compile + link (+ priming dispatch) in the server
    };
    CompileProcess() = default;
    ~CompileProcess();                   // closes the socket: the server exits; reaped here
    CompileProcess(const CompileProcess&) = delete;
    CompileProcess& operator=(const CompileProcess&) = delete;
    // Spawns `exe args...` (default: this executable with `compile-server`). False with one line
    // when it cannot; needs the render context current (checks GL_NUM_PROGRAM_BINARY_FORMATS).
    bool Start(std::string* error, const std::string& exe = "/proc/self/exe",
               const std::vector<std::string>& args = {"compile-server"});
    // Started, not known dead.
    bool Usable() const { return fd_ >= 0 && !dead_; }
    pid_t Pid() const { return pid_; }
    // Queues a compile; 0 when the server is not usable. Never blocks (what the socket does not
    // take now is written by later calls).
    uint64_t Submit(const std::string& text, RenderPath path, bool store);
    // True once the ticket is done (or the server died), filling `result`. Never blocks.
    bool Poll(uint64_t ticket, Result* result);
    // The caller no longer wants this ticket; its reply is dropped when it comes.
    void Forget(uint64_t ticket);
    // Source hand-over (an experiment for issue 12, `bench reload --modes process-source`): a
    // reply only says the program is built; the show compiles the same text itself, for the
    // driver's disk cache (shared with the server) to serve, instead of loading the binary.
    void SetHandOverSource(bool on) { handOverSource_ = on; }
    bool HandOverSource() const { return handOverSource_; }

private:
    void Pump();                         // write what is queued, read what arrived, parse replies
    void MarkDead();
    int fd_ = -1;
    pid_t pid_ = -1;
    bool dead_ = false;
    bool handOverSource_ = false;
    uint64_t next_ = 1;
    std::string outbox_, inbox_;
    // One job at a time goes to the server; the rest wait here, so a job forgotten before it was
    // sent (the performer saved again) costs no compile. Replies come back in order.
    std::deque<std::pair<uint64_t, std::string>> queued_;
    uint64_t inFlight_ = 0;
    std::map<uint64_t, Result> done_;
    std::map<uint64_t, bool> forgotten_;
};

// A process-wide server started on first use (LiveProgram's default on NVIDIA); null when it
// could not start (tried once).
CompileProcess* SharedCompileProcess();

// The server's loop: its own headless context, jobs from `in`, replies to `out`, until `in`
// closes. Returns the exit code. `sdfvj compile-server` calls this with stdin and stdout.
int RunCompileServer(int in, int out);

}  // namespace sdfvj
