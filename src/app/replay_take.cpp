// Replay for the full build: take -> ReplayCursor -> mapping -> smoothing, on the fixed clock.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "app/live_support.h"
#include "app/replay_driver.h"
#include "audio/wav.h"
#include "control/control.h"
#include "automation/automation.h"
#include "take/take.h"

namespace fs = std::filesystem;

namespace sdfvj {

// The mapping a show uses: --mapping, else the preset's, else the generic 8-knob profile.
std::string ResolveMappingPath(const Show& show, const std::string& option) {
    std::string p = !option.empty() ? option : !show.preset.mapping.empty() ? show.preset.mapping : "mappings/generic_8knob.toml";
    if (!fs::exists(p) && fs::exists(fs::path(DataRoot()) / p)) p = (fs::path(DataRoot()) / p).string();
    return p;
}

// Loads and validates a mapping for a show; errors are "file:line:col: ..." lines.
bool LoadShowMapping(const Show& show, const std::string& option, Mapping* mapping, std::string* error) {
    const std::string path = ResolveMappingPath(show, option);
    LoadResult r = LoadMapping(path, mapping);
    if (!r.ok) {
        *error = r.error;
        return false;
    }
    std::string problems;
    if (!ValidateMapping(*mapping, ShowDecls(show), &problems))   // post and ISF scene inputs too
        std::fprintf(stderr, "%s (entries for other scenes are ignored)\n", problems.c_str());
    return true;
}

// Starting values of a show as a ParamState: scene defaults overridden by preset and --param.
ParamState ShowParamState(const Show& show) {
    ParamState s = MakeParamState(ShowDecls(show));   // the scene's inputs, then the post chain's
    for (const auto& [name, value] : show.params) {
        int i = FindParam(s, name);
        if (i >= 0) s.value[i] = s.target[i] = value;
    }
    return s;
}

void CopyParams(const ParamState& s, std::vector<std::pair<std::string, float>>* out) {
    out->clear();
    for (size_t i = 0; i < s.decls.size(); ++i) out->emplace_back(s.decls[i].name, s.value[i]);
}

namespace {

// Take (if any) -> mapping -> automation -> smoothing, on the fixed clock: the same stages as
// `live`, so a replayed take with a scripted preset renders the same bytes every time.
class TakeReplayDriver : public ReplayDriver {
public:
    Take take;
    Mapping mapping;
    MappingState state;
    ParamState params;
    std::unique_ptr<ReplayCursor> cursor;
    ShowAutomation automation;
    std::string presetFile;
    ShowOptions options;            // the command line's: presets a cue switches to start from them
    std::string scenePath;          // the scene on screen
    ShowSwitch pending;
    int frame = 0;
    std::unique_ptr<AudioReplay> audio;   // TAKE.wav, when the show recorded its audio

    double Duration() const override { return take.duration; }
    void Advance(double time, double dt, std::vector<std::pair<std::string, float>>* out) override {
        // An event is applied to the first frame that starts at or after it.
        std::vector<ControlEvent> events;
        if (cursor) events = cursor->Until(time + 1e-9);
        FeedAutomation(automation, events);
        MappingActions actions;
        for (const ControlEvent& e : events) {
            ApplyEvent(mapping, state, e, params, &actions);
            if (actions.tapTempo) {
                automation.tap.Tap(e.time);
                automation.tempo.TapOnBeat(e.time, actions.detectedBpm > 0 ? actions.detectedBpm : automation.tap.bpm);
                actions.tapTempo = false;
                actions.detectedBpm = 0;
            }
        }
        std::vector<std::string> reports;
        for (const CueDesc& cue : StepAutomation(automation, params, KnobPositions(mapping, state), time, frame++, &reports))
            SwitchPreset(cue, time, &reports);
        for (const std::string& r : reports) std::fprintf(stderr, "%s\n", r.c_str());
        StepSmoothing(params, dt);
        CopyParams(params, out);
    }
    float BeatPhase(double time) const override {
        const double b = automation.tempo.Beats(time);
        return (float)(b - std::floor(b));
    }
    float Bpm() const override { return (float)automation.tempo.bpm; }
    ShowSwitch TakeShowSwitch() override { return std::move(pending); }
    bool AudioAt(double time, std::span<const float>* wave, std::span<const float>* spectrum) override {
        if (!audio) return false;
        const AudioSpectrum& s = audio->At(time);
        *wave = s.waveform;
        *spectrum = s.spectrum;
        return true;
    }

