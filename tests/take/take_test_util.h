// Helpers shared by the take tests: events, byte builders, temp files.
#pragma once
#include <unistd.h>

#include <cstdio>
#include <initializer_list>
#include <string>
#include <vector>

#include "take/take.h"

namespace take_test {

inline sdfvj::ControlEvent Midi(double t, std::initializer_list<int> bytes) {
    sdfvj::ControlEvent e;
    e.time = t;
    e.source = sdfvj::EventSource::Midi;
    for (int b : bytes) e.midi[e.midiSize++] = uint8_t(b);
    return e;
}

inline sdfvj::ControlEvent Osc(double t, const std::string& address, std::vector<sdfvj::OscArg> args) {
    sdfvj::ControlEvent e;
    e.time = t;
    e.source = sdfvj::EventSource::Osc;
    e.address = address;
    e.args = std::move(args);
    return e;
}

inline sdfvj::OscArg Arg(char type, float f = 0, int i = 0, std::string s = {}) {
    sdfvj::OscArg a;
    a.type = type;
    a.f = f;
    a.i = i;
    a.s = std::move(s);
    return a;
}

// A fresh path in the temp directory; the file is removed when the object goes.
struct TempFile {
    std::string path;
    explicit TempFile(const char* stem) {
        char buf[256];
        std::snprintf(buf, sizeof buf, "/tmp/sdfvj_%s_%d_XXXXXX", stem, int(getpid()));
        const int fd = mkstemp(buf);
        if (fd >= 0) close(fd);
        path = buf;
    }
    ~TempFile() { std::remove(path.c_str()); }
};

// Builds SMF bytes by hand.
struct Bytes {
    std::vector<uint8_t> v;
    Bytes& operator()(std::initializer_list<int> bytes) {
        for (int b : bytes) v.push_back(uint8_t(b));
        return *this;
    }
    Bytes& Str(const std::string& s) {
        v.insert(v.end(), s.begin(), s.end());
        return *this;
    }
    Bytes& U32(uint32_t x) { return (*this)({int(x >> 24), int((x >> 16) & 0xFF), int((x >> 8) & 0xFF), int(x & 0xFF)}); }
    Bytes& Header(int format, int tracks, int division) {
        Str("MThd").U32(6);
        return (*this)({0, format, 0, tracks, (division >> 8) & 0xFF, division & 0xFF});
    }
    Bytes& Track(const std::vector<uint8_t>& body) {
        Str("MTrk").U32(uint32_t(body.size()));
        v.insert(v.end(), body.begin(), body.end());
        return *this;
    }
};

inline bool SameMidi(const sdfvj::ControlEvent& e, std::initializer_list<int> bytes) {
    if (e.source != sdfvj::EventSource::Midi || e.midiSize != bytes.size()) return false;
    int i = 0;
    for (int b : bytes)
        if (e.midi[i++] != b) return false;
    return true;
}

}  // namespace take_test
