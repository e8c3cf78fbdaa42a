// soak_driver: the audience from hell for `sdfvj live`, run by scripts/soak.sh.
//
//   soak_driver --osc-port N --root DIR [--seconds S] [--midi-name NAME] [--osc-rate N]
//               [--save-ms M] [--replug-s S] [--final-preset NAME] [--final-param NAME]
//               [--final-value V] [--seed N] [--only osc|midi|saves]
//
// For --seconds it throws everything at once, from three threads:
//   - OSC over UDP to 127.0.0.1:N: valid /sdfvj/param and /sdfvj/raw floods, wrong types,
//     huge strings, absurd preset requests, unknown addresses, effect toggles, preset
//     switches by name/index/next/prev, and raw garbage datagrams (random bytes, cut-off
//     messages, broken bundles).
//   - MIDI through JACK from a virtual output port NAME (client "soak-driver"): random CC,
//     notes, sysex (some unterminated), running status, stray and system bytes. Every
//     --replug-s seconds the port is removed (client closed, or only the port) and re-created
//     later, as when a controller is unplugged.
//   - Saves under DIR (the soak's copy of shaders/, presets/, mappings/) every --save-ms:
//     alternating valid and broken, editor-style (temp file + rename) or in place, some
//     truncated, some written in two halves.
// Then it restores every file, switches to --final-preset, and sends
// `/sdfvj/raw/<final-param> f <final-value>` a few times: the value the last frames must show.
// Prints `COUNT name value` lines (the soak's event counts) and `FINAL ...` on stdout.
// Every loop is bounded by the deadline; the driver talks to 127.0.0.1 only.
#include <arpa/inet.h>
#include <csignal>
#include <lo/lo.h>
#include <netinet/in.h>

#include "../control/jack_midi_out.h"
using sdfvj::test::MakeMidiOut;
using sdfvj::test::MidiOutPtr;
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

struct Options {
    int oscPort = 0;
    std::string root;
    double seconds = 20;
    std::string midiName = "soak-controller";
    double oscRate = 2000;       // OSC datagrams per second, all kinds together
    int saveMs = 300;
    double replugSeconds = 3;
    std::string finalPreset = "demo";
    std::string finalParam = "twist";
    float finalValue = 1.2345f;
    unsigned seed = 0;
    std::string only;            // "osc", "midi" or "saves": one source alone, to tell which one stalls
};

// Event counts, printed at the end as `COUNT name value`.
struct Counts {
    std::mutex m;
    std::map<std::string, uint64_t> n;
    void Add(const std::string& k, uint64_t v = 1) {
        std::lock_guard<std::mutex> g(m);
        n[k] += v;
    }
};

Counts gCounts;
std::atomic<bool> gStop{false};

double Since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

void SleepMs(double ms) { std::this_thread::sleep_for(std::chrono::microseconds(int64_t(ms * 1000))); }

// ---------------------------------------------------------------------------------------- OSC

const char* kParams[] = {"twist", "scale", "displacement", "smoothness", "spin", "power", "nope", "",
                         "radius", "decay"};   // the last two: the post chain's (soak.sh: bloom, feedback_trails)
const char* kEffects[] = {"ao", "shadows", "soft_shadows", "fog", "specular", "pbr", "reflections", "heatmap", "bogus"};
const char* kPresets[] = {"demo", "twisted", "bulb", "walker", "demo.json", "missing", "next", "prev", "0", "1", "2", "3",
                          "99999999999999999999999", "4294967296", "18446744073709551616", "-1", "", "../../etc/passwd",
                          "007", "1e3", " 1", "next "};

