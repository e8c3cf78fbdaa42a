// The performer's overlay (see live_overlay.h). Three parts: the overlay's own memory (monitor,
// frame graph, learn), the ImGui window, and the two files it writes (presets, learned mappings).
#include "app/live_overlay.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <sstream>

#include <imgui.h>
#include <imgui_internal.h>   // GImGui->LogBuffer for OverlayUi::logText
#include <nlohmann/json.hpp>

namespace sdfvj {

namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------------
// Monitor, frame times, learn
// ---------------------------------------------------------------------------------------------

void EventMonitor::Add(const std::vector<ControlEvent>& events) {
    // A flood drains thousands a frame: only the newest `capacity` can ever be shown.
    const size_t skip = events.size() > capacity ? events.size() - capacity : 0;
    for (size_t i = skip; i < events.size(); ++i) recent.push_back(events[i]);
    while (recent.size() > capacity) recent.pop_front();
}

std::string DescribeEvent(const ControlEvent& e) {
    char head[32];
    std::snprintf(head, sizeof head, "%8.3f  ", e.time);
    std::string s = head;
    if (e.source == EventSource::Osc) {
        s += "OSC   " + e.address.substr(0, 48);
        for (size_t i = 0; i < e.args.size() && i < 4; ++i) {
            const OscArg& a = e.args[i];
            char v[48];
            if (a.type == 'f') std::snprintf(v, sizeof v, " %g", a.f);
            else if (a.type == 'i') std::snprintf(v, sizeof v, " %d", a.i);
            else if (a.type == 's') std::snprintf(v, sizeof v, " \"%.24s\"", a.s.c_str());
            else std::snprintf(v, sizeof v, " <%c>", a.type);
            s += v;
        }
        return s;
    }
    s += "MIDI ";
    for (int i = 0; i < 3; ++i) {
        char b[8];
        if (i < e.midiSize) std::snprintf(b, sizeof b, " %02X", e.midi[i]);
        else std::snprintf(b, sizeof b, "   ");
        s += b;
    }
    const int type = e.midi[0] & 0xF0, ch = (e.midi[0] & 0x0F) + 1;
    char what[48] = "";
    if (type == 0xB0) std::snprintf(what, sizeof what, "  CC %d ch%d = %d", e.midi[1], ch, e.midi[2]);
    else if (type == 0x90 && e.midi[2] > 0) std::snprintf(what, sizeof what, "  note %d ch%d on %d", e.midi[1], ch, e.midi[2]);
    else if (type == 0x80 || type == 0x90) std::snprintf(what, sizeof what, "  note %d ch%d off", e.midi[1], ch);
    else if (type == 0xE0) std::snprintf(what, sizeof what, "  pitch bend ch%d", ch);
    else if (type == 0xC0) std::snprintf(what, sizeof what, "  program %d ch%d", e.midi[1], ch);
    return s + what;
}

void FrameTimeGraph::Add(float frameMs) {
    ms.push_back(frameMs);
    if (ms.size() > capacity) ms.erase(ms.begin(), ms.begin() + (ptrdiff_t)(ms.size() - capacity));
}

float FrameTimeGraph::Average() const {
    return ms.empty() ? 0.0f : std::accumulate(ms.begin(), ms.end(), 0.0f) / (float)ms.size();
}

float FrameTimeGraph::Max() const { return ms.empty() ? 0.0f : *std::max_element(ms.begin(), ms.end()); }

void ArmLearn(LearnArm& learn, const std::string& param) {
    learn = LearnArm{};
    learn.param = param;
}

std::string LearnFromEvent(LearnArm& learn, const ControlEvent& e) {
    if (!learn.Armed() || !learn.source.empty()) return "";
    learn.source = LearnSource(e, learn.state);   // the rules of `sdfvj learn` (control.h)
    return learn.source;
}

void ObserveEvents(OverlayUi& ui, const std::vector<ControlEvent>& events) {
    ui.monitor.Add(events);
    if (!ui.learn.Armed()) return;
    for (const ControlEvent& e : events)
        if (!LearnFromEvent(ui.learn, e).empty()) break;
}

// ---------------------------------------------------------------------------------------------
// The window
// ---------------------------------------------------------------------------------------------

std::string ControlLabel(const MappingEntry& e) {
    const std::string ch = e.channel > 0 ? " ch" + std::to_string(e.channel) : "";
    switch (e.kind) {
        case SourceKind::Cc:
            return "CC " + std::to_string(e.number) + (e.hiRes ? "/" + std::to_string(e.number + 32) : "") + ch;
        case SourceKind::Note: return "note " + std::to_string(e.number) + ch;
        case SourceKind::PitchBend: return "pitch bend" + ch;
        case SourceKind::Program: return "program " + (e.number < 0 ? std::string("any") : std::to_string(e.number)) + ch;
        case SourceKind::Nrpn: return "NRPN " + std::to_string(e.number) + ch;
        case SourceKind::Osc: return "OSC " + e.oscAddress;
        case SourceKind::Audio: return std::string("audio ") + AudioFeatureName(e.audio);
    }
    return "?";
}

std::string ControlsFor(const Mapping& m, const ParamState& params, int index) {
    std::string s;
    for (const MappingEntry& e : m.entries)
        if (TargetIndex(e, params) == index &&
            (e.action == PadAction::None || e.action == PadAction::Trigger || e.action == PadAction::Toggle))
            s += (s.empty() ? "" : ", ") + ControlLabel(e);
    return s;
}

std::string PresetForNumberKey(int number, const std::vector<std::string>& presets) {
    if (number < 1 || number > 9 || (size_t)number > presets.size()) return "";
    return presets[(size_t)number - 1];
}

namespace {

const ImVec4 kRed(1.0f, 0.4f, 0.4f, 1.0f), kAmber(1.0f, 0.8f, 0.3f, 1.0f), kScript(0.5f, 0.8f, 1.0f, 1.0f);

void DrawParams(const OverlayModel& m, OverlayUi& ui, OverlayActions& a) {
    for (size_t i = 0; i < m.params.size(); ++i) {
        const OverlayParam& p = m.params[i];
        ImGui::PushID((int)i);
        if (!p.expression.empty()) {
            // Scripted: the expression owns the value; the slider only shows it moving.
            float v = p.value;
            ImGui::BeginDisabled();
            ImGui::SliderFloat(p.label.c_str(), &v, p.minValue, p.maxValue);
            ImGui::EndDisabled();
        } else {
            float v = p.target;
            if (ImGui::SliderFloat(p.label.c_str(), &v, p.minValue, p.maxValue)) a.setTargets.emplace_back((int)i, v);
        }
        ImGui::SameLine();
        if (!m.mappingFile.empty()) {
            if (ui.learn.param == p.name) {
                if (ImGui::SmallButton("cancel")) ArmLearn(ui.learn, "");
            } else if (p.expression.empty() && ImGui::SmallButton("learn")) {
                ArmLearn(ui.learn, p.name);
            }
            ImGui::SameLine();
        }
        ImGui::TextDisabled("%s", p.controls.empty() ? "-" : p.controls.c_str());
        if (!p.expression.empty()) ImGui::TextColored(kScript, "  = %s", p.expression.c_str());
        if (ui.learn.param == p.name) ImGui::TextColored(kAmber, "  learn: move a control for %s ...", p.name.c_str());
        ImGui::PopID();
    }
}

void DrawPresets(const OverlayModel& m, OverlayUi& ui, OverlayActions& a) {
    if (!ImGui::CollapsingHeader("presets", ImGuiTreeNodeFlags_DefaultOpen)) return;
    // A short scrolling list: the overlay must leave the scene visible on a small screen.
    const float rows = (float)std::clamp<size_t>(m.presets.size(), 1, 4);
    if (ImGui::BeginListBox("##presets", ImVec2(260, rows * ImGui::GetTextLineHeightWithSpacing() + 4))) {
        for (size_t i = 0; i < m.presets.size(); ++i) {
            const std::string& name = m.presets[i];
            char label[96];
            std::snprintf(label, sizeof label, "%s%.80s", i < 9 ? (std::to_string(i + 1) + "  ").c_str() : "   ", name.c_str());
            const bool onStage = name == m.currentPreset;
            if (ImGui::Selectable(label, onStage)) a.loadPreset = name;
            if (onStage && ImGui::IsWindowAppearing()) ImGui::SetScrollHereY();
        }
        ImGui::EndListBox();
    }
    if (!m.currentPreset.empty()) {
        if (ImGui::Button("save")) a.savePreset = fs::path(m.currentPreset).stem().string();
        ImGui::SameLine();
    }
    ImGui::SetNextItemWidth(140);
    const bool enter = ImGui::InputTextWithHint("##saveas", "new name", ui.saveAsName, sizeof ui.saveAsName,
                                                ImGuiInputTextFlags_EnterReturnsTrue);
    ImGui::SameLine();
    if ((ImGui::Button("save as") || enter) && ui.saveAsName[0] != '\0') a.savePreset = ui.saveAsName;
}

// Effect checkboxes, three to a row, each with its measured cost once "measure costs" ran.
void DrawEffects(const OverlayModel& m, OverlayActions& a) {
    const EffectSet& e = m.effects;
    const std::pair<const char*, bool> boxes[] = {{"shadows", e.shadows != 0}, {"ao", e.ao},   {"specular", e.specular},
                                                  {"fog", e.fog},               {"pbr", e.pbr}, {"reflections", e.reflections != 0},
                                                  {"ssaa", e.supersample != 0}};   // 4 samples a pixel (anti-aliasing)
    for (size_t i = 0; i < std::size(boxes); ++i) {
        bool on = boxes[i].second;
        if (i % 3 != 0) ImGui::SameLine(190.0f * (float)(i % 3) + ImGui::GetStyle().WindowPadding.x);
        if (ImGui::Checkbox(boxes[i].first, &on)) a.effectToggles.emplace_back(boxes[i].first, on);
        for (const auto& [name, cost] : m.effectCosts)
            if (name == boxes[i].first) {
                ImGui::SameLine();
                ImGui::TextColored(kAmber, "%s", cost.c_str());
            }
    }
    if (ImGui::SmallButton("measure costs")) a.measureCosts = true;
    ImGui::SameLine();
    ImGui::TextDisabled("%s", m.effectCostNote.empty() ? "what each effect on screen costs" : m.effectCostNote.c_str());
}

void DrawMonitor(const OverlayUi& ui) {
    if (!ImGui::CollapsingHeader("MIDI / OSC monitor")) return;
    if (ui.monitor.recent.empty()) ImGui::TextDisabled("no events yet");
    for (const ControlEvent& e : ui.monitor.recent) ImGui::TextUnformatted(DescribeEvent(e).c_str());
}

void PlotTimes(const char* id, const FrameTimeGraph& g, const char* label) {
    char caption[64];
    std::snprintf(caption, sizeof caption, "avg %.1f ms  max %.1f ms", g.Average(), g.Max());
    ImGui::PlotLines(id, g.ms.data(), (int)g.ms.size(), 0, caption, 0.0f, std::max(33.4f, g.Max()), ImVec2(360, 48));
    ImGui::SameLine();
    ImGui::TextDisabled("%s", label);
}

void DrawTimes(const OverlayModel& m, const OverlayUi& ui, OverlayActions& a) {
    PlotTimes("##frames", ui.frames, "frame ms\n(CPU)");
    // GPU: timer queries read a few frames late, never waited for; none on a software renderer.
    if (!m.gpuTimesUnavailable.empty()) ImGui::TextDisabled("GPU ms: n/a (%s)", m.gpuTimesUnavailable.c_str());
    else if (ui.gpu.ms.empty()) ImGui::TextDisabled("GPU ms: waiting for the first timer query");
    else PlotTimes("##gpu", ui.gpu, "scene ms\n(GPU timer)");
    ImGui::TextDisabled("%s path, %dx%d, scene at %dx%d", m.pathName.c_str(), m.width, m.height,
                        (int)std::lround(m.width * m.renderScale), (int)std::lround(m.height * m.renderScale));
    // A slow machine keeps its frame rate by rendering fewer pixels (upscaled with filtering); above 1
    // the scene supersamples (2: each window pixel the mean of 2x2).
    float scale = m.renderScale;
    ImGui::SetNextItemWidth(180);
    if (ImGui::SliderFloat("resolution", &scale, 0.25f, 2.0f, "%.2f")) a.renderScale = scale;
}

}  // namespace

OverlayActions DrawOverlay(const OverlayModel& m, OverlayUi& ui) {
    OverlayActions a;
    ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowBgAlpha(0.6f);
    // Never taller than the screen: past that it scrolls.
    ImGui::SetNextWindowSizeConstraints(ImVec2(0, 0), ImVec2(FLT_MAX, std::max(100.0f, ImGui::GetIO().DisplaySize.y - 20)));
    ImGui::Begin("sdfvj", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
    if (ui.logText) ImGui::LogToBuffer();   // End() stops the log and clears it: read it before
    ImGui::Text("%s  [%s, %s]  %.1f fps", m.scene.c_str(), m.effectsText.c_str(), m.pathName.c_str(), m.fps);
    DrawParams(m, ui, a);
    DrawEffects(m, a);
    DrawPresets(m, ui, a);
    DrawTimes(m, ui, a);
    DrawMonitor(ui);
    for (const std::string& line : m.statusLines) ImGui::TextDisabled("%s", line.c_str());
    if (m.recording) ImGui::TextColored(ImVec4(1, 0.3f, 0.3f, 1), "REC  %zu events", m.recorded);
    if (!m.compiling.empty()) ImGui::TextDisabled("compiling %s ...", m.compiling.c_str());
    if (!m.shaderError.empty()) ImGui::TextColored(kRed, "%s", m.shaderError.c_str());
    if (!m.hasProgram) ImGui::TextColored(kAmber, "no program yet: save a fix and it starts");
    const size_t shown = std::min<size_t>(m.reportLines.size(), 3);
    for (size_t i = m.reportLines.size() - shown; i < m.reportLines.size(); ++i)
        ImGui::TextDisabled("%s", m.reportLines[i].c_str());
    ImGui::TextDisabled("Tab: hide   F11: fullscreen   1-9: preset   Esc: quit");
    if (ui.logText) ui.text = GImGui->LogBuffer.c_str();
    ImGui::End();
    return a;
}

// ---------------------------------------------------------------------------------------------
// Files
// ---------------------------------------------------------------------------------------------


bool PresetFileName(const std::string& name, std::string* fileName, std::string* error) {
    std::string stem = name;
    if (stem.size() > 5 && stem.compare(stem.size() - 5, 5, ".json") == 0) stem.resize(stem.size() - 5);
    const bool plain = !stem.empty() && stem.size() <= 64 && stem[0] != '.' &&
                       std::all_of(stem.begin(), stem.end(), [](char c) {
                           return std::isalnum((unsigned char)c) || c == '_' || c == '-' || c == '.';
                       });
    if (!plain) {
        *error = "preset name '" + name.substr(0, 64) +
                 "' is not a plain file name, expected letters, digits, '_', '-' or '.' (at most 64, no leading '.')";
        return false;
    }
    *fileName = stem + ".json";
    return true;
}

namespace {

// 0.3f as 0.3 in the file, not 0.30000001192092896 (six digits: far below what a knob moves).
double ReadableNumber(float v) {
    if (!std::isfinite(v)) return 0.0;
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", (double)v);
    return std::strtod(text, nullptr);
}

const char* NormalsName(int n) { return n == 1 ? "forward" : n == 2 ? "tetrahedron" : "central"; }

}  // namespace

std::string SavePresetAs(const std::string& folder, const std::string& name, const PresetSnapshot& s, std::string* error) {
    std::string file;
    if (!PresetFileName(name, &file, error)) return "";
    // Keys of the preset on stage that the overlay does not edit (scripts, mapping, take) stay.
    nlohmann::ordered_json j = nlohmann::ordered_json::object();
    if (!s.basePreset.empty()) {
        std::ifstream in(s.basePreset, std::ios::binary);
        std::stringstream ss;
        ss << in.rdbuf();
        nlohmann::ordered_json base = nlohmann::ordered_json::parse(ss.str(), nullptr, false);
        if (!in || base.is_discarded() || !base.is_object()) {
            *error = s.basePreset + ": cannot read the preset on stage to keep its scripts, expected a JSON object; not saved";
            return "";
        }
        j = std::move(base);
    }
    j["scene"] = s.scene;
    nlohmann::ordered_json params = nlohmann::ordered_json::object();
    for (const auto& [param, value] : s.values) {
        auto it = s.expressions.find(param);
        if (it != s.expressions.end()) params[param] = it->second;
        else params[param] = ReadableNumber(value);
    }
    j["params"] = std::move(params);
    // "none" first: the saved list is the whole set, not changes to the scene's own.
    const std::string list = DescribeEffects(s.effects);
    j["effects"] = list == "none" ? "none" : "none," + list;
    j["normals"] = NormalsName(s.effects.normals);
    const std::string text = j.dump(2) + "\n";
    const std::string path = (fs::path(folder) / file).string();
    Preset check;
    if (!ParsePresetText(text, path, &check, error)) {
        *error += " (the saved preset would not load; not saved)";
        return "";
    }
    if (!WriteFileAtomically(path, text, error)) return "";
    return path;
}

std::string AppendLearnedMapping(const std::string& mappingPath, const std::string& param, const std::string& source,
                                 const std::vector<ParamDecl>& decls) {
    return AddLearnedEntry(mappingPath, param, source, decls, "learned in `sdfvj live`");
}

std::string FinishLearn(LearnArm& learn, const std::string& mappingPath, const std::vector<ParamDecl>& decls) {
    if (!learn.Armed() || learn.source.empty()) return "";
    const std::string error = AppendLearnedMapping(mappingPath, learn.param, learn.source, decls);
    const std::string control = learn.source.substr(0, learn.source.find('\n'));
    const std::string line = error.empty() ? "learned: " + control + " -> " + learn.param + ", written to " + mappingPath : error;
    ArmLearn(learn, "");
    return line;
}

}  // namespace sdfvj
