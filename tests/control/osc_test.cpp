// OSC end to end: a real liblo server thread on a free UDP port; messages from liblo, from the
// `oscsend` tool, and malformed packets over a raw UDP socket.
#include <arpa/inet.h>
#include <lo/lo.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cstring>

#include "test_util.h"

using namespace sdfvj;
using namespace sdfvj::test;

namespace {

struct OscRig {
    EventQueue queue;
    std::unique_ptr<InputSession> session;
    Mapping mapping;
    MappingState ms;
    ParamState params = MakeParamState(MidiSceneDecls());
    MappingActions acts;
    explicit OscRig(const std::string& feedback = "") {
        InputOptions o;
        o.midi = false;
        o.oscPort = 0;
        o.oscFeedback = feedback;
        session = std::make_unique<InputSession>(o, queue, &Now);
        REQUIRE(session->OscPort() > 0);
    }
    // Waits until `n` events have been accepted in total, then applies them as a frame would.
    bool Frame(size_t n) {
        bool ok = WaitFor([&] { return queue.Pushed() >= n; }, 3.0);
        for (const ControlEvent& e : queue.DrainUntil(Now())) ApplyEvent(mapping, ms, e, params, &acts);
        StepSmoothing(params, 1.0 / 60.0);
        return ok;
    }
    std::string Port() const { return std::to_string(session->OscPort()); }
};

void SendRaw(int port, const void* data, size_t size) {
    int fd = socket(AF_INET, SOCK_DGRAM, 0);
    REQUIRE(fd >= 0);
    sockaddr_in to{};
    to.sin_family = AF_INET;
    to.sin_port = htons(uint16_t(port));
    to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    sendto(fd, data, size, 0, reinterpret_cast<sockaddr*>(&to), sizeof to);
    close(fd);
}

void SendRaw(int port, const std::string& s) { SendRaw(port, s.data(), s.size()); }

}  // namespace

TEST_CASE("osc end to end: liblo and oscsend drive parameters, presets and effects") {
    OscRig r;
    lo_address a = lo_address_new("127.0.0.1", r.Port().c_str());
    lo_send(a, "/sdfvj/param/twist", "f", 0.75f);
    lo_send(a, "/sdfvj/raw/scale", "f", 1.25f);
    lo_send(a, "/sdfvj/preset", "s", "intro");
    lo_send(a, "/sdfvj/preset", "i", 4);
    lo_send(a, "/sdfvj/effect/shadows", "i", 1);
    lo_send(a, "/sdfvj/param/smoothness", "i", 1);  // ints are accepted as numbers
    REQUIRE(r.Frame(6));
    CHECK(Param(r.params, "twist") == Approx(1.5f));
    CHECK(Param(r.params, "scale") == Approx(1.25f));
    CHECK(Param(r.params, "smoothness") == Approx(0.5f));
    CHECK(r.acts.presetSelect == std::vector<std::string>{"intro", "4"});
    REQUIRE(r.acts.effectToggles.size() == 1);
    CHECK(r.acts.effectToggles[0] == std::pair<std::string, bool>{"shadows", true});
    lo_address_free(a);

    std::string cmd = "oscsend 127.0.0.1 " + r.Port() + " /sdfvj/param/displacement f 0.5";
    REQUIRE(std::system(cmd.c_str()) == 0);
    REQUIRE(r.Frame(7));
    CHECK(Param(r.params, "displacement") == Approx(0.5f));
    CHECK(r.session->Counters().oscMalformed == 0);
}

TEST_CASE("osc mapped addresses and out-of-range values") {
    OscRig r;
    REQUIRE(ParseMapping("[[map]]\nosc = \"/fader/1\"\ntarget = \"scale\"\ncurve = \"s\"\n", "t.toml", &r.mapping).ok);
    lo_address a = lo_address_new("127.0.0.1", r.Port().c_str());
    lo_send(a, "/fader/1", "f", 1.0f);
    lo_send(a, "/sdfvj/param/twist", "f", 4.0f);      // 4 x range: clamped, reported
    lo_send(a, "/sdfvj/raw/displacement", "f", -7.0f);
    lo_send(a, "/sdfvj/param/nosuch", "f", 0.5f);     // unknown: rejected, lists the names
    REQUIRE(r.Frame(4));
    CHECK(Param(r.params, "scale") == Approx(2.0f));
    CHECK(Param(r.params, "twist") == 3.0f);
    CHECK(Param(r.params, "displacement") == 0.0f);
    CHECK(r.params.clamped == 2);
    CHECK(r.ms.rejected == 1);
    CHECK(r.ms.lastRejected.find("expected one of: scale, twist") != std::string::npos);
    lo_address_free(a);
}

