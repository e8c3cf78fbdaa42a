// Deterministic replay with audio-driven parameters: the features a show used are recorded in its
// take (one /sdfvj/audio event per frame, through the real TakeRecorder), read back bit for bit,
// and `sdfvj render --replay` renders the same bytes twice from them, frames the audio changed.
#include <catch2/catch.hpp>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>

#include "../replay/proc_util.h"
#include "audio/audio.h"
#include "signals.h"
#include "take/take.h"

using namespace sdfvj;
using namespace sdfvj::test;
namespace fs = std::filesystem;

namespace {

// What `live` does per frame at 30 fps: analyse the frame's audio, record the feature event.
// The audio: a 128 BPM click train over a bass sine that swells from nothing over 2 s.
std::vector<ControlEvent> RecordShow(const std::string& takePath, int frames) {
    std::vector<float> audio = ClickTrain(128.0, frames / 30.0 + 0.1);
    std::vector<float> bass = Sine(93.75f, 1.0f, frames / 30.0 + 0.1);
    for (size_t i = 0; i < audio.size(); ++i) audio[i] += bass[i] * std::min(1.0f, float(i) / 96000.0f) * 0.5f;
    AudioAnalyzer an;
    TakeRecorder rec;
    std::string error;
    REQUIRE(rec.Open(takePath, &error));
    std::vector<ControlEvent> used;
    for (int f = 0; f < frames; ++f) {
        an.Process(audio.data() + size_t(f) * 1600, 1600);
        used.push_back(AudioFeatureEvent(an.TakeFeatures(), (f + 1) / 30.0));
        rec.Record(used.back());
    }
    rec.Close(frames / 30.0 + 0.05);
    return used;
}

std::string Bytes(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), {});
}

}  // namespace

TEST_CASE("audio replay: the take stores the features the show used, bit for bit", "[audio]") {
    const std::string dir = FreshDir(SDFVJ_AUDIO_OUT, "take");
    const std::string take = dir + "/audio_take.mid";
    std::vector<ControlEvent> used = RecordShow(take, 60);
    Take t;
    TakeReadResult r = ReadTake(take, &t);
    INFO(r.error);
    REQUIRE(r.ok);
    CHECK(t.warnings.empty());
    REQUIRE(t.events.size() == used.size());
    int onsets = 0;
    for (size_t i = 0; i < used.size(); ++i) {
        AudioFeatures a, b;
        REQUIRE(ReadAudioFeatureEvent(used[i], &a));
        REQUIRE(ReadAudioFeatureEvent(t.events[i], &b));
        CHECK(t.events[i].time == QuantizeTakeTime(used[i].time));
        for (size_t k = 0; k < used[i].args.size(); ++k) REQUIRE(used[i].args[k].f == t.events[i].args[k].f);
        onsets += b.onset;
    }
    CHECK(onsets >= 3);   // 2 s at 128 BPM: 4 clicks
}

TEST_CASE("audio replay: render --replay with audio-driven parameters gives the same bytes twice", "[audio]") {
    const std::string root = SDFVJ_AUDIO_OUT;
    const std::string dir = FreshDir(root, "replay");
    const std::string take = dir + "/audio_take.mid", mapping = dir + "/audio.toml";
    RecordShow(take, 30);
    {
        std::ofstream m(mapping);
        m << "[profile]\nname = \"audio test\"\n"
             "[[map]]\naudio = \"bass\"\ntarget = \"twist\"\n"
             "[[map]]\naudio = \"level\"\ntarget = \"scale\"\nrange = [0.6, 1.6]\nattack = 0.02\nrelease = 0.3\n"
             "[[pad]]\naudio = \"onset\"\ntarget = \"displacement\"\n";
    }
    const std::string a = FreshDir(root, "replay-a"), b = FreshDir(root, "replay-b"), c = FreshDir(root, "replay-none");
    auto args = [&](const std::string& out, bool withTake) {
        std::vector<std::string> v = {SDFVJ_BIN, "render", "--scene", "midi", "--frames", "30", "--size", "96x54",
                                      "--path", "fragment", "--quiet", "--param", "spin=0", "--mapping", mapping,
                                      "--out", out};
        if (withTake) v.insert(v.end(), {"--replay", take});
        return v;
    };
    pid_t pa = Spawn(args(a, true), a + ".log"), pb = Spawn(args(b, true), b + ".log");
    pid_t pc = Spawn(args(c, false), c + ".log");
    const int ra = WaitExit(pa, 90), rb = WaitExit(pb, 90), rc = WaitExit(pc, 90);
    INFO(ReadText(a + ".log") << ReadText(b + ".log") << ReadText(c + ".log"));
    REQUIRE(ra == 0);
    REQUIRE(rb == 0);
    REQUIRE(rc == 0);
    std::set<std::string> distinct;
    int changed = 0;
    for (int i = 0; i < 30; ++i) {
        char name[32];
        std::snprintf(name, sizeof name, "/frame_%05d.png", i);
        const std::string fa = Bytes(a + name), fb = Bytes(b + name), fc = Bytes(c + name);
        INFO("frame " << i);
        REQUIRE(!fa.empty());
        CHECK(fa == fb);   // tolerance: none, byte for byte
        distinct.insert(fa);
        changed += fa != fc;
    }
    // The audio moved the picture: the frames change over the take, and differ from the same
    // scene rendered without it (0 would mean the features never reached the parameters).
    CHECK(distinct.size() >= 10);
    CHECK(changed >= 25);
}
