// The stages of a `sdfvj live` frame that change the show's state (see live_session.h).
#include "app/live_session.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "app/live_support.h"

namespace fs = std::filesystem;

namespace sdfvj {

namespace {

std::string Canonical(const std::string& path) {
    std::error_code ec;
    fs::path p = fs::weakly_canonical(path, ec);
    return ec ? fs::absolute(path).lexically_normal().string() : p.string();
}

bool SameDecls(const std::vector<ParamDecl>& a, const std::vector<ParamDecl>& b) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i)
        if (a[i].name != b[i].name || a[i].type != b[i].type || a[i].minValue != b[i].minValue ||
            a[i].maxValue != b[i].maxValue || a[i].defaultValue != b[i].defaultValue || a[i].label != b[i].label)
            return false;
    return true;
}

void WatchFolderOf(LiveState& s, const std::string& canonicalFile) {
    s.foldersToWatch.push_back(fs::path(canonicalFile).parent_path().string());
}

}  // namespace

// Outside input is echoed in messages (a preset name, an OSC address): only printable text
// reaches the terminal and the overlay. Control bytes and broken UTF-8 become '?', and a line is
// cut at 2000 bytes.
std::string PrintableLine(const std::string& text) {
    std::string out;
    const size_t n = std::min(text.size(), (size_t)2000);
    for (size_t i = 0; i < n;) {
        const unsigned char c = (unsigned char)text[i];
        if (c == '\n' || c == '\t' || (c >= 0x20 && c < 0x7f)) {
            out += (char)c;
            ++i;
            continue;
        }
        const size_t len = c >= 0xf0 && c < 0xf5 ? 4 : c >= 0xe0 ? 3 : c >= 0xc2 && c < 0xe0 ? 2 : 0;
        bool ok = len > 0 && i + len <= n;
        for (size_t k = 1; ok && k < len; ++k) ok = ((unsigned char)text[i + k] & 0xc0) == 0x80;
        if (ok) {
            out.append(text, i, len);
            i += len;
        } else {
            out += '?';
            ++i;
        }
    }
    if (text.size() > n) out += "...";
    return out;
}

void LiveReport::Say(const std::string& raw) {
    const std::string line = PrintableLine(raw);
    if (print) std::fprintf(stderr, "%s\n", line.c_str());
    recent.push_back(line);
    while (recent.size() > 8) recent.pop_front();
}

void LiveReport::Limited(double now, const std::vector<std::string>& lines, const std::string& kind) {
    if (lines.empty()) return;
    Throttle& t = throttles[kind];
    if (now - t.last < 1.0) {
        t.suppressed += lines.size();
        return;
    }
    std::string line = lines.back();
    if (t.suppressed + lines.size() > 1)
        line += " (and " + std::to_string(t.suppressed + lines.size() - 1) + " more in the last second)";
    Say(line);
    t.last = now;
    t.suppressed = 0;
}

bool OpenLiveState(const ShowOptions& options, const std::string& mappingOption, LiveState* state, std::string* error) {
    LiveState s;
    s.options = options;
    if (!PrepareShow(options, &s.show, error)) return false;
    if (!LoadShowMapping(s.show, mappingOption, &s.mapping, error)) return false;
    s.mappingFile = ResolveMappingPath(s.show, mappingOption);
    s.mappingPath = Canonical(s.mappingFile);
    s.presetFile = s.show.preset.path;
    s.presetPath = s.presetFile.empty() ? "" : Canonical(s.presetFile);
    s.currentPreset = s.presetFile.empty() ? "" : fs::path(s.presetFile).filename().string();
    s.params = ShowParamState(s.show);
    s.wanted = VariantKey{s.show.scene.path, s.show.effects, s.show.path};
    if (!s.show.preset.automation.Empty() &&
        !s.automation.automation.Load(s.show.preset.automation, ShowDecls(s.show), error))
        return false;
    if (s.show.preset.automation.bpm > 0) s.automation.tempo.SetBpm(0.0, s.show.preset.automation.bpm);
    s.automation.automation.Start(0.0);
    WatchFolderOf(s, s.mappingPath);
    if (!s.presetPath.empty()) WatchFolderOf(s, s.presetPath);
    *state = std::move(s);
    return true;
}

