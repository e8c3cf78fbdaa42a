// Linked into every Catch2 test program (tests/CMakeLists.txt): a fatal signal prints the
// faulting thread's stack to stderr before the program dies, so a rare crash on CI says where
// it happened (ctest keeps the output; scripts/ci_failures.py prints it last).
//
// Catch2 installs its own handler when a run starts; on a signal it reports the test case,
// puts this handler back and raises the signal again, which lands here. Symbols of the test
// program itself need -rdynamic (ENABLE_EXPORTS); shared libraries show as lib(+offset).
#include <execinfo.h>
#include <signal.h>
#include <unistd.h>

#include <cstring>
#include <initializer_list>

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SDFVJ_CRASH_TRACE_OFF 1   // ASan reports a fatal signal better, and owns the handlers
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define SDFVJ_CRASH_TRACE_OFF 1
#endif

#ifndef SDFVJ_CRASH_TRACE_OFF
namespace {

void Write(const char* s) { (void)!write(STDERR_FILENO, s, std::strlen(s)); }

void OnFatal(int sig) {
    Write("\ncrash_trace: fatal signal ");
    Write(sig == SIGSEGV ? "SIGSEGV" : sig == SIGBUS ? "SIGBUS" : sig == SIGFPE ? "SIGFPE" : sig == SIGILL ? "SIGILL" : "SIGABRT");
    Write("; the stack of the thread it hit:\n");
    void* frames[64];
    const int n = backtrace(frames, 64);
    backtrace_symbols_fd(frames, n, STDERR_FILENO);
    signal(sig, SIG_DFL);
    raise(sig);
}

struct Install {
    Install() {
        void* warm[1];
        (void)backtrace(warm, 1);   // loads libgcc's unwinder now, not inside a handler
        static char altStack[64 * 1024];
        stack_t ss{};
        ss.ss_sp = altStack;
        ss.ss_size = sizeof altStack;
        sigaltstack(&ss, nullptr);
        struct sigaction sa{};
        sa.sa_handler = OnFatal;
        sa.sa_flags = SA_ONSTACK;
        sigemptyset(&sa.sa_mask);
        for (int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) sigaction(sig, &sa, nullptr);
    }
} install;

}  // namespace
#endif
