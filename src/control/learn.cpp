// RunLearn: `sdfvj learn --param NAME [--mapping FILE]`. Listens on every MIDI port (and OSC),
// takes the first control that moves, and appends a [[map]] entry for it to the mapping file.
#include <chrono>
#include <cstdio>
#include <fstream>
#include <thread>

#include "control/control.h"

namespace sdfvj {
namespace {

// The TOML source line for a learned event, or "" if the event is not something to learn.
// Takes the MSB of NRPN/14-bit pairs into account by waiting: the caller passes every event.
std::string LearnSource(const ControlEvent& e, std::map<int, int>* ccFirst, std::map<int, int>* nrpnSelected) {
    if (e.source == EventSource::Osc) {
        if (e.address.rfind("/sdfvj/", 0) == 0) return "";
        return "osc = \"" + e.address + "\"";
    }
    uint8_t type = e.midi[0] & 0xF0;
    int ch = (e.midi[0] & 0x0F) + 1;
    std::string chan = "\nchannel = " + std::to_string(ch);
    if (type == 0xB0) {
        int cc = e.midi[1];
        // NRPN: CC 99/98 select a number, CC 6 carries its value. RPN (101/100) deselects.
        int& sel = (*nrpnSelected)[ch];
        if (cc == 99) { sel = (sel < 0 ? 0 : (sel & 0x7F)) | (e.midi[2] << 7) | (1 << 20); return ""; }
        if (cc == 98) { sel = (sel < 0 ? 0 : (sel & ~0x7F)) | e.midi[2] | (1 << 21); return ""; }
        if (cc == 101 || cc == 100) { sel = 0; return ""; }
        if (cc == 6 && (sel & (3 << 20)) == (3 << 20)) return "nrpn = " + std::to_string(sel & 0x3FFF) + chan;
        if (cc == 6 || cc == 38) return "";
        // "Moves": a second, different value on the same CC (a pad press sends one 127).
        int key = ch * 128 + cc;
        auto it = ccFirst->find(key);
        if (it == ccFirst->end()) {
            (*ccFirst)[key] = e.midi[2];
            return "";
        }
        if (it->second == e.midi[2]) return "";
        return "cc = " + std::to_string(cc) + chan;
    }
    if (type == 0x90 && e.midi[2] > 0) return "note = " + std::to_string(e.midi[1]) + chan + "\naction = \"toggle\"";
    if (type == 0xE0) return "pitchbend = true" + chan;
    return "";
}

}  // namespace

int RunLearn(const std::string& param, const std::string& mappingPath, double timeoutSeconds) {
    Mapping existing;
    {
        std::ifstream probe(mappingPath);
        if (probe) {
            LoadResult r = LoadMapping(mappingPath, &existing);
            if (!r.ok) {
                std::fprintf(stderr, "%s\n", r.error.c_str());
                return 2;
            }
        }
    }
    EventQueue queue;
    auto t0 = std::chrono::steady_clock::now();
    auto clock = [t0] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
    InputOptions opt;
    opt.log = false;
    InputSession session(opt, queue, clock);
    for (const std::string& s : session.StatusLines()) std::fprintf(stderr, "%s\n", s.c_str());
    std::fprintf(stderr, "learn: move the control for '%s' (%.0f s)...\n", param.c_str(), timeoutSeconds);
    std::map<int, int> ccFirst, nrpnSelected;
    while (clock() < timeoutSeconds) {
        for (const ControlEvent& e : queue.DrainUntil(clock())) {
            std::string src = LearnSource(e, &ccFirst, &nrpnSelected);
            if (src.empty()) continue;
            std::ofstream out(mappingPath, std::ios::app);
            if (!out) {
                std::fprintf(stderr, "%s:1:1: cannot write the file, expected a writable mapping file\n", mappingPath.c_str());
                return 2;
            }
            out << "\n# learned by `sdfvj learn --param " << param << "`\n[[map]]\n" << src << "\ntarget = \"" << param << "\"\n";
            out.close();
            Mapping check;
            LoadResult r = LoadMapping(mappingPath, &check);
            if (!r.ok) {
                std::fprintf(stderr, "%s\n", r.error.c_str());
                return 2;
            }
            std::printf("learned: %s -> %s, written to %s\n", src.substr(0, src.find('\n')).c_str(), param.c_str(), mappingPath.c_str());
            return 0;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    std::fprintf(stderr, "learn: no control moved within %.0f s\n", timeoutSeconds);
    return 1;
}

}  // namespace sdfvj