std::string ResolvePresetRequest(const std::string& request, const std::string& current,
                                 const std::vector<std::string>& presets) {
    if (presets.empty()) return "";
    size_t at = 0;
    for (size_t i = 0; i < presets.size(); ++i)
        if (presets[i] == current) at = i;
    if (request == "next") return presets[(at + 1) % presets.size()];
    if (request == "prev") return presets[(at + presets.size() - 1) % presets.size()];
    if (!request.empty() && std::all_of(request.begin(), request.end(), [](char c) { return c >= '0' && c <= '9'; })) {
        size_t index = 0;
        auto [end, ec] = std::from_chars(request.data(), request.data() + request.size(), index);
        if (ec != std::errc() || end != request.data() + request.size() || index >= presets.size()) return "";
        return presets[index];
    }
    for (const std::string& p : presets)
        if (p == request || p == request + ".json") return p;
    return "";
}

ParamState RebaseParams(const ParamState& old, const std::vector<ParamDecl>& decls) {
    ParamState s = MakeParamState(decls);
    s.clamped = old.clamped;
    s.lastClamp = old.lastClamp;
    for (size_t i = 0; i < decls.size(); ++i) {
        const int j = FindParam(old, decls[i].name);
        if (j < 0) continue;
        s.value[i] = ClampParam(decls[i], old.value[(size_t)j]);
        s.target[i] = ClampParam(decls[i], old.target[(size_t)j]);
        if (old.decls[(size_t)j].type == decls[i].type) s.smoothingTau[i] = old.smoothingTau[(size_t)j];
    }
    return s;
}

void ApplyControl(LiveState& state, const std::vector<ControlEvent>& events, double now) {
    state.actions.Clear();
    FeedAutomation(state.automation, events);
    for (const ControlEvent& e : events) ApplyEvent(state.mapping, state.mappingState, e, state.params, &state.actions);
    // Bad-input reports: at most one line a second, so a flood cannot stall the frame.
    state.report.Limited(now, state.actions.messages);
}

bool ApplyPresetFile(LiveState& state, const std::string& file, bool reload, double now, double morphBeats) {
    ShowOptions so = state.options;
    so.scene.clear();
    so.params.clear();
    so.preset = file;
    so.onStage = &state.show;
    Show next;
    std::string err;
    Automation scripts;
    const AutomationDesc& desc = next.preset.automation;
    if (!PrepareShow(so, &next, &err) || (!desc.Empty() && !scripts.Load(desc, ShowDecls(next), &err))) {
        state.report.Say(err + (reload ? " — keeping the current values" : " — keeping the current preset"));
        return false;
    }
    for (const std::string& n : next.notices) state.report.Say(n);
    next.path = state.show.path;
    const bool sceneChange = next.scene.path != state.show.scene.path;
    state.show = std::move(next);
    state.presetFile = state.show.preset.path;
    state.presetPath = Canonical(state.presetFile);
    state.currentPreset = fs::path(state.presetFile).filename().string();
    WatchFolderOf(state, state.presetPath);
    state.wanted = VariantKey{state.show.scene.path, state.show.effects, state.show.path};
    // Scripts, tempo and cue list start over with the preset.
    ShowAutomation& a = state.automation;
    a.automation = std::move(scripts);
    if (state.show.preset.automation.bpm > 0) a.tempo.SetBpm(now, state.show.preset.automation.bpm);
    a.automation.Start(a.tempo.Beats(now));
    a.morph = ParamMorph{};
    MorphDesc how = state.show.preset.automation.morph;
    if (morphBeats >= 0) how.seconds = morphBeats * 60.0 / a.tempo.bpm;
    state.pendingTargets.clear();
    if (!sceneChange && how.seconds > 0) {
        StartMorph(a.morph, state.params, state.show.params, now, how);   // same scene: every value morphs
    } else {
        for (const auto& [name, value] : state.show.params) state.pendingTargets[name] = value;
        state.pendingScenePath = state.show.scene.path;
        state.pendingCut = sceneChange;
    }
    state.sendFeedback = true;
    const std::string line = std::string(reload ? "reloaded " : "preset ") +
                             (reload ? state.presetFile : state.currentPreset) + " (" + state.show.scene.name + ")";
    if (reload) state.report.Say(line);
    else state.report.Limited(now, {line}, "preset");   // pads and OSC can switch faster than anyone reads
    return true;
}