struct OscBlaster {
    lo_address addr = nullptr;
    int udp = -1;
    sockaddr_in dst{};
    std::mt19937 rng;
    explicit OscBlaster(const Options& o) : rng(o.seed * 7919u + 1) {
        std::string port = std::to_string(o.oscPort);
        addr = lo_address_new("127.0.0.1", port.c_str());
        udp = socket(AF_INET, SOCK_DGRAM, 0);
        dst.sin_family = AF_INET;
        dst.sin_port = htons(uint16_t(o.oscPort));
        dst.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    }
    ~OscBlaster() {
        if (addr) lo_address_free(addr);
        if (udp >= 0) close(udp);
    }
    int Uniform(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); }
    float Unit() { return std::uniform_real_distribution<float>(0.0f, 1.0f)(rng); }
    template <size_t N> const char* Pick(const char* (&a)[N]) { return a[Uniform(0, int(N) - 1)]; }

    void Raw(const void* data, size_t n, const char* kind) {
        sendto(udp, data, n, 0, reinterpret_cast<const sockaddr*>(&dst), sizeof dst);
        gCounts.Add(kind);
    }
    std::string Junk(size_t n) {
        std::string s(n, '\0');
        for (char& c : s) c = char(Uniform(0, 255));
        return s;
    }
    // A valid message serialized, then cut short or with its type tags bent.
    void Mangled() {
        lo_message m = lo_message_new();
        lo_message_add_float(m, Unit());
        lo_message_add_string(m, "soak");
        size_t len = 0;
        void* bytes = lo_message_serialise(m, "/sdfvj/param/twist", nullptr, &len);
        lo_message_free(m);
        if (!bytes) return;
        std::string s(static_cast<char*>(bytes), len);
        free(bytes);
        switch (Uniform(0, 3)) {
        case 0: s.resize(size_t(Uniform(0, int(s.size()) - 1))); break;   // truncated
        case 1: s[s.find(',') + 1] = char(Uniform(1, 255)); break;         // type tag bent
        case 2: s[size_t(Uniform(0, int(s.size()) - 1))] ^= char(1 << Uniform(0, 7)); break;
        default: s.replace(s.find(','), 2, ",b"); break;                    // blob over a float
        }
        Raw(s.data(), s.size(), "osc_mangled");
    }
    void Bundle() {
        std::string s = std::string("#bundle\0", 8) + Junk(8);             // header + time tag
        uint32_t size = Uniform(0, 1) ? htonl(0x7fffffff) : htonl(uint32_t(Uniform(0, 64)));
        s.append(reinterpret_cast<const char*>(&size), 4);
        s += Junk(size_t(Uniform(0, 40)));
        Raw(s.data(), s.size(), "osc_bad_bundle");
    }

    // One datagram of a random kind. Preset switches and effect toggles are rarer (they make the
    // show compile); parameter traffic is the flood.
    void One() {
        int r = Uniform(0, 999);
        std::string param = std::string("/sdfvj/param/") + Pick(kParams);
        std::string raw = std::string("/sdfvj/raw/") + Pick(kParams);
        if (r < 450) {
            lo_send(addr, param.c_str(), "f", Unit());
            gCounts.Add("osc_valid_param");
        } else if (r < 600) {
            float v;
            switch (Uniform(0, 5)) {
            case 0: v = std::numeric_limits<float>::quiet_NaN(); break;
            case 1: v = std::numeric_limits<float>::infinity(); break;
            case 2: v = -1e30f; break;
            case 3: v = std::numeric_limits<float>::denorm_min(); break;
            default: v = (Unit() - 0.5f) * 8.0f; break;
            }
            lo_send(addr, raw.c_str(), "f", v);
            gCounts.Add("osc_raw");
        } else if (r < 700) {   // wrong types and argument counts
            switch (Uniform(0, 7)) {
            case 0: lo_send(addr, param.c_str(), "s", "abc"); break;
            case 1: lo_send(addr, param.c_str(), "i", Uniform(-5, 5)); break;
            case 2: lo_send(addr, param.c_str(), ""); break;
            case 3: lo_send(addr, param.c_str(), "ff", Unit(), Unit()); break;
            case 4: lo_send(addr, param.c_str(), "d", 0.5); break;
            case 5: lo_send(addr, param.c_str(), "T"); break;
            case 6: lo_send(addr, "/sdfvj/preset", "f", Unit()); break;
            default: lo_send(addr, "/sdfvj/effect/ao", "s", "on"); break;
            }
            gCounts.Add("osc_wrong_type");
        } else if (r < 760) {   // unknown addresses
            static const char* kUnknown[] = {"/sdfvj", "/sdfvj/", "/sdfvj/param/", "/sdfvj/raw/", "/sdfvj/effect/",
                                             "/sdfvj/effect", "/foo/bar", "/sdfvj/param/twist/extra", "/sdfvj/PRESET", "/"};
            lo_send(addr, Pick(kUnknown), "f", Unit());
            gCounts.Add("osc_unknown_address");
        } else if (r < 775) {   // preset switches, sane and absurd
            if (Uniform(0, 1)) lo_send(addr, "/sdfvj/preset", "s", Pick(kPresets));
            else lo_send(addr, "/sdfvj/preset", "i", Uniform(0, 9) ? Uniform(-3, 6) : (Uniform(0, 1) ? INT32_MAX : INT32_MIN));
            gCounts.Add("osc_preset");
        } else if (r < 795) {   // effect toggles
            std::string e = std::string("/sdfvj/effect/") + (Uniform(0, 2) ? "ao" : Pick(kEffects));
            lo_send(addr, e.c_str(), "i", Uniform(0, 1));
            gCounts.Add("osc_effect_toggle");
        } else if (r < 800) {   // huge strings
            std::string big(size_t(Uniform(1000, 60000)), char('a' + Uniform(0, 25)));
            if (Uniform(0, 1)) lo_send(addr, "/sdfvj/preset", "s", big.c_str());
            else lo_send(addr, ("/sdfvj/param/" + big.substr(0, 30000)).c_str(), "f", 0.5f);
            gCounts.Add("osc_huge_string");
        } else if (r < 940) {
            std::string j = Junk(size_t(Uniform(0, 9) ? Uniform(1, 200) : Uniform(200, 8000)));
            if (!j.empty() && Uniform(0, 1)) j[0] = '/';   // looks like an address to liblo
            Raw(j.data(), j.size(), "osc_garbage");
        } else if (r < 990) {
            Mangled();
        } else {
            Bundle();
        }
    }
};