    // A cue that switches presets, as `live` applies it (ApplyPresetFile): the preset starts from
    // the command line's options, its scripts and cue list start over at this beat, the values
    // morph over the cue's `over` beats on the same scene (else glide), and jump on a new scene.
    // A preset that does not load is reported with its line and the show stays as it is.
    void SwitchPreset(const CueDesc& cue, double time, std::vector<std::string>* reports) {
        const std::string cueAt = presetFile + ":" + std::to_string(cue.line) + ": cue preset '" + cue.preset + "'";
        const std::string file = PresetFileFor(cue.preset);
        if (file.empty()) {
            reports->push_back(cueAt + " does not exist, expected a preset name (see `sdfvj list`)");
            return;
        }
        ShowOptions so = options;
        so.scene.clear();
        so.params.clear();
        so.preset = file;
        auto next = std::make_unique<Show>();
        std::string error;
        Automation scripts;
        const AutomationDesc& desc = next->preset.automation;
        if (!PrepareShow(so, next.get(), &error) || (!desc.Empty() && !scripts.Load(desc, ShowDecls(*next), &error))) {
            reports->push_back(error + " — " + cueAt + " is not followed, the show stays as it is");
            return;
        }
        const bool sceneChange = next->scene.path != scenePath;
        automation.automation = std::move(scripts);
        if (desc.bpm > 0) automation.tempo.SetBpm(time, desc.bpm);
        automation.automation.Start(automation.tempo.Beats(time));
        automation.morph = ParamMorph{};
        MorphDesc how = desc.morph;
        if (cue.overBeats >= 0) how.seconds = cue.overBeats * 60.0 / automation.tempo.bpm;
        if (sceneChange) {
            params = ShowParamState(*next);   // a new scene is a cut: its values jump
        } else if (how.seconds > 0) {
            StartMorph(automation.morph, params, next->params, time, how);
        } else {
            for (const auto& [name, value] : next->params) {
                const int i = FindParam(params, name);
                if (i >= 0) SetParamTarget(params, i, value);
            }
        }
        reports->push_back("cue at " + FormatSeconds(time) + ": preset " + fs::path(file).filename().string() + " (" +
                           next->scene.name + ")");
        presetFile = next->preset.path;
        scenePath = next->scene.path;
        const MorphDesc fade = desc.morph;
        pending.fadeSeconds = sceneChange && fade.easing != Easing::Cut ? fade.seconds : 0.0;
        pending.weight = [fade](double since) { return Ease(fade.easing, fade.seconds > 0 ? since / fade.seconds : 1.0); };
        pending.show = std::move(next);
    }

    // presets/NAME.json for a cue's "NAME" (or "NAME.json"), "" when there is none.
    static std::string PresetFileFor(const std::string& name) {
        for (const std::string& p : ListPresets())
            if (p == name || p == name + ".json") return (fs::path(DataRoot()) / "presets" / p).string();
        return "";
    }
    static std::string FormatSeconds(double t) {
        char text[32];
        std::snprintf(text, sizeof text, "%.3f s", t);
        return text;
    }
};

}  // namespace

std::unique_ptr<ReplayDriver> MakeReplayDriver(const Show& show, const std::string& takePath,
                                               const std::string& mappingPath, std::string* error,
                                               const ShowOptions* options) {
    auto d = std::make_unique<TakeReplayDriver>();
    if (options) d->options = *options;
    d->scenePath = show.scene.path;
    if (!takePath.empty()) {
        std::string path = takePath;
        if (!fs::exists(path) && fs::exists(fs::path(DataRoot()) / path)) path = (fs::path(DataRoot()) / path).string();
        TakeReadResult r = ReadTake(path, &d->take);
        if (!r.ok) {
            *error = r.error;
            return nullptr;
        }
        for (const std::string& w : d->take.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
        d->cursor = std::make_unique<ReplayCursor>(d->take);
        // The audio `live --record --audio` wrote beside the take; a damaged one is one line and
        // the replay goes on without audio (ISF audio inputs read silence, as without a WAV).
        const std::string wavPath = TakeWavPath(path);
        std::error_code ec;
        if (fs::exists(wavPath, ec)) {
            WavAudio wav;
            std::string why;
            if (ReadWav(wavPath, &wav, &why)) {
                d->audio = std::make_unique<AudioReplay>(std::move(wav));
                std::vector<std::pair<double, int64_t>> anchors;   // where each frame of the show was in the WAV
                AudioFeatures f;
                for (const ControlEvent& e : d->take.events)
                    if (ReadAudioFeatureEvent(e, &f) && f.wavSample >= 0) anchors.emplace_back(e.time, f.wavSample);
                d->audio->SetAnchors(std::move(anchors));
            } else std::fprintf(stderr, "sdfvj render: %s — rendering without the take's audio\n", why.c_str());
        }
    }
    if (!LoadShowMapping(show, mappingPath, &d->mapping, error)) return nullptr;
    d->params = ShowParamState(show);
    const AutomationDesc& scripts = show.preset.automation;
    if (!scripts.Empty() && !d->automation.automation.Load(scripts, ShowDecls(show), error)) return nullptr;
    if (scripts.bpm > 0) d->automation.tempo.SetBpm(0.0, scripts.bpm);
    d->automation.automation.Start(0.0);
    d->presetFile = show.preset.path;
    return d;
}

}  // namespace sdfvj
