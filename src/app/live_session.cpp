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

void TapTempo::Tap(double now) {
    if (!taps.empty() && now - taps.back() > 2.0) taps.clear();   // a pause starts a new count
    taps.push_back(now);
    if (taps.size() > 5) taps.erase(taps.begin());
    if (taps.size() >= 2) {
        std::vector<double> gaps;
        for (size_t i = 1; i < taps.size(); ++i) gaps.push_back(taps[i] - taps[i - 1]);
        std::sort(gaps.begin(), gaps.end());
        double gap = gaps[gaps.size() / 2];
        if (gap > 0.2 && gap < 2.0) bpm = 60.0 / gap;
    }
    origin = now;
}

float TapTempo::Phase(double now) const {
    double beats = (now - origin) * bpm / 60.0;
    return (float)(beats - std::floor(beats));
}

void LiveReport::Say(const std::string& line) {
    if (print) std::fprintf(stderr, "%s\n", line.c_str());
    recent.push_back(line);
    while (recent.size() > 8) recent.pop_front();
}

void LiveReport::Limited(double now, const std::vector<std::string>& lines) {
    if (lines.empty()) return;
    if (now - lastLimited < 1.0) {
        suppressed += lines.size();
        return;
    }
    std::string line = lines.back();
    if (suppressed + lines.size() > 1)
        line += " (and " + std::to_string(suppressed + lines.size() - 1) + " more in the last second)";
    Say(line);
    lastLimited = now;
    suppressed = 0;
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
    for (const ControlEvent& e : events) ApplyEvent(state.mapping, state.mappingState, e, state.params, &state.actions);
    // Bad-input reports: at most one line a second, so a flood cannot stall the frame.
    state.report.Limited(now, state.actions.messages);
}

bool ApplyPresetFile(LiveState& state, const std::string& file, bool reload) {
    ShowOptions so = state.options;
    so.scene.clear();
    so.params.clear();
    so.preset = file;
    Show next;
    std::string err;
    if (!PrepareShow(so, &next, &err)) {
        state.report.Say(err + (reload ? " — keeping the current values" : " — keeping the current preset"));
        return false;
    }
    next.path = state.show.path;
    const bool sceneChange = next.scene.path != state.show.scene.path;
    state.show = std::move(next);
    state.presetFile = state.show.preset.path;
    state.presetPath = Canonical(state.presetFile);
    state.currentPreset = fs::path(state.presetFile).filename().string();
    WatchFolderOf(state, state.presetPath);
    state.wanted = VariantKey{state.show.scene.path, state.show.effects, state.show.path};
    state.pendingTargets.clear();
    for (const auto& [name, value] : state.show.params) state.pendingTargets[name] = value;
    state.pendingScenePath = state.show.scene.path;
    state.pendingCut = sceneChange;
    state.sendFeedback = true;
    state.report.Say(std::string(reload ? "reloaded " : "preset ") + (reload ? state.presetFile : state.currentPreset) +
                     " (" + state.show.scene.name + ")");
    return true;
}

void ApplyActions(LiveState& state, double now) {
    const MappingActions& a = state.actions;
    if (a.tapTempo) state.tempo.Tap(now);
    // Preset pads and /sdfvj/preset: values glide there through smoothing; a new scene or effect
    // set compiles while the current one keeps rendering.
    for (const std::string& request : a.presetSelect) {
        const std::string name = ResolvePresetRequest(request, state.currentPreset, ListPresets());
        if (name.empty()) {
            state.report.Say("sdfvj live: preset '" + request.substr(0, 64) +
                             "': no such preset, expected a name, an index or next/prev (see `sdfvj list`)");
            continue;
        }
        ApplyPresetFile(state, (fs::path(DataRoot()) / "presets" / name).string(), false);
    }
    // Effect pads and /sdfvj/effect/<name>: a new variant compiles while the old one renders.
    for (const auto& [name, on] : a.effectToggles) {
        std::string err;
        EffectSet e = state.wanted.effects;
        if (!ParseEffectList((on ? "" : "-") + name, &e, &err)) {
            state.report.Say("sdfvj live: " + err);
            continue;
        }
        state.wanted.effects = e;
        state.show.effects = e;
    }
}

void ApplyFileChanges(LiveState& state, const std::vector<std::string>& changedFiles) {
    bool presetSaved = false, mappingSaved = false;
    for (const std::string& f : changedFiles) {
        const std::string path = Canonical(f);
        presetSaved |= !state.presetPath.empty() && path == state.presetPath;
        mappingSaved |= path == state.mappingPath;
    }
    // The preset on stage was edited: apply it again (a broken save is reported, values stay).
    if (presetSaved) ApplyPresetFile(state, state.presetFile, true);
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

}  // namespace sdfvj