void RunOsc(const Options& o, Clock::time_point deadline) {
    OscBlaster b(o);
    const auto t0 = Clock::now();
    uint64_t sent = 0;
    while (!gStop && Clock::now() < deadline) {
        const uint64_t due = uint64_t(Since(t0) * o.oscRate);
        for (int k = 0; sent < due && k < 200; ++k, ++sent) b.One();
        SleepMs(1);
    }
}

// --------------------------------------------------------------------------------------- MIDI

struct MidiBlaster {
    const Options& o;
    MidiOutPtr out;
    std::mt19937 rng;
    explicit MidiBlaster(const Options& opt) : o(opt), rng(opt.seed * 104729u + 3) {}
    int Uniform(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); }

    bool Plug(bool newClient) {
        try {
            if (newClient || !out) {
                out.reset();
                out = MakeMidiOut("soak-driver");
            }
            out->openVirtualPort(o.midiName);
            return true;
        } catch (const std::exception& e) {
            std::fprintf(stderr, "soak_driver: cannot open the MIDI port: %s\n", e.what());
            out.reset();
            gCounts.Add("midi_plug_failed");
            return false;
        }
    }
    void Unplug(bool wholeClient) {
        if (!out) return;
        if (wholeClient) out.reset();
        else out->closePort();
    }
    void Send(std::vector<unsigned char> bytes, const char* kind) {
        if (!out || bytes.empty()) return;
        try {
            out->sendMessage(&bytes);
            gCounts.Add(kind);
        } catch (const std::exception&) {
            gCounts.Add("midi_send_failed");
        }
    }
    unsigned char D() { return (unsigned char)Uniform(0, 127); }
    void One() {
        int r = Uniform(0, 999);
        unsigned char ch = (unsigned char)Uniform(0, 15);
        if (r < 550) {
            unsigned char cc = (unsigned char)(Uniform(0, 1) ? Uniform(0, 31) : Uniform(0, 127));
            Send({(unsigned char)(0xB0 | ch), cc, D()}, "midi_cc");
        } else if (r < 600) {   // pads: notes the mappings bind to presets, effects, tap tempo
            unsigned char note = (unsigned char)(Uniform(0, 3) ? Uniform(36, 43) : Uniform(0, 127));
            Send({(unsigned char)((Uniform(0, 1) ? 0x90 : 0x80) | ch), note, D()}, "midi_note");
        } else if (r < 700) {   // running status: several CCs behind one status byte
            std::vector<unsigned char> b{(unsigned char)(0xB0 | ch)};
            for (int i = Uniform(1, 6); i > 0; --i) { b.push_back(D()); b.push_back(D()); }
            if (Uniform(0, 3) == 0) b.pop_back();   // and a dangling half message
            Send(b, "midi_running_status");
        } else if (r < 740) {   // SysEx, some without F7, some enormous
            std::vector<unsigned char> b{0xF0};
            for (int i = Uniform(0, 9) ? Uniform(1, 40) : Uniform(200, 3000); i > 0; --i) b.push_back(D());
            if (Uniform(0, 3)) b.push_back(0xF7);
            Send(b, "midi_sysex");
        } else if (r < 800) {   // system and realtime bytes, stray data
            static const std::vector<std::vector<unsigned char>> kOdd = {
                {0xF8}, {0xFE}, {0xFA}, {0xFC}, {0xFF}, {0xF6}, {0xF1, 0x10}, {0xF2, 0x01, 0x02}, {0xF3, 0x05},
                {0xF7}, {0x05}, {0x05, 0x10, 0x7F}, {0xF4}, {0xF5, 0x01}, {0xB0}, {0x90, 0x3C}};
            Send(kOdd[size_t(Uniform(0, int(kOdd.size()) - 1))], "midi_system_or_stray");
        } else if (r < 900) {   // the rest of the channel voice messages
            switch (Uniform(0, 3)) {
            case 0: Send({(unsigned char)(0xE0 | ch), D(), D()}, "midi_other"); break;     // pitch bend
            case 1: Send({(unsigned char)(0xC0 | ch), D()}, "midi_other"); break;          // program
            case 2: Send({(unsigned char)(0xD0 | ch), D()}, "midi_other"); break;          // pressure
            default: Send({(unsigned char)(0xA0 | ch), D(), D()}, "midi_other"); break;    // poly AT
            }
        } else {                // random bytes
            std::vector<unsigned char> b(size_t(Uniform(1, 16)));
            for (unsigned char& c : b) c = (unsigned char)Uniform(0, 255);
            Send(b, "midi_random_bytes");
        }
    }
};

