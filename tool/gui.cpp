#include <epoxy/gl.h>
// GLFW after epoxy: epoxy provides the GL declarations, GLFW must not include its own.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "base/files.h"
#include "base/log.h"
#include "devices/uvc/live_device_watcher.h"
#include "frame/image_io.h"
#include "tool/options.h"
#include "tool/partial_present.h"
#include "tool/summary.h"
#include "tool/version.h"
#include "ui/frame_damage.h"
#include "ui/input_queue.h"
#include "ui/viewer.h"

#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>

#include <algorithm>
#include <cfloat>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <utility>
#include <vector>

namespace dc::tool {

namespace {

using Clock = std::chrono::steady_clock;

constexpr float kBackground[3] = {0.08f, 0.08f, 0.1f};
// How long past its --frames a window waits for the source's first frame before it ends all the same.
constexpr std::chrono::seconds kFirstFrameWait{60};

struct GlfwWindowDeleter {
    void operator()(GLFWwindow* w) const { glfwDestroyWindow(w); }
};
using WindowPtr = std::unique_ptr<GLFWwindow, GlfwWindowDeleter>;

// Owns glfwInit/glfwTerminate for the scope of the GUI run.
struct GlfwLibrary {
    bool ok = glfwInit() == GLFW_TRUE;
    ~GlfwLibrary() {
        if (ok)
            glfwTerminate();
    }
};

// Owns the ImGui context and both backends.
struct ImGuiScope {
    explicit ImGuiScope(GLFWwindow* window, const std::string& iniPath) : ini(iniPath) {
        ImGui::CreateContext();
        ImGui::GetIO().IniFilename = ini.c_str();
        // A HiDPI screen (content scale 2 on a 4K laptop) gets text and widgets of the same physical size.
        float scaleX = 1.0f, scaleY = 1.0f;
        glfwGetWindowContentScale(window, &scaleX, &scaleY);
        if (scaleX > 1.0f) {
            ImGui::GetStyle().ScaleAllSizes(scaleX);
            ImGui::GetIO().FontGlobalScale = scaleX;
        }
        glfwReady = ImGui_ImplGlfw_InitForOpenGL(window, true);
        glReady = ImGui_ImplOpenGL3_Init("#version 330 core");
    }
    ~ImGuiScope() {
        if (glReady)
            ImGui_ImplOpenGL3_Shutdown();
        if (glfwReady)
            ImGui_ImplGlfw_Shutdown();
        ImGui::DestroyContext();
    }
    std::string ini; // ImGui keeps the pointer: the string must outlive the context
    bool glfwReady = false;
    bool glReady = false;
};

// Every key, character, button, scroll and cursor event goes into the queue, which feeds ImGui one frame's
// worth at a time (ui::InputQueue says why); these replace the ImGui backend's own callbacks for them.
struct WindowInput {
    ui::InputQueue queue;
    std::vector<std::string> dropped; // files and folders dropped on the window, to open as sources
    bool exposed = false;             // the window system lost the picture: it is drawn again
};

ui::InputQueue& queueOf(GLFWwindow* window) {
    return static_cast<WindowInput*>(glfwGetWindowUserPointer(window))->queue;
}

void onDrop(GLFWwindow* window, int count, const char** paths) {
    auto& dropped = static_cast<WindowInput*>(glfwGetWindowUserPointer(window))->dropped;
    for (int i = 0; i < count; ++i)
        dropped.emplace_back(paths[i]);
}

void onKey(GLFWwindow* window, int key, int, int action, int mods) {
    // Ctrl+Q quits at once, whatever the queue holds.
    if (key == GLFW_KEY_Q && action == GLFW_PRESS && (mods & GLFW_MOD_CONTROL))
        glfwSetWindowShouldClose(window, GLFW_TRUE);
    if (action != GLFW_REPEAT) // ImGui repeats held keys itself
        queueOf(window).push({ui::InputEvent::Kind::Key, key, action == GLFW_PRESS, 0.0f, 0.0f});
}

void onChar(GLFWwindow* window, unsigned codepoint) {
    queueOf(window).push({ui::InputEvent::Kind::Char, static_cast<int>(codepoint), false, 0.0f, 0.0f});
}

void onMouseButton(GLFWwindow* window, int button, int action, int) {
    queueOf(window).push({ui::InputEvent::Kind::MouseButton, button, action == GLFW_PRESS, 0.0f, 0.0f});
}

void onCursor(GLFWwindow* window, double x, double y) {
    queueOf(window).push(
        {ui::InputEvent::Kind::CursorPos, 0, false, static_cast<float>(x), static_cast<float>(y)});
}

// The mouse left the window: nothing is under it any more (no hover readout left behind), whatever the
// last position inside was.
void onCursorEnter(GLFWwindow* window, int entered) {
    if (!entered)
        queueOf(window).push({ui::InputEvent::Kind::CursorPos, 0, false, -FLT_MAX, -FLT_MAX});
}

void onRefresh(GLFWwindow* window) {
    static_cast<WindowInput*>(glfwGetWindowUserPointer(window))->exposed = true;
}

void onScroll(GLFWwindow* window, double x, double y) {
    queueOf(window).push(
        {ui::InputEvent::Kind::Scroll, 0, false, static_cast<float>(x), static_cast<float>(y)});
}

void queueInput(GLFWwindow* window, WindowInput& input) {
    glfwSetWindowUserPointer(window, &input);
    glfwSetDropCallback(window, onDrop);
    glfwSetKeyCallback(window, onKey);
    glfwSetCharCallback(window, onChar);
    glfwSetMouseButtonCallback(window, onMouseButton);
    glfwSetCursorPosCallback(window, onCursor);
    glfwSetCursorEnterCallback(window, onCursorEnter);
    glfwSetScrollCallback(window, onScroll);
    glfwSetWindowRefreshCallback(window, onRefresh);
}

// The primary monitor's area for windows (without panels and docks); 1280x720 where none is known.
ui::WindowPlacement workArea() {
    ui::WindowPlacement area{0, 0, 1280, 720, false};
    if (GLFWmonitor* monitor = glfwGetPrimaryMonitor())
        glfwGetMonitorWorkarea(monitor, &area.x, &area.y, &area.width, &area.height);
    if (area.width <= 0 || area.height <= 0)
        area = {0, 0, 1280, 720, false};
    return area;
}

// Where the window opens: where it was closed, kept on the screen; the first time, 1280x720 or 80 % of a
// larger screen, centred, never larger than the screen.
ui::WindowPlacement initialPlacement(const ui::WindowPlacement& saved) {
    const ui::WindowPlacement area = workArea();
    ui::WindowPlacement p = saved;
    if (p.width <= 0 || p.height <= 0) {
        p.width = std::max(1280, area.width * 4 / 5);
        p.height = std::max(720, area.height * 4 / 5);
        p.x = area.x + (area.width - std::min(p.width, area.width)) / 2;
        p.y = area.y + (area.height - std::min(p.height, area.height)) / 2;
    }
    p.width = std::min(p.width, area.width);
    p.height = std::min(p.height, area.height);
    p.x = std::clamp(p.x, area.x, area.x + area.width - p.width);
    p.y = std::clamp(p.y, area.y, area.y + area.height - p.height);
    return p;
}

WindowPtr openWindow(const ui::WindowPlacement& saved) {
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE); // shown once in its place
    const ui::WindowPlacement p = initialPlacement(saved);
    WindowPtr window(glfwCreateWindow(p.width, p.height, "depthcloud", nullptr, nullptr));
    if (!window)
        return window;
    glfwSetWindowPos(window.get(), p.x, p.y);
    glfwShowWindow(window.get());
    if (p.maximized)
        glfwMaximizeWindow(window.get());
    return window;
}

ui::WindowPlacement placementOf(GLFWwindow* window) {
    ui::WindowPlacement p;
    glfwGetWindowPos(window, &p.x, &p.y);
    glfwGetWindowSize(window, &p.width, &p.height);
    p.maximized = glfwGetWindowAttrib(window, GLFW_MAXIMIZED) == GLFW_TRUE;
    return p;
}

ui::Settings loadSettings(const std::string& path, bool reset) {
    if (reset) {
        logInfo("settings: defaults and the default layout (--reset)");
        return {};
    }
    std::ifstream in(path);
    if (!in) {
        logInfo("settings: defaults (" + path + " does not exist yet)");
        return {};
    }
    std::stringstream text;
    text << in.rdbuf();
    auto settings = ui::settingsFromJson(text.str());
    if (!settings) {
        logWarning(path + ": " + settings.error().message + "; starting with default settings");
        return {};
    }
    logInfo("settings: " + path);
    return *settings;
}

// The window as the user sees it, read from the back buffer just before it is shown.
Status saveScreenshot(GLFWwindow* window, const std::string& path) {
    int w = 0, h = 0;
    glfwGetFramebufferSize(window, &w, &h);
    // Framebuffer 0 is the window's back buffer.
    const std::vector<std::uint8_t> rgba = render::readFramebufferRgba(0, w, h);
    if (rgba.empty())
        return Error{"cannot save " + path + ": the window has no size"};
    return frame::writeRgbaPng(path, w, h, rgba.data());
}

// The time between two of the display's refreshes (60 Hz where the display does not say).
Clock::duration refreshPeriod() {
    const GLFWvidmode* mode = glfwGetVideoMode(glfwGetPrimaryMonitor());
    const int hz = mode && mode->refreshRate > 0 ? mode->refreshRate : 60;
    return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / hz));
}

