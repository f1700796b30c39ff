#include "ui/headless_ui.h"

#include <backends/imgui_impl_opengl3.h>

#include <GLFW/glfw3.h>

#include <utility>

namespace dc::ui {

HeadlessUi::~HeadlessUi() {
    if (rendererReady_)
        ImGui_ImplOpenGL3_Shutdown();
    if (context_)
        ImGui::DestroyContext(context_);
}

Status HeadlessUi::init(int width, int height) {
    if (width <= 0 || height <= 0)
        return Error{"headless UI needs a positive size"};
    context_ = ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr; // tests and benchmarks start from the default layout every time
    io.DisplaySize = ImVec2(static_cast<float>(width), static_cast<float>(height));
    // The named keys as GLFW's backend maps them, so shortcuts behave the same with and without a window.
    const std::pair<ImGuiKey, int> keys[] = {
        {ImGuiKey_Escape, GLFW_KEY_ESCAPE},       {ImGuiKey_Space, GLFW_KEY_SPACE},
        {ImGuiKey_LeftArrow, GLFW_KEY_LEFT},      {ImGuiKey_RightArrow, GLFW_KEY_RIGHT},
        {ImGuiKey_UpArrow, GLFW_KEY_UP},          {ImGuiKey_DownArrow, GLFW_KEY_DOWN},
        {ImGuiKey_Home, GLFW_KEY_HOME},           {ImGuiKey_End, GLFW_KEY_END},
        {ImGuiKey_Enter, GLFW_KEY_ENTER},         {ImGuiKey_KeyPadEnter, GLFW_KEY_KP_ENTER},
        {ImGuiKey_Backspace, GLFW_KEY_BACKSPACE}, {ImGuiKey_Tab, GLFW_KEY_TAB}};
    for (const auto& [key, code] : keys)
        io.KeyMap[key] = code;
    if (!ImGui_ImplOpenGL3_Init("#version 330 core"))
        return Error{"ImGui's OpenGL 3 renderer failed to initialise"};
    rendererReady_ = true;
    target_.resize(width, height);
    return {};
}

Status HeadlessUi::resize(int width, int height) {
    damage_.forget();
    return target_.resize(width, height);
}

void HeadlessUi::newFrame(float deltaSeconds) {
    ImGuiIO& io = ImGui::GetIO();
    io.DeltaTime = deltaSeconds > 0.0f ? deltaSeconds : 1.0f / 60.0f;
    io.DisplaySize = ImVec2(static_cast<float>(target_.width()), static_cast<float>(target_.height()));
    ImGui_ImplOpenGL3_NewFrame();
    ImGui::NewFrame();
}

void HeadlessUi::render() {
    ImGui::Render();
    ImDrawData& data = *ImGui::GetDrawData();
    snapClipRects(data);
    damage_.forget(); // the next renderIfChanged() draws its whole frame
    target_.bindAndClear(0.1f, 0.1f, 0.12f);
    ImGui_ImplOpenGL3_RenderDrawData(&data);
}

bool HeadlessUi::renderIfChanged(std::uint64_t contentVersion) {
    ImGui::Render();
    ImDrawData& data = *ImGui::GetDrawData();
    snapClipRects(data);
    const std::vector<DamageRect> rects = damage_.update(data, contentVersion, ImGui::GetIO().Fonts->TexID);
    if (changedFramesWhole_ && !rects.empty()) {
        target_.bindAndClear(0.1f, 0.1f, 0.12f);
        ImGui_ImplOpenGL3_RenderDrawData(&data);
        return true;
    }
    drawDamaged(data, rects, [this](const DamageRect& r) {
        target_.bindAndClearWithin(pixelRectOf(r, target_.height()), 0.1f, 0.1f, 0.12f);
    });
    return !rects.empty();
}

} // namespace dc::ui
