// LoadMapping: TOML -> Mapping, with `file:line:col: what is wrong, expected ...` errors.
// The format is documented in docs/input.md; every key is checked so a typo is an error
// instead of a silently ignored line.
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include <toml++/toml.h>

#include "control/control.h"

namespace sdfvj {
namespace {

struct LoadError {
    std::string text;
};

std::string Where(const std::string& path, const toml::source_region& r) {
    return path + ":" + std::to_string(r.begin.line) + ":" + std::to_string(r.begin.column) + ": ";
}

[[noreturn]] void Fail(const std::string& path, const toml::node& n, const std::string& what) {
    throw LoadError{Where(path, n.source()) + what};
}

int GetInt(const std::string& path, const toml::node& n, const char* key, int lo, int hi) {
    auto v = n.value<int64_t>();
    if (!n.is_integer() || !v || *v < lo || *v > hi)
        Fail(path, n, std::string("bad value for '") + key + "', expected an integer " +
                          std::to_string(lo) + ".." + std::to_string(hi));
    return int(*v);
}

float GetNumber(const std::string& path, const toml::node& n, const char* key) {
    if (!n.is_number()) Fail(path, n, std::string("bad value for '") + key + "', expected a number");
    double d = *n.value<double>();
    if (!std::isfinite(d)) Fail(path, n, std::string("bad value for '") + key + "', expected a finite number");
    return float(d);
}

bool GetBool(const std::string& path, const toml::node& n, const char* key) {
    if (!n.is_boolean()) Fail(path, n, std::string("bad value for '") + key + "', expected true or false");
    return *n.value<bool>();
}

std::string GetString(const std::string& path, const toml::node& n, const char* key) {
    if (!n.is_string()) Fail(path, n, std::string("bad value for '") + key + "', expected a string");
    return *n.value<std::string>();
}

int GetChannel(const std::string& path, const toml::node& n) {
    if (n.is_string() && *n.value<std::string>() == "any") return 0;
    if (!n.is_integer()) Fail(path, n, "bad value for 'channel', expected 1..16 or \"any\"");
    return GetInt(path, n, "channel", 1, 16);
}

template <typename E>
E GetEnum(const std::string& path, const toml::node& n, const char* key,
          std::initializer_list<std::pair<const char*, E>> names) {
    std::string expected;
    if (n.is_string()) {
        std::string s = *n.value<std::string>();
        for (auto& [name, e] : names)
            if (s == name) return e;
    }
    for (auto& [name, e] : names) expected += (expected.empty() ? "" : ", ") + std::string(name);
    Fail(path, n, std::string("bad value for '") + key + "', expected one of: " + expected);
}

MappingEntry ParseEntry(const std::string& path, const toml::table& t, bool pad, int profileChannel) {
    static const std::set<std::string> kKeys = {
        "cc", "cc14", "note", "pitchbend", "program", "nrpn", "osc", "channel", "hires", "target",
        "range", "curve", "curve_amount", "invert", "smoothing", "takeover", "encoder", "step",
        "action", "preset", "effect", "audio", "gain", "attack", "release"};
    MappingEntry en;
    en.line = int(t.source().begin.line);
    en.column = int(t.source().begin.column);
    en.channel = profileChannel;
    for (auto&& [k, v] : t)
        if (!kKeys.count(std::string(k.str())))
            Fail(path, v, "unknown key '" + std::string(k.str()) +
                              "', expected one of: cc, cc14, note, pitchbend, program, nrpn, osc, channel, "
                              "hires, target, range, curve, curve_amount, invert, smoothing, takeover, "
                              "encoder, step, action, preset, effect, audio, gain, attack, release");

    int sources = 0;
    bool hiResSet = false;
    if (auto n = t.get("cc")) { en.kind = SourceKind::Cc; en.number = GetInt(path, *n, "cc", 0, 127); ++sources; }
    if (auto n = t.get("cc14")) {
        en.kind = SourceKind::Cc; en.number = GetInt(path, *n, "cc14", 0, 31); en.hiRes = true;
        hiResSet = true; ++sources;
    }
    if (auto n = t.get("note")) { en.kind = SourceKind::Note; en.number = GetInt(path, *n, "note", 0, 127); ++sources; }
    if (auto n = t.get("pitchbend")) {
        if (!GetBool(path, *n, "pitchbend")) Fail(path, *n, "bad value for 'pitchbend', expected true");
        en.kind = SourceKind::PitchBend; ++sources;
    }
    if (auto n = t.get("program")) {
        en.kind = SourceKind::Program; ++sources;
        if (n->is_string() && *n->value<std::string>() == "any") en.number = -1;
        else if (n->is_integer()) en.number = GetInt(path, *n, "program", 0, 127);
        else Fail(path, *n, "bad value for 'program', expected 0..127 or \"any\"");
    }
    if (auto n = t.get("nrpn")) {
        en.kind = SourceKind::Nrpn; en.number = GetInt(path, *n, "nrpn", 0, 16383); en.hiRes = true; ++sources;
    }
    if (auto n = t.get("osc")) {
        en.kind = SourceKind::Osc; en.oscAddress = GetString(path, *n, "osc"); ++sources;
        if (en.oscAddress.empty() || en.oscAddress[0] != '/')
            Fail(path, *n, "bad value for 'osc', expected an address starting with '/'");
    }
    if (auto n = t.get("audio")) {
        // A feature of the audio input (src/audio): audio = "bass".
        en.kind = SourceKind::Audio; ++sources;
        if (!n->is_string() || !ParseAudioFeatureName(*n->value<std::string>(), &en.audio))
            Fail(path, *n, "bad value for 'audio', expected one of: " + AudioFeatureNameList());
    }
    if (sources != 1)
        Fail(path, t, sources == 0 ? "entry has no source, expected one of cc, cc14, note, pitchbend, program, nrpn, osc, audio"
                                   : "entry has more than one source, expected exactly one of cc, cc14, note, "
                                     "pitchbend, program, nrpn, osc, audio");
    // gain, attack and release shape an audio feature; on a knob they would be silently ignored.
    for (const char* key : {"gain", "attack", "release"}) {
        auto n = t.get(key);
        if (!n) continue;
        if (en.kind != SourceKind::Audio)
            Fail(path, *n, std::string("'") + key + "' applies to audio sources only, expected it removed or audio = \"...\"");
        const float v = GetNumber(path, *n, key);
        if (std::string(key) == "gain") {
            if (v <= 0.0f || v > 100.0f) Fail(path, *n, "bad value for 'gain', expected a number in (0, 100]");
            en.gain = v;
        } else {
            if (v < 0.0f || v > 60.0f) Fail(path, *n, std::string("bad value for '") + key + "', expected seconds 0..60");
            (std::string(key) == "attack" ? en.attack : en.release) = v;
        }
    }

    if (auto n = t.get("channel")) en.channel = GetChannel(path, *n);
    if (auto n = t.get("hires")) {
        bool h = GetBool(path, *n, "hires");
        if (en.kind == SourceKind::Cc && h && en.number > 31)
            Fail(path, *n, "14-bit CC pairs need the MSB on CC 0..31 (LSB is CC n+32), expected cc <= 31");
        if (h && en.kind != SourceKind::Cc && en.kind != SourceKind::Nrpn)
            Fail(path, *n, "'hires' applies to cc and nrpn sources only, expected it removed");
        if (!h && hiResSet) Fail(path, *n, "cc14 is always 14-bit, expected hires = true or no hires key");
        en.hiRes = h;
    }
    if (auto n = t.get("target")) {
        // A name ("twist"), or a position: target = 3 is the scene's third input, so one
        // controller profile drives every scene.
        if (n->is_integer()) {
            en.targetIndex = GetInt(path, *n, "target", 1, 64);
            en.target = "#" + std::to_string(en.targetIndex);
        } else {
            en.target = GetString(path, *n, "target");
        }
    }
    if (auto n = t.get("range")) {
        const toml::array* arr = n->as_array();
        if (!arr || arr->size() != 2) Fail(path, *n, "bad value for 'range', expected [min, max]");
        en.outMin = GetNumber(path, *arr->get(0), "range");
        en.outMax = GetNumber(path, *arr->get(1), "range");
        en.hasRange = true;
    }
    if (auto n = t.get("curve"))
        en.curve = GetEnum<Curve>(path, *n, "curve", {{"linear", Curve::Linear}, {"exponential", Curve::Exponential},
                                                      {"logarithmic", Curve::Logarithmic}, {"s", Curve::S}});
    if (auto n = t.get("curve_amount")) {
        en.curveAmount = GetNumber(path, *n, "curve_amount");
        if (en.curveAmount <= 0.0f || en.curveAmount > 20.0f)
            Fail(path, *n, "bad value for 'curve_amount', expected a number in (0, 20]");
    }
    if (auto n = t.get("invert")) en.invert = GetBool(path, *n, "invert");
    if (auto n = t.get("smoothing")) {
        en.smoothing = GetNumber(path, *n, "smoothing");
        if (en.smoothing < 0.0f || en.smoothing > 60.0f)
            Fail(path, *n, "bad value for 'smoothing', expected seconds 0..60");
    }
    if (auto n = t.get("takeover"))
        en.takeover = GetEnum<Takeover>(path, *n, "takeover",
                                        {{"none", Takeover::None}, {"pickup", Takeover::Pickup}, {"scale", Takeover::Scale}});
    if (auto n = t.get("encoder")) {
        en.encoder = GetEnum<EncoderMode>(path, *n, "encoder",
                                          {{"absolute", EncoderMode::Absolute}, {"signed_bit", EncoderMode::SignedBit},
                                           {"signed_bit2", EncoderMode::SignedBit2},
                                           {"binary_offset", EncoderMode::BinaryOffset},
                                           {"twos_complement", EncoderMode::TwosComplement}});
        if (en.encoder != EncoderMode::Absolute && (en.kind != SourceKind::Cc || en.hiRes))
            Fail(path, *n, "relative encoders send 7-bit CCs, expected a 'cc' source");
    }
    if (auto n = t.get("step")) {
        en.step = GetNumber(path, *n, "step");
        if (en.step <= 0.0f || en.step > 1.0f) Fail(path, *n, "bad value for 'step', expected a fraction in (0, 1]");
    }
    if (auto n = t.get("action")) {
        en.action = GetEnum<PadAction>(path, *n, "action",
                                       {{"continuous", PadAction::None}, {"trigger", PadAction::Trigger},
                                        {"toggle", PadAction::Toggle}, {"preset", PadAction::Preset},
                                        {"effect", PadAction::Effect}, {"tap_tempo", PadAction::TapTempo}});
    } else if (pad || en.kind == SourceKind::Note) {
        en.action = PadAction::Trigger;
    } else if (en.kind == SourceKind::Program) {
        en.action = PadAction::Preset;
    }
    if (auto n = t.get("preset")) en.preset = GetString(path, *n, "preset");
    if (auto n = t.get("effect")) en.effect = GetString(path, *n, "effect");

    bool needsTarget = en.action == PadAction::None || en.action == PadAction::Trigger || en.action == PadAction::Toggle;
    if (needsTarget && en.target.empty()) Fail(path, t, "entry has no 'target', expected a parameter name");
    if (en.action == PadAction::Effect && en.effect.empty())
        Fail(path, t, "action \"effect\" has no 'effect', expected an effect name");
    if (en.encoder != EncoderMode::Absolute && en.action != PadAction::None)
        Fail(path, t, "a relative encoder cannot drive a pad action, expected action = \"continuous\"");
    return en;
}

}  // namespace

LoadResult ParseMapping(const std::string& text, const std::string& path, Mapping* out) {
    LoadResult r;
    try {
        toml::table root = toml::parse(text, path);
        Mapping m;
        m.path = path;
        int channel = 0;
        for (auto&& [k, v] : root) {
            std::string key(k.str());
            if (key != "profile" && key != "map" && key != "pad")
                Fail(path, v, "unknown table '" + key + "', expected [profile], [[map]] or [[pad]]");
        }
        if (auto n = root.get("profile")) {
            const toml::table* pt = n->as_table();
            if (!pt) Fail(path, *n, "'profile' must be a table, expected [profile]");
            for (auto&& [k, v] : *pt) {
                std::string key(k.str());
                if (key == "name") m.name = GetString(path, v, "name");
                else if (key == "device") m.device = GetString(path, v, "device");
                else if (key == "channel") channel = GetChannel(path, v);
                else if (key == "presets") {
                    const toml::array* arr = v.as_array();
                    if (!arr || arr->size() > 128)
                        Fail(path, v, "bad value for 'presets', expected a list of up to 128 preset names");
                    for (auto&& e : *arr) {
                        std::string name = GetString(path, e, "presets");
                        if (name.empty() || name.find('/') != std::string::npos || name.size() > 128)
                            Fail(path, e, "bad preset name in 'presets', expected a name from presets/ such as \"demo\"");
                        m.presets.push_back(name);
                    }
                }
                else Fail(path, v, "unknown key '" + key + "' in [profile], expected name, device, channel or presets");
            }
        }
        // Keep file order across [[map]] and [[pad]] so "later entries win" reads naturally.
        std::vector<std::pair<const toml::table*, bool>> tables;
        for (const char* key : {"map", "pad"}) {
            auto n = root.get(key);
            if (!n) continue;
            const toml::array* arr = n->as_array();
            if (!arr || !arr->is_array_of_tables())
                Fail(path, *n, std::string("'") + key + "' must be an array of tables, expected [[" + key + "]]");
            for (auto&& e : *arr) tables.emplace_back(e.as_table(), std::string(key) == "pad");
        }
        std::stable_sort(tables.begin(), tables.end(), [](auto& a, auto& b) {
            return a.first->source().begin.line < b.first->source().begin.line;
        });
        for (auto& [t, pad] : tables) m.entries.push_back(ParseEntry(path, *t, pad, channel));
        *out = std::move(m);
        r.ok = true;
    } catch (const toml::parse_error& e) {
        const auto& b = e.source().begin;
        r.error = path + ":" + std::to_string(b.line) + ":" + std::to_string(b.column) + ": " +
                  std::string(e.description()) + ", expected valid TOML";
    } catch (const LoadError& e) {
        r.error = e.text;
    }
    return r;
}

LoadResult LoadMapping(const std::string& path, Mapping* out) {
    std::ifstream f(path, std::ios::binary);
    if (!f) return LoadResult{false, path + ":1:1: cannot open the file, expected a readable mapping file"};
    std::stringstream ss;
    ss << f.rdbuf();
    return ParseMapping(ss.str(), path, out);
}

bool ValidateMapping(const Mapping& m, const std::vector<ParamDecl>& decls, std::string* error) {
    std::string all;
    for (const MappingEntry& en : m.entries) {
        if (en.target.empty() || en.targetIndex > 0) continue;
        bool found = false;
        for (const ParamDecl& d : decls) found = found || d.name == en.target;
        if (!found)
            all += (all.empty() ? "" : "\n") + m.path + ":" + std::to_string(en.line) + ":" +
                   std::to_string(en.column) + ": unknown parameter '" + en.target +
                   "', expected one of: " + ParamNameList(decls);
    }
    if (error) *error = all;
    return all.empty();
}

}  // namespace sdfvj
