// The show's state in `sdfvj live` and the stages one frame runs over it.
//
// cmd_live.cpp owns the window, GL, devices and the watcher; everything a performer changes
// lives here, in one plain struct, and each stage of the frame is a free function over it:
//
//   ApplyControl(state, events, now)        MIDI/OSC events -> mapping -> parameter targets, actions
//   ApplyActions(state, now)                tap tempo, preset selects, effect toggles
//   ApplyFileChanges(state, changedFiles)   the mapping or the preset on stage was saved
//   FollowScene(state, sceneOnScreen)       parameters follow the header of the program on screen
//   RunAutomation(state, now, frame)        scripted presets: cues, expressions, morphs (automation.h)
//   StepSmoothing(state.params, dt)         (control.h)
//
// None of them touches GL or a device, so each is tested on its own (tests/live/live_state_test).
// What they ask of the outside world (a program variant, folders to watch, OSC feedback) is left
// in the state for the frame to act on. Nothing here throws on bad input: a broken file or an
// unknown preset is a line in `state.report` and the last good state stays.
#pragma once
#include <cstdint>
#include <deque>
#include <map>
#include <string>
#include <vector>

#include "app/show.h"
#include "automation/automation.h"
#include "control/control.h"

namespace sdfvj {

// Lines for the performer: printed on stderr and kept for the overlay. Lines that a flood of bad
// input can cause go through Limited(): at most one a second, with a count of the rest.
struct LiveReport {
    std::deque<std::string> recent;     // newest last, at most 8
    bool print = true;                  // also write to stderr
    struct Throttle { double last = -1e9; uint64_t suppressed = 0; };
    std::map<std::string, Throttle> throttles;   // one per kind of line ("input", "preset", ...)
    void Say(const std::string& line);
    void Limited(double now, const std::vector<std::string>& lines, const std::string& kind = "input");
};

// Printable text for the terminal and the overlay: control bytes and broken UTF-8 become '?'.
std::string PrintableLine(const std::string& text);

struct LiveState {
    ShowOptions options;                // the command line's show options (presets start from them)
    Show show;                          // the scene, preset and effects asked for
    VariantKey wanted;                  // the program the frame should show (LiveProgram::Request)
    ParamState params;                  // the parameters of the scene on screen
    std::map<std::string, float> pendingTargets;   // a preset's values for a scene still compiling
    std::string pendingScenePath;
    bool pendingCut = false;            // the preset changes the scene: its values jump, not glide

    Mapping mapping;
    MappingState mappingState;
    std::string mappingFile, mappingPath;   // as given, canonical

    std::string presetFile, presetPath;     // the preset on stage ("" = none), as given and canonical
    std::string currentPreset;              // its file name, for next/prev
    std::vector<std::string> presetReloads; // the preset on stage was saved: apply it again

    MappingActions actions;             // what this frame's events asked for
    ShowAutomation automation;          // the preset's scripts, the tempo (tap, clock) and morphs
    LiveReport report;

    // Requests for the frame (it clears them once acted on).
    std::vector<std::string> foldersToWatch;
    bool sendFeedback = false;          // a preset was applied: echo values to --osc-feedback
};

// Resolves the show, its mapping and starting values. False with one line on bad usage.
bool OpenLiveState(const ShowOptions& options, const std::string& mappingOption, LiveState* state, std::string* error);

// A preset request from a pad or OSC: a name, a file name, an index into `presets` (decimal,
// any length: out of range is "no such preset", never an exception), next or prev.
// Returns the file name from `presets`, or "" when nothing matches.
std::string ResolvePresetRequest(const std::string& request, const std::string& current,
                                 const std::vector<std::string>& presets);

// A parameter state for new declarations that keeps, by name, the values and targets of `old`
// (clamped to the new ranges); new names start at their defaults, removed ones are dropped.
ParamState RebaseParams(const ParamState& old, const std::vector<ParamDecl>& decls);

void ApplyControl(LiveState& state, const std::vector<ControlEvent>& events, double now);
void ApplyActions(LiveState& state, double now);
void ApplyFileChanges(LiveState& state, const std::vector<std::string>& changedFiles, double now);
void FollowScene(LiveState& state, const SceneInfo& onScreen);
void RunAutomation(LiveState& state, double now, int frame);
// u_beat: the phase 0..1 within the current beat.
float BeatPhase(const LiveState& state, double now);

// Applies a preset file (a reload of the one on stage when `reload`): values morph there over the
// preset's morph time (or glide through smoothing), its scripts start, a new scene or effect set
// becomes `wanted`. A preset that does not load or whose expressions or cues are broken is
// reported with file:line; nothing changes. `morphBeats` >= 0 overrides the preset's morph time
// (a cue's "over").
bool ApplyPresetFile(LiveState& state, const std::string& file, bool reload, double now, double morphBeats = -1.0);

}  // namespace sdfvj
