// `sdfvj learn` as a separate process, taught over OSC (no MIDI device needed): the mapping file
// changes all or nothing, and learn starts even while another program holds OSC port 9000.
#include <arpa/inet.h>
#include <lo/lo.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <catch2/catch.hpp>

#include <chrono>
#include <thread>
#include <fstream>
#include <regex>

#include "control/control.h"
#include "proc_util.h"

using namespace sdfvj;
using namespace sdfvj::test;
namespace fs = std::filesystem;

namespace {

// The OSC port learn announces on stderr, or -1 when it says none within `seconds`.
int LearnOscPort(const std::string& log, double seconds) {
    const std::regex announced("(?:listening on UDP port|send OSC to port) ([0-9]+)");
    auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    int port = -1;
    while (std::chrono::steady_clock::now() < end) {
        std::string text = ReadText(log);
        // The fallback line, when present, is the one that counts; it comes after the status line.
        for (auto it = std::sregex_iterator(text.begin(), text.end(), announced); it != std::sregex_iterator(); ++it)
            port = std::stoi((*it)[1]);
        if (text.find("learn: move the control") != std::string::npos) return port;
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return port;
}

// Starts learn, waits for its port and moves an OSC control until learn exits. Returns its code.
int LearnOverOsc(const std::string& dir, const std::string& param, const std::string& mapping, int* port) {
    const std::string log = dir + "/learn.log";
    pid_t pid = Spawn({SDFVJ_BIN, "learn", "--param", param, "--mapping", mapping, "--timeout", "20"}, log,
                      {{"JACK_NO_START_SERVER", "1"}});
    *port = LearnOscPort(log, 15);
    if (*port > 0) {
        lo_address to = lo_address_new("127.0.0.1", std::to_string(*port).c_str());
        for (int i = 0; i < 100; ++i) {
            lo_send(to, "/fader1", "f", 0.25f + 0.005f * float(i));
            int status = 0;
            if (waitpid(pid, &status, WNOHANG) == pid) {
                lo_address_free(to);
                return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
        }
        lo_address_free(to);
    }
    return WaitExit(pid, 25);
}

}  // namespace

TEST_CASE("learn: an entry that would make the mapping invalid leaves the file byte-identical", "[learn]") {
    const std::string dir = FreshDir(SDFVJ_LEARN_OUT, "invalid");
    const std::string mapping = dir + "/inline.toml";
    // Valid on its own, but an inline `map` array cannot take another [[map]] table.
    const std::string text = "# knobs as an inline array\nmap = [ { cc = 1, target = \"twist\" } ]";
    { std::ofstream(mapping, std::ios::binary) << text; }
    Mapping m;
    REQUIRE(ParseMapping(text, mapping, &m).ok);
    int port = -1;
    int rc = LearnOverOsc(dir, "scale", mapping, &port);
    const std::string log = ReadText(dir + "/learn.log");
    INFO(log);
    REQUIRE(port > 0);
    CHECK(rc == 2);
    CHECK(ReadText(mapping) == text);
    CHECK(log.find(mapping + ":") != std::string::npos);   // file:line: what is wrong
    CHECK(log.find("unchanged") != std::string::npos);
    int leftovers = 0;
    for (const auto& e : fs::directory_iterator(dir)) leftovers += e.path().filename().string().find(".learn-") != std::string::npos;
    CHECK(leftovers == 0);
}

TEST_CASE("learn: with the OSC port held by another program, learn takes a free port and learns", "[learn]") {
    const std::string dir = FreshDir(SDFVJ_LEARN_OUT, "port-taken");
    // Hold 9000 as a running `sdfvj live` would. Another test of the suite (ctest -j) may hold it
    // for a moment and let it go just before learn binds: wait until it is ours (CI saw that).
    int holder = socket(AF_INET, SOCK_DGRAM, 0);
    REQUIRE(holder >= 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_ANY);
    a.sin_port = htons(9000);
    bool held = false;
    for (int i = 0; i < 600 && !held; ++i) {
        held = bind(holder, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
        if (!held) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    INFO("bound 9000 ourselves: " << held);
    REQUIRE(held);
    const std::string mapping = dir + "/learned.toml";
    const std::string before = "[profile]\nname = \"mine\"\n\n[[map]]\ncc = 1\ntarget = \"twist\"";   // no final newline
    { std::ofstream(mapping, std::ios::binary) << before; }
    int port = -1;
    int rc = LearnOverOsc(dir, "scale", mapping, &port);
    close(holder);
    const std::string log = ReadText(dir + "/learn.log");
    INFO(log);
    REQUIRE(port > 0);
    CHECK(port != 9000);
    CHECK(log.find("port 9000 is taken") != std::string::npos);
    CHECK(rc == 0);
    const std::string after = ReadText(mapping);
    CHECK(after.rfind(before, 0) == 0);                        // the old text, untouched, first
    Mapping m;
    LoadResult r = ParseMapping(after, mapping, &m);
    INFO(r.error);
    REQUIRE(r.ok);
    REQUIRE(m.entries.size() == 2);
    CHECK(m.entries[1].kind == SourceKind::Osc);
    CHECK(m.entries[1].oscAddress == "/fader1");
    CHECK(m.entries[1].target == "scale");
}

TEST_CASE("learn: a parameter name that is not a scene input name is refused before listening", "[learn]") {
    const std::string dir = FreshDir(SDFVJ_LEARN_OUT, "bad-name");
    const std::string mapping = dir + "/learned.toml";
    int rc = Run({SDFVJ_BIN, "learn", "--param", "tw\"ist", "--mapping", mapping, "--timeout", "1"}, dir + "/learn.log", 20);
    const std::string log = ReadText(dir + "/learn.log");
    INFO(log);
    CHECK(rc == 2);
    CHECK(log.find("bad parameter name") != std::string::npos);
    CHECK_FALSE(fs::exists(mapping));
}