// How long the next frame may wait for the engine's next result: until a refresh period after the last
// frame began. A GL that swaps without waiting for the display (software GL, or vsync off) would
// otherwise redraw as fast as the cores allow, frames the display never shows; a new result still starts
// the frame at once, and where the swap waits for the display this is already over.
std::chrono::milliseconds waitBudget(Clock::time_point lastFrameStart, Clock::duration period) {
    const auto left = lastFrameStart + period - Clock::now();
    // Rounded up: a wait rounded down would let the frames come a little faster than the display.
    return std::max(std::chrono::ceil<std::chrono::milliseconds>(left), std::chrono::milliseconds(0));
}

// The finished ImGui frame into the back buffer, whole.
void composite(GLFWwindow* window) {
    int w = 0, h = 0;
    glfwGetFramebufferSize(window, &w, &h);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, w, h);
    glClearColor(kBackground[0], kBackground[1], kBackground[2], 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

// The finished ImGui frame into the back buffer where it changed, each part copied to the window. False
// where the X server refused a copy (the window changed size since the back buffer did).
bool presentParts(const PartialPresenter& presenter, const std::vector<ui::DamageRect>& rects) {
    ImDrawData& data = *ImGui::GetDrawData();
    const int height = static_cast<int>(data.DisplaySize.y * data.FramebufferScale.y);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, static_cast<int>(data.DisplaySize.x * data.FramebufferScale.x), height);
    ui::drawDamaged(data, rects, [height](const ui::DamageRect& r) {
        render::clearColorWithin(ui::pixelRectOf(r, height), kBackground[0], kBackground[1], kBackground[2]);
    });
    bool shown = true;
    for (const ui::DamageRect& r : rects)
        shown = presenter.copy(ui::pixelRectOf(r, height)) && shown;
    return shown;
}

