#include "ui/headless_ui.h"

#include <backends/imgui_impl_opengl3.h>
#include <epoxy/gl.h>

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
    if (!ImGui_ImplOpenGL3_Init("#version 330 core"))
        return Error{"ImGui's OpenGL 3 renderer failed to initialise"};
    rendererReady_ = true;
    target_.resize(width, height);
    return {};
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
    target_.bind();
    glClearColor(0.1f, 0.1f, 0.12f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

} // namespace dc::ui
