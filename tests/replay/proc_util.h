// Helpers for tests that drive the real `sdfvj` binary and outside tools as separate processes:
// spawn with a changed environment and output to a file, wait with a time limit, free UDP ports.
#pragma once
#include <arpa/inet.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <fcntl.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace sdfvj::test {

struct EnvChange {
    std::string name;
    std::string value;
    bool unset = false;
};

// Starts argv[0] (PATH lookup) with stdout and stderr appended to `logPath`. Returns the pid.
inline pid_t Spawn(const std::vector<std::string>& argv, const std::string& logPath,
                   const std::vector<EnvChange>& env = {}) {
    pid_t pid = fork();
    if (pid != 0) return pid;
    for (const EnvChange& e : env) {
        if (e.unset) unsetenv(e.name.c_str());
        else setenv(e.name.c_str(), e.value.c_str(), 1);
    }
    int fd = open(logPath.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
    if (fd >= 0) { dup2(fd, 1); dup2(fd, 2); close(fd); }
    int devnull = open("/dev/null", O_RDONLY);
    if (devnull >= 0) { dup2(devnull, 0); close(devnull); }
    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    execvp(args[0], args.data());
    _exit(127);
}

// Waits for `pid`; kills it after `seconds`. Returns the exit code, 128+signal, or -1 on timeout.
inline int WaitExit(pid_t pid, double seconds) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    int status = 0;
    for (;;) {
        pid_t r = waitpid(pid, &status, WNOHANG);
        if (r == pid) break;
        if (r < 0) return -2;
        if (std::chrono::steady_clock::now() > end) {
            kill(pid, SIGKILL);
            waitpid(pid, &status, 0);
            return -1;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    if (WIFEXITED(status)) return WEXITSTATUS(status);
    if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
    return -3;
}

inline int Run(const std::vector<std::string>& argv, const std::string& logPath, double seconds,
               const std::vector<EnvChange>& env = {}) {
    return WaitExit(Spawn(argv, logPath, env), seconds);
}

inline std::string ReadText(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
}

inline bool HaveTool(const std::string& name) {
    return std::system(("command -v " + name + " >/dev/null 2>&1").c_str()) == 0;
}

// A UDP port that was free a moment ago (bind to 0, read it back, close).
inline int FreeUdpPort() {
    int s = socket(AF_INET, SOCK_DGRAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    a.sin_port = 0;
    bind(s, (sockaddr*)&a, sizeof a);
    socklen_t len = sizeof a;
    getsockname(s, (sockaddr*)&a, &len);
    close(s);
    return ntohs(a.sin_port);
}

// A fresh, empty folder under the test output folder.
inline std::string FreshDir(const std::string& root, const std::string& name) {
    std::filesystem::path p = std::filesystem::path(root) / name;
    std::filesystem::remove_all(p);
    std::filesystem::create_directories(p);
    return p.string();
}

}  // namespace sdfvj::test