// What drawChanged did: whether it drew, and whether the window may show less than it drew (a copy refused).
struct Drawn {
    bool drawn = false;
    bool incomplete = false;
};

// Draws the frame where it changed: in parts for a presenter, whole for a swap. The last frame is drawn
// whole for a swap even if unchanged, since the screenshot reads the back buffer.
Drawn drawChanged(GLFWwindow* window, const std::optional<PartialPresenter>& parts,
                  const std::vector<ui::DamageRect>& changed, bool last) {
    if (parts && !changed.empty())
        return {true, !presentParts(*parts, changed)};
    if (!parts && (!changed.empty() || last)) {
        composite(window);
        return {true, false};
    }
    return {};
}

std::pair<int, int> sizeOf(GLFWwindow* window) {
    int w = 0, h = 0;
    glfwGetFramebufferSize(window, &w, &h);
    return {w, h};
}

// Whether the window's framebuffer changed size since `size` (which it updates): the next frame is drawn
// whole. Software GL gives the back buffer the window's new size only at a swap (Mesa revalidates the
// drawable there), so where nothing else swaps this swaps once first: a copy from a back buffer of the old
// size would leave the picture offset, or ask the X server for pixels outside its image. `stale` (a copy
// was refused) asks for the same without a size GLFW has seen change: the resize is on its way.
bool followSize(GLFWwindow* window, std::pair<int, int>& size, const std::optional<PartialPresenter>& parts,
                bool stale) {
    const std::pair<int, int> now = sizeOf(window);
    if (now == size && !stale)
        return false;
    size = now;
    if (parts && !parts->resizeBackBuffer())
        logWarning("window: the X server refused a swap while the window changed size; drawn whole again");
    return true;
}

