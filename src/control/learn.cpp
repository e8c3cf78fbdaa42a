// RunLearn: `sdfvj learn --param NAME [--mapping FILE]`. Listens on every MIDI port (and OSC),
// takes the first control that moves, and appends a [[map]] entry for it to the mapping file.
//
// The file is never left half-done: the new text (old text + the entry) is built in memory,
// parsed as a mapping, and only then written to a temporary file in the same folder and renamed
// over the original. Any failure leaves the file byte-identical.
// OSC listens on 9000 like `sdfvj live`; when a running show already holds that port, learn
// takes a free one and says which.
#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <chrono>
#include <memory>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "control/control.h"

namespace sdfvj {
namespace {

constexpr int kLearnOscPort = 9000;   // the same default as `sdfvj live --osc-port`

// Parameter names are scene uniforms (u_<name>): a TOML string of them needs no escaping.
bool IsParamName(const std::string& s) {
    if (s.empty() || !(std::isalpha((unsigned char)s[0]) || s[0] == '_')) return false;
    for (char c : s)
        if (!(std::isalnum((unsigned char)c) || c == '_')) return false;
    return true;
}

// Whole file, or "" with *exists = false when there is none. False on a read error.
bool ReadWhole(const std::string& path, std::string* text, bool* exists) {
    *exists = false;
    text->clear();
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) return !ec;
    std::ifstream f(path, std::ios::binary);
    if (!f) return false;
    std::stringstream ss;
    ss << f.rdbuf();
    *exists = true;
    *text = ss.str();
    return !f.bad();
}

}  // namespace

std::string LearnSource(const ControlEvent& e, LearnState& state) {
    if (e.source == EventSource::Osc) {
        if (e.address.empty() || e.address.rfind("/sdfvj/", 0) == 0) return "";
        // The address goes into a TOML string: only what cannot break out of one.
        for (char c : e.address)
            if (c == '"' || c == '\\' || (unsigned char)c < 0x20 || (unsigned char)c >= 0x7F) return "";
        return "osc = \"" + e.address + "\"";
    }
    if (e.midiSize < 2) return "";   // clock, start, stop: not a control
    const int type = e.midi[0] & 0xF0, ch = (e.midi[0] & 0x0F) + 1;
    const std::string chan = "\nchannel = " + std::to_string(ch);
    if (type == 0xB0 && e.midiSize == 3) {
        const int cc = e.midi[1];
        // NRPN: CC 99/98 select a number, CC 6 carries its value. RPN (101/100) deselects.
        int& sel = state.nrpnSelected.try_emplace(ch, -1).first->second;
        if (cc == 99) { sel = (sel < 0 ? 0 : (sel & 0x7F)) | (e.midi[2] << 7) | (1 << 20); return ""; }
        if (cc == 98) { sel = (sel < 0 ? 0 : (sel & ~0x7F)) | e.midi[2] | (1 << 21); return ""; }
        if (cc == 101 || cc == 100) { sel = 0; return ""; }
        if (cc == 6 && sel > 0 && (sel & (3 << 20)) == (3 << 20)) return "nrpn = " + std::to_string(sel & 0x3FFF) + chan;
        if (cc == 6 || cc == 38) return "";
        // "Moves": a second, different value on the same CC (a pad press sends one 127).
        const int key = ch * 128 + cc;
        auto it = state.ccFirst.find(key);
        if (it == state.ccFirst.end()) {
            state.ccFirst[key] = e.midi[2];
            return "";
        }
        if (it->second == e.midi[2]) return "";
        return "cc = " + std::to_string(cc) + chan;
    }
    if (type == 0x90 && e.midiSize == 3 && e.midi[2] > 0)
        return "note = " + std::to_string(e.midi[1]) + chan + "\naction = \"toggle\"";
    if (type == 0xE0) return "pitchbend = true" + chan;
    return "";
}

bool WriteFileAtomically(const std::string& path, const std::string& text, std::string* error) {
    namespace fs = std::filesystem;
    std::error_code ec;
    fs::path target = fs::is_symlink(path, ec) ? fs::canonical(path, ec) : fs::path(path);
    fs::path folder = target.parent_path().empty() ? fs::path(".") : target.parent_path();
    std::string tmp = (folder / ("." + target.filename().string() + ".tmp-XXXXXX")).string();
    int fd = mkstemp(tmp.data());
    if (fd < 0) {
        *error = path + ":1:1: cannot write next to the file (" + std::strerror(errno) +
                 "), expected a writable folder " + folder.string();
        return false;
    }
    struct stat st;
    mode_t mode = stat(target.c_str(), &st) == 0 ? (st.st_mode & 07777) : mode_t(0644);
    bool ok = fchmod(fd, mode) == 0;
    for (size_t done = 0; ok && done < text.size();) {
        ssize_t n = write(fd, text.data() + done, text.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) ok = false;
        else done += size_t(n);
    }
    ok = ok && fsync(fd) == 0;
    int savedErrno = errno;
    ok = close(fd) == 0 && ok;
    if (ok && rename(tmp.c_str(), target.c_str()) != 0) {
        ok = false;
        savedErrno = errno;
    }
    if (!ok) {
        unlink(tmp.c_str());
        *error = path + ":1:1: cannot write the file (" + std::strerror(savedErrno) + "), expected a writable file";
    }
    return ok;
}

