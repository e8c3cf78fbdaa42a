// live_overlay: the performer's overlay in `sdfvj live`. Plain data in, what the performer did out.
//
// Usage, per frame (render thread, between ImGui::NewFrame and ImGui::Render):
//   ObserveEvents(ui, drainedEvents);               // the MIDI/OSC monitor and an armed learn
//   ui.frames.Add(frameMs);
//   OverlayModel m = ...;                            // what the show is doing, copied out of it
//   OverlayActions a = DrawOverlay(m, ui);           // one ImGui window
//   ... the session applies `a`: parameter targets, preset load/save, effect toggles, learn ...
//
// Nothing here reaches into the session: the overlay never writes the show's state itself, so
// what a click does is the same code path as a pad or an OSC message, applied by the session.
// The file helpers (SavePresetAs, AppendLearnedMapping) write atomically (temp file + rename) so
// the watcher of a running show sees the old file or the new one, never half of one.
#pragma once
#include <cstddef>
#include <deque>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "control/control.h"
#include "scene/scene.h"

namespace sdfvj {

// ---------------------------------------------------------------------------------------------
// Monitor, frame times, learn: the overlay's own memory between frames
// ---------------------------------------------------------------------------------------------

// The last few control events the frames drained, newest last.
struct EventMonitor {
    std::deque<ControlEvent> recent;
    size_t capacity = 12;
    void Add(const std::vector<ControlEvent>& events);
};
// One line for the monitor: "  1.234  MIDI  B0 02 7F  CC 2 ch1" or "  1.234  OSC   /x 0.5".
std::string DescribeEvent(const ControlEvent& e);

// The last frame times in ms, oldest first: the CPU's (wall time from one frame to the next) and
// the GPU's (GL timer queries of the scene draw, read a few frames late, never waited for).
struct FrameTimeGraph {
    std::vector<float> ms;
    size_t capacity = 120;
    void Add(float frameMs);
    float Average() const;
    float Max() const;
};

// MIDI learn inside the show: armed on one parameter, it takes the next control that moves.
struct LearnArm {
    std::string param;                      // "" = not armed
    std::string source;                     // the TOML source lines of the control, once found
    LearnState state;                       // what `LearnSource` has seen so far (control.h)
    bool Armed() const { return !param.empty(); }
};
// Arms (or re-arms) learn on `param`; an empty name disarms.
void ArmLearn(LearnArm& learn, const std::string& param);
// Feeds one event; returns the TOML source lines ("cc = 2\nchannel = 1") once a control moved,
// else "". The same rules as `sdfvj learn`: a CC moves when it sends a second, different value;
// a note-on becomes a toggle pad; NRPN waits for its number; /sdfvj/ addresses are not learned.
std::string LearnFromEvent(LearnArm& learn, const ControlEvent& e);

// Widget state ImGui needs across frames, and the monitor, graph and learn above.
struct OverlayUi {
    EventMonitor monitor;
    FrameTimeGraph frames;                  // CPU ms per frame
    FrameTimeGraph gpu;                     // GPU ms per frame (GpuTimerRing), empty on llvmpipe
    LearnArm learn;
    char saveAsName[64] = {};
    // Tests read what the overlay shows: with logText, `text` holds every label, value and caption
    // the last DrawOverlay wrote (ImGui's log, one line per row of widgets).
    bool logText = false;
    std::string text;
};
// The frame's drained events: into the monitor, and into learn when it is armed.
void ObserveEvents(OverlayUi& ui, const std::vector<ControlEvent>& events);

// ---------------------------------------------------------------------------------------------
// What the overlay shows and what it returns
// ---------------------------------------------------------------------------------------------

// "CC 2 ch1", "CC 7/39 ch any" (14-bit), "note 36 ch10", "OSC /x", "pitch bend ch1", "program any".
std::string ControlLabel(const MappingEntry& e);
// The controls mapped to parameter `index` of `params` (by name or by position, target = N),
// joined with ", "; "" when none.
std::string ControlsFor(const Mapping& m, const ParamState& params, int index);

struct OverlayParam {
    std::string name, label;
    float minValue = 0.0f, maxValue = 1.0f;
    float value = 0.0f;             // what the frame renders
    float target = 0.0f;            // where it glides (what the slider edits)
    std::string controls;           // ControlsFor(mapping, name)
    std::string expression;         // "" unless scripted: then the slider is read-only and shows `value`
};

struct OverlayModel {
    std::string scene, effectsText, pathName;   // title line
    float fps = 0.0f;
    int width = 0, height = 0;                  // framebuffer
    float renderScale = 1.0f;                   // the scene renders at this fraction of the window
    std::vector<OverlayParam> params;
    std::vector<std::string> presets;           // ListPresets(): file names, index = number key - 1
    std::string currentPreset;                  // file name of the preset on stage, "" = none
    EffectSet effects;                          // the effects asked for (checkbox state)
    std::vector<std::string> statusLines;       // devices
    std::vector<std::string> reportLines;       // the session's recent lines, newest last
    std::string shaderError;                    // "shaders/scenes/midi.glsl:42: ..." or ""
    std::string compiling;                      // effects of a variant still compiling, "" = none
    bool hasProgram = true;
    bool recording = false;
    size_t recorded = 0;
    std::string mappingFile;                    // where learn writes, "" = learn unavailable
    std::string gpuTimesUnavailable;            // why there is no GPU graph ("software renderer"), "" = shown
    // Effect costs (effect_costs.h): checkbox name -> "+3.21 ms", "n/a", "..."; only measured ones.
    std::vector<std::pair<std::string, std::string>> effectCosts;
    std::string effectCostNote;                 // what the costs are ("median of 9 frame pairs, ...")
};

struct OverlayActions {
    std::vector<std::pair<int, float>> setTargets;            // parameter index, new target
    std::string loadPreset;                                   // a file name from presets
    std::string savePreset;                                   // a name to save under (save or save-as)
    std::vector<std::pair<std::string, bool>> effectToggles;  // as /sdfvj/effect/<name> i
    float renderScale = 0.0f;                                 // > 0: render the scene at this fraction
    bool measureCosts = false;                                // "measure costs": time each effect of the program
    bool Empty() const {
        return setTargets.empty() && loadPreset.empty() && savePreset.empty() && effectToggles.empty() &&
               renderScale <= 0.0f && !measureCosts;
    }
};

// Draws the overlay window; returns what the performer did this frame. Learn buttons arm and
// cancel ui.learn directly (it is the overlay's own state).
OverlayActions DrawOverlay(const OverlayModel& m, OverlayUi& ui);

// "1".."9" pressed this frame -> the preset file name it picks (index in `presets`), or "".
std::string PresetForNumberKey(int number, const std::vector<std::string>& presets);

// ---------------------------------------------------------------------------------------------
// Files
// ---------------------------------------------------------------------------------------------

// A name that can be presets/NAME.json: letters, digits, '_', '-', '.', at most 64 chars, not
// starting with '.'. A trailing ".json" is allowed and dropped. False with one line otherwise.
bool PresetFileName(const std::string& name, std::string* fileName, std::string* error);

// What a saved preset holds: the values the show renders now, the expressions of a scripted
// preset, and the effects asked for. The keys of `basePreset` (the preset on stage: mapping,
// take, bpm, morph, envelopes, cues, loop_bars) are kept.
struct PresetSnapshot {
    std::string scene;                                   // scene name
    std::vector<std::pair<std::string, float>> values;   // by parameter name
    std::map<std::string, std::string> expressions;      // scripted parameters: name -> text
    EffectSet effects;
    std::string basePreset;                              // path of the preset on stage, "" = none
};
// Writes folder/NAME.json atomically and reads it back with LoadPreset (a snapshot that does not
// read back is not written). Returns the path written, or "" with one line in *error.
std::string SavePresetAs(const std::string& folder, const std::string& name, const PresetSnapshot& s,
                         std::string* error);

// Appends a [[map]] entry for `source` -> `param` to the mapping file, all or nothing: the new
// text must parse (ParseMapping), have one more entry and validate against `decls`
// (ValidateMapping); then it replaces the file atomically. Returns "" or one error line.
std::string AppendLearnedMapping(const std::string& mappingPath, const std::string& param, const std::string& source,
                                 const std::vector<ParamDecl>& decls);
// The learn stage of a frame: once the armed learn found its control, appends it to the mapping
// file (AppendLearnedMapping; the watcher then reloads it) and disarms. Returns the line for the
// performer ("learned: cc = 2 -> twist, written to m.toml" or the error), "" while still waiting.
std::string FinishLearn(LearnArm& learn, const std::string& mappingPath, const std::vector<ParamDecl>& decls);

}  // namespace sdfvj