// `m` outlives the storm: the controller stays plugged in through the calm end, so the show
// must be listening to it again when it is checked.
void RunMidi(MidiBlaster& m, Clock::time_point deadline) {
    const Options& o = m.o;
    if (!m.Plug(true)) return;
    auto nextReplug = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(o.replugSeconds));
    while (!gStop && Clock::now() < deadline) {
        for (int i = 0; i < 2; ++i) m.One();   // ~1500 messages/s with the sleep below
        SleepMs(1);
        if (o.replugSeconds > 0 && Clock::now() >= nextReplug) {
            const bool whole = m.Uniform(0, 1) == 1;
            m.Unplug(whole);
            gCounts.Add(whole ? "midi_unplug_client" : "midi_unplug_port");
            // Longer than sdfvj's 250 ms port poll, so the show sees the port gone.
            SleepMs(m.Uniform(400, 900));
            if (m.Plug(whole)) gCounts.Add("midi_replug");
            nextReplug = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(o.replugSeconds));
        }
    }
}

// -------------------------------------------------------------------------------------- saves

struct Target {
    fs::path path;
    std::string original;
    std::string kind;   // scene, lib, preset, mapping, isf
};

std::string ReadAll(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
}

struct Saver {
    const Options& o;
    std::vector<Target> targets;
    std::mt19937 rng;
    uint64_t n = 0;
    explicit Saver(const Options& opt) : o(opt), rng(opt.seed * 31337u + 5) {
        const std::pair<const char*, const char*> dirs[] = {
            {"shaders/scenes", "scene"}, {"shaders/lib", "lib"}, {"presets", "preset"}, {"mappings", "mapping"},
            {"shaders/isf", "isf"}};
        for (const auto& [dir, kind] : dirs) {
            std::error_code ec;
            for (const auto& e : fs::directory_iterator(fs::path(o.root) / dir, ec)) {
                const std::string ext = e.path().extension().string();
                if (ext != ".glsl" && ext != ".json" && ext != ".toml" && ext != ".fs") continue;
                targets.push_back({e.path(), ReadAll(e.path()), kind});
            }
        }
    }
    int Uniform(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); }

    // Replaces the first occurrence of `from` (or appends `alt` when it is missing).
    static std::string Replace(std::string s, const std::string& from, const std::string& to, const std::string& alt = "") {
        size_t at = s.find(from);
        if (at == std::string::npos) return s + alt;
        return s.replace(at, from.size(), to);
    }

    // A valid variant: the original with a small change that forces a rebuild. Few distinct
    // variants, so Mesa's shader cache keeps the soak from being only a compile benchmark.
    std::string Valid(const Target& t) {
        const int v = Uniform(0, 3);
        if (t.kind == "preset") return t.original + std::string(size_t(v) + 1, '\n');   // JSON allows trailing space
        if (t.kind == "mapping") return t.original + "\n# soak save " + std::to_string(v) + "\n";
        // A post effect's fix: the file on screen put back (which builds nothing) or a new program,
        // built and first drawn in the chain's spare context (isf/isf_host.h), no frame waiting.
        if (t.kind == "isf" && v == 0) return t.original;
        return t.original + "\n// soak save " + std::to_string(v) + "\n";
    }
    std::string Broken(const Target& t) {
        const std::string& s = t.original;
        switch (Uniform(0, 7)) {
        case 0: return s.substr(0, size_t(Uniform(0, int(s.size()))));          // truncated anywhere
        case 1: return "";
        case 2: {
            std::string j(size_t(Uniform(1, 400)), '\0');
            for (char& c : j) c = char(Uniform(0, 255));
            return j;
        }
        default: break;
        }
        if (t.kind == "scene") {
            switch (Uniform(0, 8)) {
            case 0: return Replace(s, "\"DEFAULT\": ", "\"DEFAULT\": \"abc\", \"X\": ");   // wrong type in the header
            case 1: return Replace(s, "\"MIN\": ", "\"MIN\": [1, 2], \"X\": ");
            case 2: return Replace(s, "\"INPUTS\": [", "\"INPUTS\": {\"a\": 1}, \"X\": [");
            case 3: return Replace(s, "\"NAME\": \"", "\"NAME\": 42, \"X\": \"");
            case 4: return Replace(s, "}*/", "*/");                                        // header JSON cut
            case 5: return Replace(s, "/*{", "/*{{");
            case 6: return Replace(s, "\"TYPE\": \"float\"", "\"TYPE\": \"quaternion\"");
            case 7: return s + "\nvoid soak() { soak_undeclared_symbol; }\n";             // GLSL error
            default: return Replace(s, "\"INPUTS\": [", "\"INPUTS\": [{\"NAME\": 5}, ");
            }
        }
        if (t.kind == "lib") {
            const std::string self = "lib/" + t.path.filename().string();
            switch (Uniform(0, 3)) {
            case 0: return s + "\nfloat soakBroken( {\n";
            case 1: return "#include \"" + self + "\"\n" + s;                   // includes itself
            case 2: return "#include \"lib/soak_missing.glsl\"\n" + s;
            default: return s + "\n#include\n";
            }
        }
        if (t.kind == "isf") {   // the post chain's files (soak.sh starts live with --post)
            const std::string glslError = "\nvoid soakBroken( {\n";   // also where a file lacks the anchor
            switch (Uniform(0, 10)) {
            case 0: return Replace(s, "\"WIDTH\": \"", "\"WIDTH\": \"$WIDTH / 0 + ", glslError);      // not a finite size
            case 1: return Replace(s, "\"WIDTH\": \"", "\"WIDTH\": \"$nope + ((", glslError);        // unknown variable, unclosed
            case 2: return Replace(s, "\"PASSES\": [", "\"PASSES\": [{\"TARGET\": \"huge\", \"WIDTH\": \"$WIDTH * 1e6\", \"HEIGHT\": \"1e300 * 1e300\"}, ", glslError);
            case 3: return Replace(s, "\"TYPE\": \"float\"", "\"TYPE\": \"quaternion\"", glslError);
            case 4: return Replace(s, "\"DEFAULT\": ", "\"DEFAULT\": \"abc\", \"X\": ", glslError);
            case 5: return Replace(s, "\"PASSES\": [", "\"PASSES\": {\"a\": 1}, \"X\": [", glslError);
            case 6: return Replace(s, "\"MAX\": ", "\"MAX\": -1e6, \"X\": ", glslError);            // MIN > MAX
            case 7: return Replace(s, "\"MIN\": ", "\"MIN\": 1e30, \"X\": ", glslError);            // past the value limit
            case 8: return Replace(s, "}*/", "*/", glslError);                                          // header JSON cut
            case 9: return Replace(s, "\"TARGET\": \"", "\"TARGET\": 5, \"X\": \"", glslError);
            default: return s + glslError;                                                             // GLSL error
            }
        }
        if (t.kind == "preset") {
            switch (Uniform(0, 5)) {
            case 0: return Replace(s, "\"scene\": \"", "\"scene\": 42, \"x\": \"");
            case 1: return Replace(s, "\"params\": {", "\"params\": 5, \"x\": {");
            case 2: return Replace(s, "\"scene\": \"", "\"scene\": \"no_such_scene_");
            case 3: return Replace(s, "\"params\": {", "\"params\": {\"twist\": \"x\", ");
            case 4: return Replace(s, "\"params\": {", "\"params\": {\"twist\": 1e308, \"scale\": -1e308, ");
            default: return Replace(s, "\"effects\": \"", "\"effects\": \"warp_drive,reflections=99999999999,");
            }
        }
        switch (Uniform(0, 4)) {   // mapping
        case 0: return Replace(s, "cc = ", "cc = \"x\"\nq = ");
        case 1: return Replace(s, "cc = ", "cc = 99999999999 #");
        case 2: return s + "\n[[map]\ncc = 1\n";
        case 3: return Replace(s, "target = \"", "target = 7\nq = \"");
        default: return s + "\n[[map]]\ncc = -1\ntarget = \"twist\"\nchannel = 99\n";
        }
    }

    static bool WriteFile(const fs::path& p, const std::string& text) {
        std::ofstream f(p, std::ios::binary | std::ios::trunc);
        f.write(text.data(), std::streamsize(text.size()));
        return bool(f);
    }
    // Editor-style: a temp file in the same folder, then rename over the original.
    static bool Rename(const fs::path& p, const std::string& text) {
        fs::path tmp = p.parent_path() / ("." + p.filename().string() + ".soak~");
        if (!WriteFile(tmp, text)) return false;
        std::error_code ec;
        fs::rename(tmp, p, ec);
        return !ec;
    }
    void Save(const Target& t, const std::string& text, bool valid) {
        switch (Uniform(0, 3)) {
        case 0:
        case 1:
            Rename(t.path, text);
            gCounts.Add("save_rename");
            break;
        case 2:
            WriteFile(t.path, text);
            gCounts.Add("save_in_place");
            break;
        default: {   // in place, in two halves with a pause: a slow writer seen half-way
            WriteFile(t.path, text.substr(0, text.size() / 2));
            SleepMs(Uniform(5, 80));
            WriteFile(t.path, text);
            gCounts.Add("save_two_halves");
            break;
        }
        }
        gCounts.Add(valid ? "save_valid" : "save_broken");
        gCounts.Add("save_" + t.kind);
    }
    void One() {
        if (targets.empty()) return;
        // The scene on stage (midi) and the library get most of the saves, the post chain's files some.
        const Target* t = &targets[size_t(Uniform(0, int(targets.size()) - 1))];
        if (Uniform(0, 2) == 0)
            for (const Target& c : targets)
                if (c.path.filename() == "midi.glsl" || (Uniform(0, 1) && c.path.filename() == "common.glsl")) t = &c;
        if (Uniform(0, 7) == 0) {
            const std::string chain = Uniform(0, 1) ? "bloom.fs" : "feedback_trails.fs";
            for (const Target& c : targets)
                if (c.path.filename() == chain) t = &c;
        }
        const bool valid = (n++ % 2) == 0;
        Save(*t, valid ? Valid(*t) : Broken(*t), valid);
    }
    void RestoreAll() {
        for (const Target& t : targets) Rename(t.path, t.original);
        gCounts.Add("restored_files", targets.size());
    }
};