std::string AddLearnedEntry(const std::string& mappingPath, const std::string& param, const std::string& source,
                            const std::vector<ParamDecl>& decls, const std::string& comment) {
    std::string text;
    bool exists = false;
    if (!ReadWhole(mappingPath, &text, &exists))
        return mappingPath + ":1:1: cannot read the file, expected a readable mapping file";
    Mapping before;
    if (exists) {
        LoadResult r = ParseMapping(text, mappingPath, &before);
        if (!r.ok) return r.error + " (learn did not write)";
    }
    std::string next = text;
    if (!next.empty() && next.back() != '\n') next += '\n';
    next += "\n# " + comment + "\n[[map]]\n" + source + "\ntarget = \"" + param + "\"\n";
    Mapping after;
    LoadResult r = ParseMapping(next, mappingPath, &after);
    if (!r.ok) return r.error + " (after adding the learned entry; " + mappingPath + " is unchanged)";
    if (after.entries.size() != before.entries.size() + 1 || after.entries.back().target != param)
        return mappingPath + ":1:1: the learned entry did not read back as one more [[map]] for '" + param +
               "', expected the file to take new [[map]] tables (" + mappingPath + " is unchanged)";
    if (!decls.empty()) {   // only the new entry must fit this scene: the file may hold others
        Mapping added;
        added.entries.push_back(after.entries.back());
        std::string problems;
        if (!ValidateMapping(added, decls, &problems)) return problems + " (" + mappingPath + " is unchanged)";
    }
    std::string error;
    if (!WriteFileAtomically(mappingPath, next, &error)) return error;
    return "";
}

int RunLearn(const std::string& param, const std::string& mappingPath, double timeoutSeconds) {
    if (!IsParamName(param)) {
        std::fprintf(stderr, "sdfvj learn: bad parameter name '%s', expected letters, digits and '_' (a scene INPUT name)\n",
                     param.c_str());
        return 2;
    }
    {
        std::string text;
        bool exists = false;
        Mapping existing;
        if (!ReadWhole(mappingPath, &text, &exists)) {
            std::fprintf(stderr, "%s:1:1: cannot read the file, expected a readable mapping file\n", mappingPath.c_str());
            return 2;
        }
        LoadResult r = exists ? ParseMapping(text, mappingPath, &existing) : LoadResult{true, ""};
        if (!r.ok) {
            std::fprintf(stderr, "%s\n", r.error.c_str());
            return 2;
        }
    }
    EventQueue queue;
    auto t0 = std::chrono::steady_clock::now();
    auto clock = [t0] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
    InputOptions opt;
    opt.log = false;
    // A running `sdfvj live` holds 9000: learn must still start, on a port of its own. Binding is
    // the test (a check before it would race with whoever binds between the two).
    opt.oscPort = kLearnOscPort;
    auto session = std::make_unique<InputSession>(opt, queue, clock);
    if (session->OscPort() <= 0) {
        session.reset();
        opt.oscPort = 0;
        session = std::make_unique<InputSession>(opt, queue, clock);
    }
    for (const std::string& s : session->StatusLines()) std::fprintf(stderr, "%s\n", s.c_str());
    if (opt.oscPort == 0 && session->OscPort() > 0)
        std::fprintf(stderr, "learn: UDP port %d is taken (a running `sdfvj live`?), send OSC to port %d instead\n",
                     kLearnOscPort, session->OscPort());
    std::fprintf(stderr, "learn: move the control for '%s' (%.0f s)...\n", param.c_str(), timeoutSeconds);
    LearnState learnState;
    while (clock() < timeoutSeconds) {
        for (const ControlEvent& e : queue.DrainUntil(clock())) {
            std::string src = LearnSource(e, learnState);
            if (src.empty()) continue;
            std::string error = AddLearnedEntry(mappingPath, param, src, {}, "learned by `sdfvj learn --param " + param + "`");
            if (!error.empty()) {
                std::fprintf(stderr, "%s\n", error.c_str());
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