// One ImGui frame, with the input that came in. Returns where its picture differs from the one the window
// shows (nothing moved, no new data, no input that changed anything: nowhere).
std::vector<ui::DamageRect> uiFrame(ui::Viewer& viewer, WindowInput& input, ui::FrameDamage& damage) {
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    input.queue.apply(ImGui::GetIO());
    ImGui::NewFrame();
    viewer.drawUi();
    ImGui::Render();
    ImDrawData& data = *ImGui::GetDrawData();
    ui::snapClipRects(data);
    if (std::exchange(input.exposed, false))
        damage.forget();
    return damage.update(data, viewer.renderer().contentVersion(), ImGui::GetIO().Fonts->TexID);
}

// The picker's "Cameras" entries: the depth-capable devices, each opened by its --source value.
std::vector<ui::SourceEntry> cameraEntries(const devices::LiveDeviceListing& listing) {
    std::vector<ui::SourceEntry> entries;
    for (const devices::LiveDeviceInfo& d : listing.devices)
        if (d.depthCapable())
            entries.push_back({d.label(), d.sourceSpec});
    return entries;
}

int writeOutputs(GLFWwindow* window, ui::Viewer& viewer, const std::string& dir) {
    Status s = saveScreenshot(window, dir + "/screenshot.png");
    if (s) {
        if (auto written = viewer.savePanels(dir); !written)
            s = written.error();
    }
    if (s) {
        const auto renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
        s = base::writeTextFile(dir + "/summary.json",
                                summaryJson(viewer.summary(), renderer ? renderer : "unknown", "gui"));
    }
    if (!s) {
        std::fprintf(stderr, "depthcloud: error: %s\n", s.error().message.c_str());
        return kExitFailure;
    }
    return kExitOk;
}

} // namespace

