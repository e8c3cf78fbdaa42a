// Crash safety: a recorder that dies without Close() (exit without cleanup, SIGKILL) leaves a
// file that reads back with every event except at most the last second.
#include <signal.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <catch2/catch.hpp>

#include "take_test_util.h"

using namespace sdfvj;
using namespace take_test;

static double Now() {
    timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return double(ts.tv_sec) + double(ts.tv_nsec) * 1e-9;
}

// Child: records one CC event every 2 ms carrying its index (14 bits in the two data bytes),
// time = seconds since `origin`, until `stopAt` (then _exit without Close) or forever.
[[noreturn]] static void RecordInChild(const std::string& path, double origin, double stopAt) {
    TakeRecorder* rec = new TakeRecorder();  // never destroyed: no Close()
    TakeRecorderDesc desc;
    desc.timeOrigin = origin;
    std::string error;
    if (!rec->Open(path, desc, &error)) _exit(3);
    for (int i = 0;; ++i) {
        const double t = Now();
        if (t - origin >= stopAt) _exit(0);
        rec->Record(Midi(t, {0xB0, i & 0x7F, (i >> 7) & 0x7F}));
        usleep(2000);
    }
}

// Reads the file and checks: a clean prefix of the recorded sequence, reaching within a
// second of `stoppedAt`.
static void CheckSurvivors(const std::string& path, double stoppedAt) {
    Take take;
    const TakeReadResult r = ReadTake(path, &take);
    INFO(r.error);
    REQUIRE(r.ok);
    for (const std::string& w : take.warnings) {
        INFO(w);
        CHECK(w.find(": byte ") != std::string::npos);
    }
    REQUIRE_FALSE(take.events.empty());
    double last = -1.0;
    for (size_t k = 0; k < take.events.size(); ++k) {
        const ControlEvent& e = take.events[k];
        REQUIRE(e.midiSize == 3);
        REQUIRE(e.midi[0] == 0xB0);
        REQUIRE(size_t(e.midi[1] | e.midi[2] << 7) == (k & 0x3FFF));  // no gaps, no garbage
        REQUIRE(e.time >= last);
        last = e.time;
    }
    INFO("last event kept at " << last << " s, recording stopped at " << stoppedAt << " s");
    CHECK(last >= stoppedAt - 1.0);
}

TEST_CASE("take: a recorder that exits without Close keeps all but the last second", "[take][slow]") {
    TempFile file("exit");
    const double origin = Now();
    const pid_t pid = fork();
    REQUIRE(pid >= 0);
    if (pid == 0) RecordInChild(file.path, origin, 2.2);
    int status = 0;
    REQUIRE(waitpid(pid, &status, 0) == pid);
    REQUIRE(WIFEXITED(status));
    REQUIRE(WEXITSTATUS(status) == 0);
    CheckSurvivors(file.path, 2.2);
}

TEST_CASE("take: a SIGKILLed recorder keeps all but the last second", "[take][slow]") {
    for (double killAt : {1.3, 2.05}) {  // two different points in the flush cycle
        TempFile file("kill");
        const double origin = Now();
        const pid_t pid = fork();
        REQUIRE(pid >= 0);
        if (pid == 0) RecordInChild(file.path, origin, 1e9);
        while (Now() - origin < killAt) usleep(1000);
        kill(pid, SIGKILL);
        const double stoppedAt = Now() - origin;
        int status = 0;
        REQUIRE(waitpid(pid, &status, 0) == pid);
        REQUIRE(WIFSIGNALED(status));
        CheckSurvivors(file.path, stoppedAt);
    }
}

TEST_CASE("take: a recorder file is readable between flushes", "[take]") {
    TempFile file("live");
    TakeRecorder rec;
    TakeRecorderDesc desc;
    desc.flushInterval = 60.0;  // only explicit flushes in this test
    std::string error;
    REQUIRE(rec.Open(file.path, desc, &error));
    Take take;
    REQUIRE(ReadTake(file.path, &take).ok);  // an empty take right after Open
    CHECK(take.events.empty());
    CHECK(take.warnings.empty());
    rec.Record(Midi(0.1, {0x90, 60, 1}));
    rec.Record(Osc(0.2, "/x", {Arg('f', 1.0f)}));
    REQUIRE(ReadTake(file.path, &take).ok);
    CHECK(take.events.empty());  // not flushed yet
    rec.Flush();
    REQUIRE(ReadTake(file.path, &take).ok);
    CHECK(take.warnings.empty());
    CHECK(take.events.size() == 2);
    rec.Record(Midi(0.3, {0x80, 60, 0}));
    rec.Flush();
    REQUIRE(ReadTake(file.path, &take).ok);
    CHECK(take.warnings.empty());
    CHECK(take.events.size() == 3);
    rec.Close(5.0);
    REQUIRE(ReadTake(file.path, &take).ok);
    CHECK(take.events.size() == 3);
    CHECK(take.duration == 5.0);
}

static std::vector<uint8_t> Slurp(const std::string& path) {
    std::vector<uint8_t> bytes;
    if (std::FILE* f = std::fopen(path.c_str(), "rb")) {
        int c;
        while ((c = std::fgetc(f)) != EOF) bytes.push_back(uint8_t(c));
        std::fclose(f);
    }
    return bytes;
}

TEST_CASE("take: a recorder killed between writing events and their length reads back", "[take]") {
    // The state a crash leaves between steps 1 and 3 of a write (docs/takes.md): the new events
    // and End-of-Track are on disk, the MTrk length is still the old one.
    for (int kind = 0; kind < 4; ++kind) {
        TempFile file("midwrite");
        TakeRecorder rec;
        TakeRecorderDesc desc;
        desc.flushInterval = 60.0;
        std::string error;
        REQUIRE(rec.Open(file.path, desc, &error));
        rec.Record(Midi(0.1, {0x90, 60, 1}));
        rec.Record(Midi(0.2, {0x80, 60, 0}));
        rec.Flush();
        const std::vector<uint8_t> before = Slurp(file.path);
        // Second write: events whose first bytes do and do not fit where End-of-Track was.
        if (kind == 0) rec.Record(Midi(0.3, {0xB0, 7, 64}));                     // 00 B0 07 40 + ...
        if (kind == 1) rec.Record(Midi(9000.0, {0xB0, 7, 64}));                  // 4-byte delta
        if (kind == 2) rec.Record(Osc(0.3, "/a/long/osc/address/for/the/meta/length", {Arg('f', 1)}));
        if (kind == 3) rec.Record(Midi(0.3, {0xF8}));                            // F7 escape
        rec.Record(Midi(9001.0, {0xB0, 8, 1}));
        rec.Flush();
        std::vector<uint8_t> mid = Slurp(file.path);
        REQUIRE(mid.size() > before.size());
        std::copy(before.begin() + 18, before.begin() + 22, mid.begin() + 18);  // old length
        Take take;
        const TakeReadResult r = ParseTake(mid.data(), mid.size(), "take.mid", &take);
        INFO("kind " << kind << ": " << r.error);
        REQUIRE(r.ok);
        REQUIRE(take.events.size() >= 2);
        REQUIRE(take.events.size() <= 3);
        CHECK(SameMidi(take.events[0], {0x90, 60, 1}));
        CHECK(SameMidi(take.events[1], {0x80, 60, 0}));
        if (take.events.size() == 3) CHECK(take.events[2].time >= 0.3 - 1e-9);  // a whole, real event
        CHECK_FALSE(take.warnings.empty());
        rec.Close();
    }
}