TEST_CASE("osc malformed packets over raw UDP are counted and never stop the server") {
    OscRig r;
    int port = r.session->OscPort();
    // Truncated: address without padding, type tag cut short, float missing its bytes.
    SendRaw(port, std::string("/sdfvj/param/tw", 15));
    SendRaw(port, std::string("/sdfvj/param/twist\0\0,f\0\0\x3f\x80", 26));
    // Bad type tags: no leading comma, unknown tag, tag string not terminated.
    SendRaw(port, std::string("/sdfvj/param/twist\0\0xf\0\0\0\0\0\0", 28));
    SendRaw(port, std::string("/a\0\0,fq\0\0\0\0\0", 12));
    SendRaw(port, std::string("/a\0\0,ffffffffffff", 17));
    // Garbage and an empty packet.
    SendRaw(port, std::string("\xff\xfe\x00\x01garbage!", 12));
    SendRaw(port, "", 0);
    std::string bundle("#bundle\0\0\0\0\0\0\0\0\x01\x7f\xff\xff\xf0", 20);
    SendRaw(port, bundle);
    const uint64_t malformedSent = 8;  // the empty packet may not even be delivered as one
    // Wrong types in well-formed messages.
    lo_address a = lo_address_new("127.0.0.1", r.Port().c_str());
    lo_send(a, "/sdfvj/param/twist", "s", "loud");
    lo_send(a, "/sdfvj/preset", "f", 1.0f);
    lo_send(a, "/sdfvj/effect/fog", "");
    lo_send(a, "/sdfvj/bogus", "f", 1.0f);
    // A huge string (60,000 bytes): valid OSC, but longer than sdfvj accepts.
    std::string huge(60000, 'x');
    lo_send(a, "/sdfvj/preset", "s", huge.c_str());
    // A huge string without its terminator, as raw bytes.
    std::string hugeRaw = std::string("/sdfvj/preset\0\0\0,s\0\0", 20) + std::string(60000, 'y');
    SendRaw(port, hugeRaw);
    // After all that, a valid message still works.
    lo_send(a, "/sdfvj/param/twist", "f", 1.0f);
    REQUIRE(r.Frame(1));
    CHECK(Param(r.params, "twist") == Approx(3.0f));
    const InputCounters& c = r.session->Counters();
    REQUIRE(WaitFor([&] { return c.oscMalformed >= malformedSent && c.oscWrongType >= 5; }, 2.0));
    CHECK(c.oscWrongType == 5);
    CHECK(c.oscMessages == 1);
    lo_address_free(a);
}

namespace {
struct FeedbackSink {
    std::mutex m;
    std::vector<std::pair<std::string, float>> got;
    std::string preset;
};
int OnFeedback(const char* path, const char* types, lo_arg** argv, int, lo_message, void* user) {
    auto* s = static_cast<FeedbackSink*>(user);
    std::lock_guard<std::mutex> g(s->m);
    if (types[0] == 'f') s->got.emplace_back(path, argv[0]->f);
    if (types[0] == 's') s->preset = &argv[0]->s;
    return 0;
}
}  // namespace

TEST_CASE("osc feedback: current values go back to HOST:PORT on preset change") {
    FeedbackSink sink;
    lo_server_thread st = lo_server_thread_new_with_proto(nullptr, LO_UDP, nullptr);
    REQUIRE(st);
    lo_server_thread_add_method(st, nullptr, nullptr, OnFeedback, &sink);
    lo_server_thread_start(st);
    OscRig r("127.0.0.1:" + std::to_string(lo_server_thread_get_port(st)));
    SetParamByName(r.params, "twist", 1.5f, nullptr);
    r.session->SendFeedback(r.params, "intro");
    REQUIRE(WaitFor([&] { std::lock_guard<std::mutex> g(sink.m); return sink.got.size() == 5 && !sink.preset.empty(); }, 2.0));
    {
        std::lock_guard<std::mutex> g(sink.m);
        CHECK(sink.got[1].first == "/sdfvj/param/twist");
        CHECK(sink.got[1].second == Approx(0.75f));
        CHECK(sink.preset == "intro");
    }
    lo_server_thread_free(st);
}

TEST_CASE("osc port in use is a status line, not an error") {
    EventQueue q;
    InputOptions o;
    o.midi = false;
    o.oscPort = 0;
    InputSession first(o, q, &Now);
    o.oscPort = first.OscPort();
    o.log = false;
    InputSession second(o, q, &Now);
    CHECK(second.OscPort() == -1);
    bool mentioned = false;
    for (const std::string& s : second.StatusLines()) mentioned = mentioned || s.find("cannot listen") != std::string::npos;
    CHECK(mentioned);
}