int runGui(const ViewerOptions& options, std::unique_ptr<devices::Device> device, Devices companions) {
    GlfwLibrary glfw;
    if (!glfw.ok) {
        std::fprintf(stderr, "depthcloud: error: cannot open a window (GLFW failed to initialise); "
                             "use --headless\n");
        return kExitFailure;
    }
    const std::string configDir = ui::configDirectory();
    std::error_code ec;
    std::filesystem::create_directories(configDir, ec);
    const std::string settingsPath = configDir + "/settings.json";
    const std::string iniPath = configDir + "/layout.ini";
    if (options.reset)
        std::filesystem::remove(iniPath, ec);
    auto chosen = chosenSettings(
        options.settingsPath.empty() ? loadSettings(settingsPath, options.reset) : ui::Settings{}, options);
    if (!chosen) { // runViewer checked the arguments already: only a file changed since can fail here
        std::fprintf(stderr, "depthcloud: error: %s\n", chosen.error().message.c_str());
        return kExitFailure;
    }
    ui::Settings settings = std::move(*chosen);

    WindowPtr window = openWindow(settings.window);
    if (!window) {
        std::fprintf(stderr,
                     "depthcloud: error: no OpenGL 3.3 context available for a window; use --headless\n");
        return kExitFailure;
    }
    glfwMakeContextCurrent(window.get());
    glfwSwapInterval(1);

    ui::rememberSource(settings, options.source);
    int status = kExitOk;
    {
        ImGuiScope imgui(window.get(), iniPath);
        WindowInput input;
        queueInput(window.get(), input);
        render::ViewRenderer renderer;
        if (Status s = renderer.init(); !s) {
            std::fprintf(stderr, "depthcloud: error: %s\n", s.error().message.c_str());
            return kExitFailure;
        }
        const auto glRenderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
        logInfo(std::string("renderer: OpenGL on ") + (glRenderer ? glRenderer : "an unknown renderer"));
        logInfo("source: " + options.source);
        engine::Instrument instrument(std::move(device), options.source);
        ui::Viewer viewer(instrument, renderer, settings);
        viewer.setAbout(versionLine());
        const auto own = furtherSourcesSettings(viewer.settings(), options);
        for (std::size_t i = 0; i < companions.size() && own; ++i) {
            auto c = ui::Companion::create(std::move(companions[i]), options.companions[i], viewer.settings(),
                                           (*own)[i]);
            if (!c) {
                std::fprintf(stderr, "depthcloud: error: %s\n", c.error().message.c_str());
                return kExitFailure;
            }
            viewer.companions().add(std::move(*c));
            viewer.settings().panels.sources = true;
        }
        instrument.start();
        devices::LiveDeviceWatcher cameras;
        const auto start = Clock::now();
        const Clock::duration period = refreshPeriod();
        Clock::time_point frameStart = start;
        ui::FrameDamage damage;
        std::pair<int, int> framebufferSize = sizeOf(window.get());
        bool incomplete = false;                        // a part of the last frame did not reach the window
        std::optional<Clock::time_point> framesCounted; // when the window drew its --frames
        // Software GL draws only what changed, into a back buffer that nothing swaps; a GPU draws whole
        // frames, synchronised with the display by the swap.
        const std::optional<PartialPresenter> parts =
            renderer.softwareGl() ? PartialPresenter::forCurrentContext() : std::nullopt;
        logInfo(parts ? "window: drawn where it changes (software GL, GLX_MESA_copy_sub_buffer)"
                      : "window: whole frames, swapped");
        for (int frame = 0;; ++frame) {
            if (auto listing = cameras.takeUpdate())
                viewer.setLiveSources(cameraEntries(*listing));
            const std::chrono::milliseconds wait = waitBudget(frameStart, period);
            const auto now = Clock::now();
            viewer.update(std::chrono::duration<double>(now - start).count(), wait);
            frameStart = now + std::chrono::duration_cast<Clock::duration>(
                                   std::chrono::duration<double, std::milli>(viewer.lastWaitMs()));
            glfwPollEvents(); // after the wait: the frame acts on the freshest input
            if (followSize(window.get(), framebufferSize, parts, std::exchange(incomplete, false)))
                damage.forget();
            const auto uiStart = Clock::now();
            const std::vector<ui::DamageRect> changed = uiFrame(viewer, input, damage);
            for (const std::string& path : std::exchange(input.dropped, {}))
                (void)viewer.openPath(path);
            if (viewer.quitRequested())
                glfwSetWindowShouldClose(window.get(), GLFW_TRUE);
            // Closing the window ends the run like the last of --frames: --out still gets its files. --frames
            // counts the window's frames, and a source slow to start on a busy machine may not have shown one
            // by then: the run goes on until it has (or kFirstFrameWait passed), so --out has a picture.
            if (options.frames && frame + 1 >= *options.frames && !framesCounted)
                framesCounted = Clock::now();
            const bool last =
                glfwWindowShouldClose(window.get()) ||
                (framesCounted && (viewer.shown() || Clock::now() - *framesCounted > kFirstFrameWait));
            const auto [drawn, refused] = drawChanged(window.get(), parts, changed, last);
            incomplete = refused;
            if (drawn)
                viewer.recordUiMilliseconds(
                    std::chrono::duration<double, std::milli>(Clock::now() - uiStart).count());
            if (last && !options.outDirectory.empty())
                status = writeOutputs(window.get(), viewer, options.outDirectory);
            if (drawn && !parts)
                glfwSwapBuffers(window.get());
            viewer.presented(drawn);
            if (last)
                break;
        }
        viewer.settings().window = placementOf(window.get());
        if (Status s = base::writeTextFile(settingsPath, ui::settingsToJson(viewer.settings())); !s)
            logWarning("settings not saved: " + s.error().message);
    }
    return status;
}

} // namespace dc::tool
