// DrawOverlay (src/app/live_overlay.h) in an ImGui context with no window or GL: tests set the
// mouse by hand, find a widget by scanning the mouse over the screen, and click it.
#pragma once
#include <catch2/catch.hpp>

#include <imgui.h>
#include <imgui_internal.h>

#include "app/live_overlay.h"

namespace sdfvj::test {

struct HeadlessImGui {
    HeadlessImGui() {
        ImGui::CreateContext();
        ImGuiIO& io = ImGui::GetIO();
        io.IniFilename = nullptr;
        io.DisplaySize = ImVec2(640, 480);
        io.DeltaTime = 1.0f / 60.0f;
        unsigned char* pixels = nullptr;
        int w = 0, h = 0;
        io.Fonts->GetTexDataAsRGBA32(&pixels, &w, &h);   // a built atlas is all NewFrame needs
    }
    ~HeadlessImGui() { ImGui::DestroyContext(); }
    // One frame with the mouse at `pos`, button down or up; returns the overlay's actions.
    OverlayActions Frame(const OverlayModel& m, OverlayUi& ui, ImVec2 pos, bool down, ImGuiID* hovered = nullptr) {
        ImGuiIO& io = ImGui::GetIO();
        io.MousePos = pos;
        io.MouseDown[0] = down;
        ImGui::NewFrame();
        OverlayActions a = DrawOverlay(m, ui);
        if (hovered) *hovered = GImGui->HoveredId;
        ImGui::Render();
        return a;
    }
    // Where the item with `id` is: scans the mouse over the screen until ImGui says it is hovered.
    bool Find(const OverlayModel& m, OverlayUi& ui, ImGuiID id, ImVec2* at) {
        const ImVec2 size = ImGui::GetIO().DisplaySize;
        for (float y = 12; y < size.y - 4; y += 4)
            for (float x = 12; x < size.x - 20; x += 8) {
                ImGuiID h = 0;
                Frame(m, ui, ImVec2(x, y), false, &h);
                if (h == id) {
                    *at = ImVec2(x, y);
                    return true;
                }
            }
        return false;
    }
};

// The id ImGui gives a widget labelled `label` under PushID(index) in the overlay window.
inline ImGuiID ParamWidgetId(int index, const char* label) {
    ImGuiWindow* w = ImGui::FindWindowByName("sdfvj");
    REQUIRE(w != nullptr);
    const ImGuiID seed = ImHashData(&index, sizeof index, w->ID);
    return ImHashStr(label, 0, seed);
}

}  // namespace sdfvj::test