void ApplyActions(LiveState& state, double now) {
    const MappingActions& a = state.actions;
    if (a.tapTempo) {
        state.automation.tap.Tap(now);
        // A detected beat (an audio mapping on tap_tempo) brings its own tempo.
        state.automation.tempo.TapOnBeat(now, a.detectedBpm > 0 ? a.detectedBpm : state.automation.tap.bpm);
    }
    // Preset pads and /sdfvj/preset: values glide there through smoothing; a new scene or effect
    // set compiles while the current one keeps rendering.
    for (const std::string& request : a.presetSelect) {
        const std::string name = ResolvePresetRequest(request, state.currentPreset, ListPresets());
        if (name.empty()) {   // a flood of these (a tablet gone wrong) prints one line a second
            state.report.Limited(now, {"sdfvj live: preset '" + request.substr(0, 64) +
                                       "': no such preset, expected a name, an index or next/prev (see `sdfvj list`)"},
                                 "no preset");
            continue;
        }
        ApplyPresetFile(state, (fs::path(DataRoot()) / "presets" / name).string(), false, now);
    }
    // Effect pads, /sdfvj/effect/<name> and a leader's /sdfvj/effects: a new variant compiles
    // while the old one renders. A change is said (the effect set asked for).
    const EffectSet before = state.wanted.effects;
    for (const auto& [name, on] : a.effectToggles) {
        std::string err;
        EffectSet e = state.wanted.effects;
        if (!ParseEffectList((on ? "" : "-") + name, &e, &err)) {
            state.report.Limited(now, {"sdfvj live: " + err}, "effect");
            continue;
        }
        state.wanted.effects = e;
        state.show.effects = e;
    }
    if (state.wanted.effects != before)
        state.report.Limited(now, {"sdfvj live: effects " + DescribeEffects(state.wanted.effects)}, "effects");
}

void ApplyFileChanges(LiveState& state, const std::vector<std::string>& changedFiles, double now) {
    bool presetSaved = false, mappingSaved = false;
    for (const std::string& f : changedFiles) {
        const std::string path = Canonical(f);
        presetSaved |= !state.presetPath.empty() && path == state.presetPath;
        mappingSaved |= path == state.mappingPath;
    }
    // The preset on stage was edited: apply it again (a broken save is reported, values stay).
    if (presetSaved) ApplyPresetFile(state, state.presetFile, true, now);
    if (mappingSaved) {
        Mapping next;
        LoadResult r = LoadMapping(state.mappingFile, &next);
        if (!r.ok) {
            state.report.Say(r.error + " — keeping the previous mapping");
            return;
        }
        std::string problems;
        if (!ValidateMapping(next, state.params.decls, &problems))
            state.report.Say(problems + " (entries for other scenes are ignored)");
        state.mapping = std::move(next);
        state.mappingState = MappingState{};
        state.report.Say("reloaded " + state.mappingFile);
    }
}

void FollowScene(LiveState& state, const SceneInfo& onScreen) {
    // The header on screen changed (a saved scene added, renamed or re-ranged an input, or a new
    // scene finished compiling): rebuild the parameters by name, once.
    if (!SameDecls(state.params.decls, onScreen.params)) state.params = RebaseParams(state.params, onScreen.params);
    if (onScreen.path == state.show.scene.path) state.show.scene.params = onScreen.params;
    // A preset's values wait until its scene is on screen; a scene change is a cut, so they jump.
    if (!state.pendingTargets.empty() && onScreen.path == state.pendingScenePath) {
        for (const auto& [name, value] : state.pendingTargets) {
            const int i = FindParam(state.params, name);
            if (i < 0) continue;
            SetParamTarget(state.params, i, value);
            if (state.pendingCut) state.params.value[(size_t)i] = state.params.target[(size_t)i];
        }
        state.pendingTargets.clear();
    }
}

void RunAutomation(LiveState& state, double now, int frame) {
    std::vector<std::string> reports;
    // knob1..16 only matter to expressions: no vector is built per frame for a preset without any.
    const bool scripted = !state.automation.automation.Desc().expressions.empty();
    const std::vector<float> knobs = scripted ? KnobPositions(state.mapping, state.mappingState) : std::vector<float>{};
    for (const CueDesc& cue : StepAutomation(state.automation, state.params, knobs, now, frame, &reports)) {
        const std::string name = ResolvePresetRequest(cue.preset, state.currentPreset, ListPresets());
        if (name.empty()) {
            reports.push_back(state.show.preset.automation.file + ":" + std::to_string(cue.line) + ": cue preset '" +
                              cue.preset + "' does not exist, expected a preset name (see `sdfvj list`)");
            continue;
        }
        ApplyPresetFile(state, (fs::path(DataRoot()) / "presets" / name).string(), false, now, cue.overBeats);
    }
    for (const std::string& r : reports) state.report.Say(r);
}

float BeatPhase(const LiveState& state, double now) {
    const double beats = state.automation.tempo.Beats(now);
    return (float)(beats - std::floor(beats));
}

}  // namespace sdfvj