void RunSaves(const Options& o, Clock::time_point deadline) {
    Saver s(o);
    while (!gStop && Clock::now() < deadline) {
        s.One();
        SleepMs(o.saveMs * (0.5 + 0.01 * s.Uniform(0, 100)));
    }
    s.RestoreAll();
}

bool Arg(int argc, char** argv, int& i, const char* name, std::string* out) {
    if (std::strcmp(argv[i], name) != 0 || i + 1 >= argc) return false;
    *out = argv[++i];
    return true;
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        std::string v;
        if (Arg(argc, argv, i, "--osc-port", &v)) o.oscPort = std::atoi(v.c_str());
        else if (Arg(argc, argv, i, "--root", &v)) o.root = v;
        else if (Arg(argc, argv, i, "--seconds", &v)) o.seconds = std::atof(v.c_str());
        else if (Arg(argc, argv, i, "--midi-name", &v)) o.midiName = v;
        else if (Arg(argc, argv, i, "--osc-rate", &v)) o.oscRate = std::atof(v.c_str());
        else if (Arg(argc, argv, i, "--save-ms", &v)) o.saveMs = std::max(20, std::atoi(v.c_str()));
        else if (Arg(argc, argv, i, "--replug-s", &v)) o.replugSeconds = std::atof(v.c_str());
        else if (Arg(argc, argv, i, "--final-preset", &v)) o.finalPreset = v;
        else if (Arg(argc, argv, i, "--final-param", &v)) o.finalParam = v;
        else if (Arg(argc, argv, i, "--final-value", &v)) o.finalValue = std::strtof(v.c_str(), nullptr);
        else if (Arg(argc, argv, i, "--seed", &v)) o.seed = unsigned(std::strtoul(v.c_str(), nullptr, 10));
        else if (Arg(argc, argv, i, "--only", &v)) o.only = v;
        else {
            std::fprintf(stderr, "soak_driver: unknown or incomplete argument '%s' (see the comment at the top of soak_driver.cpp)\n", argv[i]);
            return 2;
        }
    }
    if (o.oscPort <= 0 || o.oscPort > 65535 || o.root.empty() || !fs::is_directory(o.root)) {
        std::fprintf(stderr, "soak_driver: needs --osc-port N and --root DIR (a copy of shaders/, presets/, mappings/)\n");
        return 2;
    }
    if (o.seconds <= 0 || o.seconds > 24 * 3600) o.seconds = 20;

    // SIGTERM (the show died, the soak stops us): end the storm, restore the files, print the counts.
    std::signal(SIGTERM, [](int) { gStop = true; });
    const auto t0 = Clock::now();
    const auto deadline = t0 + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(o.seconds));
    std::printf("STORM start, %.0f s\n", o.seconds);
    std::fflush(stdout);
    MidiBlaster midi(o);
    std::vector<std::thread> threads;
    if (o.only.empty() || o.only == "osc") threads.emplace_back(RunOsc, std::cref(o), deadline);
    if (o.only.empty() || o.only == "midi") threads.emplace_back(RunMidi, std::ref(midi), deadline);
    if (o.only.empty() || o.only == "saves") threads.emplace_back(RunSaves, std::cref(o), deadline);
    for (std::thread& t : threads) t.join();
    std::printf("STORM end after %.1f s\n", Since(t0));
    std::fflush(stdout);

    if (gStop) {
        std::printf("STOPPED by SIGTERM\n");
        std::lock_guard<std::mutex> g(gCounts.m);
        for (const auto& [k, v] : gCounts.n) std::printf("COUNT %s %llu\n", k.c_str(), (unsigned long long)v);
        return 1;
    }
    // The storm is over and every file is back. The performer picks the preset and sets one value.
    lo_address a = lo_address_new("127.0.0.1", std::to_string(o.oscPort).c_str());
    SleepMs(1000);
    lo_send(a, "/sdfvj/preset", "s", o.finalPreset.c_str());
    gCounts.Add("final_osc");
    SleepMs(2500);   // the preset's scene compiles (it may have been a broken save a moment ago)
    const std::string address = "/sdfvj/raw/" + o.finalParam;
    for (int i = 0; i < 8; ++i) {
        lo_send(a, address.c_str(), "f", o.finalValue);
        gCounts.Add("final_osc");
        SleepMs(250);
    }
    lo_address_free(a);
    std::printf("FINAL %s f %g\n", address.c_str(), double(o.finalValue));
    {
        std::lock_guard<std::mutex> g(gCounts.m);
        for (const auto& [k, v] : gCounts.n) std::printf("COUNT %s %llu\n", k.c_str(), (unsigned long long)v);
    }
    return 0;
}
