#include "ui/viewer.h"

#include "base/files.h"
#include "base/log.h"
#include "devices/source_spec.h"
#include "processing/point_cloud.h"
#include "render/cloud_pick.h"

#include <imgui_internal.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string_view>
#include <tuple>
#include <utility>
#include <vector>

namespace dc::ui {

namespace {

// First-run placement (the saved layout wins afterwards): controls on the left, the cloud in the middle,
// depth, confidence and camera stacked on the right, all above the status bar.
struct Layout {
    ImVec2 origin;
    ImVec2 size;
    float leftWidth;
    float rightWidth;
};

// Between the menu bar and the status bar (both measured this frame: the viewport's work area would take
// the menu bar into account only from the next frame on).
Layout defaultLayout(float menuHeight, float statusHeight) {
    const ImGuiViewport* vp = ImGui::GetMainViewport();
    const ImVec2 size{vp->Size.x, std::max(vp->Size.y - menuHeight - statusHeight, 1.0f)};
    return {{vp->Pos.x, vp->Pos.y + menuHeight},
            size,
            std::clamp(size.x * 0.23f, 220.0f, 340.0f),
            size.x * 0.27f};
}

// The docked timeline: a title bar and four rows (transport, scrubber, range, export), and a thin row per
// further source under the scrubber.
float timelineStripHeight(std::size_t sourceRows) {
    return ImGui::GetFrameHeight() + 4.0f * ImGui::GetFrameHeightWithSpacing() +
           static_cast<float>(sourceRows) * ImGui::GetTextLineHeightWithSpacing() +
           2.0f * ImGui::GetStyle().WindowPadding.y;
}

// Popups (a combo's list, a menu), tooltips and toasts go in front of every panel and the timeline strip,
// in the order they had among themselves; a frame whose order is already so changes nothing.
void raiseOverlays() {
    std::vector<ImGuiWindow*> overlays;
    for (ImGuiWindow* w : GImGui->Windows) {
        const bool overlay = (w->Flags & (ImGuiWindowFlags_Popup | ImGuiWindowFlags_Tooltip)) != 0 ||
                             std::string_view(w->Name).starts_with(kToastPrefix);
        if (overlay && !(w->Flags & ImGuiWindowFlags_ChildWindow))
            overlays.push_back(w);
    }
    for (ImGuiWindow* w : overlays)
        ImGui::BringWindowToDisplayFront(w);
}

constexpr const char* kShortcutsTitle = "Shortcuts";
constexpr const char* kAboutTitle = "About depthcloud";
constexpr std::pair<const char*, const char*> kShortcuts[] = {
    {"1 2 3", "lowest confidence drawn: low, medium, high"},
    {"R", "auto-rotate on or off"},
    {"V", "reset the view"},
    {"C T S L", "Controls, Timeline, Stats, Log panels"},
    {"O F A", "Source, Fog, Aura panels"},
    {"P", "snapshot: every panel and the cloud as PLY"},
    {"Z", "undo the last anchor"},
    {"Space", "play or pause a replay"},
    {"Left Right", "step a replay one frame"},
    {"Home End", "first or last frame of a replay"},
    {"Esc", "close a menu, or a panel shown large"},
    {"Drag, wheel", "orbit, zoom the cloud; double-click resets it"},
    {"Ctrl+Q", "quit"}};

PanelImage imageOf(const render::RenderTarget& target) {
    return {target.colorTexture(), target.width(), target.height(), true};
}

// A depth or confidence panel's image: shaped as the map it shows, which the target may hold every n-th
// sample of.
PanelImage dataPanelImage(const render::RenderTarget& target, const render::ViewRenderer& renderer) {
    PanelImage image = imageOf(target);
    if (renderer.panelsMapWidth() > 0) {
        image.width = renderer.panelsMapWidth();
        image.height = renderer.panelsMapHeight();
    }
    return image;
}

PanelImage imageOf(const render::RgbaTexture& texture) {
    return {texture.id(), texture.width(), texture.height(), false};
}

// The camera panel's picture: made on the GPU from the image's planes, or the engine's.
PanelImage cameraImageOf(const render::ViewRenderer& renderer) {
    return renderer.cameraFromGpu() ? imageOf(renderer.cameraTarget()) : imageOf(renderer.cameraTexture());
}

// A clip-space point of the cloud's view in the cloud image, as fractions of its size (NDC y points up,
// image rows go down).
ImVec2 cloudFraction(const glm::vec4& clip) {
    const float w = clip.w > 1e-6f ? clip.w : 1e-6f;
    return {0.5f * (clip.x / w + 1.0f), 0.5f * (1.0f - clip.y / w)};
}

// The Quality panel's region on the cloud's surface (processing::roiOutline), in the cloud image. A vertex
// behind the view breaks its line as a missing sample does: projected, it would land mirrored on the image.
std::vector<std::vector<ImVec2>> roiOutlineOnCloud(const processing::ShownDepth& depth,
                                                   const processing::ShownQuality& quality,
                                                   const CloudSettings& cloud,
                                                   const glm::mat4& viewProjection) {
    // Smooth at any panel size, and few enough to project every frame.
    constexpr int kMaxVertices = 200;
    const std::vector<processing::Polyline3> runs =
        quality.polygon.empty() ? processing::roiOutline(*depth.data, depth.intrinsics, quality.roi,
                                                         cloud.minConfidence, cloud.nearMeters, kMaxVertices)
                                : processing::roiOutline(*depth.data, depth.intrinsics, quality.polygon,
                                                         cloud.minConfidence, cloud.nearMeters, kMaxVertices);
    std::vector<std::vector<ImVec2>> lines;
    for (const processing::Polyline3& run : runs) {
        lines.emplace_back();
        for (const auto& [x, y, z] : run) {
            const glm::vec4 clip = viewProjection * glm::vec4(x, y, z, 1.0f);
            if (clip.w > 0.0f)
                lines.back().push_back(cloudFraction(clip));
            else if (lines.back().size() >= 2)
                lines.emplace_back();
            else
                lines.back().clear();
        }
        if (lines.back().size() < 2)
            lines.pop_back();
    }
    return lines;
}

} // namespace

void Viewer::setZoomedPanel(const std::string& title) {
    if (!zoomed_.empty() && zoomed_ != title)
        restoring_ = zoomed_;
    if (title.empty() && !zoomed_.empty())
        restoring_ = zoomed_;
    zoomed_ = title;
}

// A zoomed panel covers the work area and stays in front; the panel that was zoomed goes back to where it
// was; every other panel keeps the user's layout, with the default placement on first use.
void Viewer::placePanel(const char* title, float x, float y, float w, float h) {
    if (zoomed_ == title) {
        ImGui::SetNextWindowPos(workOrigin_, ImGuiCond_Always);
        ImGui::SetNextWindowSize(workSize_, ImGuiCond_Always);
        ImGui::SetNextWindowFocus();
        ImGui::SetNextWindowBgAlpha(1.0f); // the panels behind must not show through
        return;
    }
    if (restoring_ == title) {
        if (const auto it = panelPlaces_.find(title); it != panelPlaces_.end()) {
            ImGui::SetNextWindowPos(it->second.first, ImGuiCond_Always);
            ImGui::SetNextWindowSize(it->second.second, ImGuiCond_Always);
        }
        restoring_.clear();
        return;
    }
    const ImGuiCond when = layoutResets_.erase(title) > 0 ? ImGuiCond_Always : ImGuiCond_FirstUseEver;
    ImGui::SetNextWindowPos({workOrigin_.x + x, workOrigin_.y + y}, when);
    ImGui::SetNextWindowSize({std::min(w, workSize_.x), std::min(h, workSize_.y)}, when);
    if (when != ImGuiCond_Always)
        keepInsideWorkArea(ImGui::FindWindowByName(title));
    // A panel that reaches below the work area (placed before the timeline strip appeared) ends above it.
    const float bottom = workOrigin_.y + workSize_.y;
    const ImGuiWindow* window = ImGui::FindWindowByName(title);
    if (when != ImGuiCond_Always && window && window->Pos.y < bottom - 1.0f &&
        window->Pos.y + window->Size.y > bottom + 0.5f)
        ImGui::SetNextWindowSize({window->Size.x, bottom - window->Pos.y}, ImGuiCond_Always);
}

// A panel the window shrank away from comes back within reach: one larger than the work area is made to
// fit it, and one whose title bar is off the window is moved back in. A panel the user moved partly over
// an edge (or over the timeline strip) stays where it is.
void Viewer::keepInsideWorkArea(const ImGuiWindow* window) const {
    if (!window)
        return;
    const ImVec2 size{std::min(window->Size.x, workSize_.x), std::min(window->Size.y, workSize_.y)};
    const float reach = 2.0f * ImGui::GetFrameHeight(); // of a title bar, to grab it
    const ImGuiViewport* vp = ImGui::GetMainViewport();
    const float left = vp->Pos.x, top = workOrigin_.y;
    const float right = left + vp->Size.x, bottom = vp->Pos.y + vp->Size.y;
    ImVec2 pos = window->Pos;
    if (pos.x > right - reach || pos.x + size.x < left + reach)
        pos.x = std::clamp(pos.x, left, right - size.x);
    if (pos.y > bottom - reach || pos.y < top)
        pos.y = std::clamp(pos.y, top, bottom - size.y);
    if (size.x != window->Size.x || size.y != window->Size.y)
        ImGui::SetNextWindowSize(size, ImGuiCond_Always);
    if (pos.x != window->Pos.x || pos.y != window->Pos.y)
        ImGui::SetNextWindowPos(pos, ImGuiCond_Always);
}

// Every panel but the source picker has a place in the layout: the controls on the left, the cloud in the
// middle with the stats and the log in a strip under it, the image panels in a column on the right.
constexpr const char* kDockedTitles[] = {kControlsTitle, kCloudTitle,    kDepthTitle, kConfidenceTitle,
                                         kCameraTitle,   kInfraredTitle, kFogTitle,   kAuraTitle,
                                         kStatsTitle,    kLogTitle};

// The docked panels follow the window's size and each other: a resized window, or a panel shown or hidden,
// lays them all out again.
void Viewer::followLayout() {
    const ImVec2 size = ImGui::GetMainViewport()->Size;
    std::vector<std::string_view> shown = rightColumn();
    const PanelVisibility& show = settings_.panels;
    for (const auto& [title, on] :
         {std::pair{kControlsTitle, show.controls}, std::pair{kCloudTitle, show.cloud},
          std::pair{kStatsTitle, show.stats}, std::pair{kLogTitle, show.log}})
        if (on)
            shown.push_back(title);
    const bool laidOut = layoutSize_.x > 0.0f;
    if (laidOut && (size.x != layoutSize_.x || size.y != layoutSize_.y || shown != dockedShown_))
        layoutResets_.insert(std::begin(kDockedTitles), std::end(kDockedTitles));
    layoutSize_ = size;
    dockedShown_ = std::move(shown);
}

// The right column's panels shown, top to bottom; they share its height. Titles are compared by their
// text: two uses of one literal need not share an address (unoptimized builds do not merge them).
std::vector<std::string_view> Viewer::rightColumn() const {
    const PanelVisibility& show = settings_.panels;
    std::vector<std::string_view> titles;
    for (const auto& [title, on] :
         {std::pair{kDepthTitle, show.depth}, std::pair{kConfidenceTitle, show.confidence},
          std::pair{kCameraTitle, show.camera},
          std::pair{kInfraredTitle, show.infrared && infraredAvailable()}, std::pair{kFogTitle, show.fog},
          std::pair{kAuraTitle, show.aura}})
        if (on)
            titles.push_back(title);
    return titles;
}

void Viewer::resetLayout() {
    settings_.panels = {};
    zoomed_.clear();
    restoring_.clear();
    panelPlaces_.clear();
    // Each panel goes back to its default place the next time it is drawn, whenever that is.
    layoutResets_ = {kCloudTitle,    kDepthTitle,   kConfidenceTitle,     kCameraTitle, kControlsTitle,
                     kStatsTitle,    kLogTitle,     kSourceTitle,         kFogTitle,    kAuraTitle,
                     kInfraredTitle, kQualityTitle, kCameraControlsTitle, kTimingTitle};
}

// File: what a person opens and saves, each also a shortcut or a button elsewhere.
void Viewer::drawFileMenu() {
    if (!ImGui::BeginMenu("File"))
        return;
    if (ImGui::MenuItem("Open...", "O"))
        settings_.panels.source = true;
    if (ImGui::BeginMenu("Recent", !settings_.recentSources.empty())) {
        for (const std::string& spec : settings_.recentSources)
            if (ImGui::MenuItem(spec.c_str()))
                pendingSource_ = spec;
        ImGui::EndMenu();
    }
    ImGui::Separator();
    if (ImGui::MenuItem(instrument_.recording().recording ? "Stop recording" : "Record"))
        toggleRecording();
    if (ImGui::MenuItem("Snapshot", "P"))
        (void)saveSnapshot(kSnapshotDirectory);
    if (ImGui::MenuItem("Export...", nullptr, false, instrument_.replay() != nullptr))
        settings_.panels.timeline = true; // the timeline holds the export range, format and folder
    ImGui::Separator();
    if (ImGui::MenuItem("Quit", "Ctrl+Q"))
        quitRequested_ = true;
    ImGui::EndMenu();
}

void Viewer::drawHelpMenu() {
    if (!ImGui::BeginMenu("Help"))
        return;
    if (ImGui::MenuItem("Shortcuts"))
        helpShown_ = true;
    if (ImGui::MenuItem("About depthcloud"))
        aboutShown_ = true;
    ImGui::EndMenu();
}

void Viewer::drawHelpWindows() {
    if (helpShown_) {
        ImGui::SetNextWindowSize({460.0f, 0.0f}, ImGuiCond_FirstUseEver);
        if (ImGui::Begin(kShortcutsTitle, &helpShown_, ImGuiWindowFlags_AlwaysAutoResize)) {
            for (const auto& [keys, what] : kShortcuts) {
                ImGui::TextUnformatted(keys);
                ImGui::SameLine(ImGui::GetFontSize() * 9.0f);
                ImGui::TextDisabled("%s", what);
            }
        }
        ImGui::End();
    }
    if (aboutShown_) {
        if (ImGui::Begin(kAboutTitle, &aboutShown_, ImGuiWindowFlags_AlwaysAutoResize)) {
            ImGui::TextUnformatted(about_.c_str());
            ImGui::TextDisabled("See what a depth camera measures.");
        }
        ImGui::End();
    }
}

// The menu bar: File, every panel (with its shortcut) and the layout reset, Help; returns its height.
float Viewer::drawMenuBar() {
    if (!ImGui::BeginMainMenuBar())
        return 0.0f;
    const float height = ImGui::GetWindowSize().y;
    drawFileMenu();
    if (ImGui::BeginMenu("View")) {
        PanelVisibility& show = settings_.panels;
        const std::tuple<const char*, const char*, bool*> panels[] = {
            {kCloudTitle, nullptr, &show.cloud},
            {kDepthTitle, nullptr, &show.depth},
            {kConfidenceTitle, nullptr, &show.confidence},
            {kCameraTitle, nullptr, &show.camera},
            {kInfraredTitle, nullptr, &show.infrared},
            {kControlsTitle, "C", &show.controls},
            {kTimelineTitle, "T", &show.timeline},
            {kStatsTitle, "S", &show.stats},
            {kLogTitle, "L", &show.log},
            {kSourceTitle, "O", &show.source},
            {kFogTitle, "F", &show.fog},
            {kAuraTitle, "A", &show.aura},
            {kQualityTitle, nullptr, &show.quality},
            {kCameraControlsTitle, nullptr, &show.cameraControls},
            {kTimingTitle, nullptr, &show.timing},
            {kSourcesTitle, nullptr, &show.sources}};
        for (const auto& [title, key, shown] : panels)
            ImGui::MenuItem(title, key, shown, shown != &show.infrared || infraredAvailable());
        ImGui::Separator();
        if (ImGui::MenuItem("Reset layout"))
            resetLayout();
        ImGui::EndMenu();
    }
    drawHelpMenu();
    ImGui::EndMainMenuBar();
    return height;
}

void Viewer::afterPanel(const char* title, const PanelResult& result) {
    if (zoomed_ != title && restoring_ != title)
        panelPlaces_[title] = {result.windowPos, result.windowSize};
    if (result.probe)
        hoverProbe_ = result.probe;
    if (result.toggleZoom)
        setZoomedPanel(zoomed_ == title ? std::string() : std::string(title));
    if (result.drawnRect)
        setDrawnRoi(*result.drawnRect);
    if (result.drawnPolygon)
        setDrawnPolygon(*result.drawnPolygon);
}

void Viewer::drawUi() {
    handleShortcuts(settings_);
    const bool escape = ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Escape), false);
    if (escape && !GImGui->OpenPopupStack.empty()) {
        ImGui::ClosePopupToLevel(0, true); // Esc closes an open menu or list before anything else
    } else if (!ImGui::GetIO().WantTextInput) {
        if (!zoomed_.empty() && escape)
            setZoomedPanel({});
        if (ImGui::IsKeyPressed('Z', false))
            presenter_.anchors().undo();
        if (ImGui::IsKeyPressed('P', false))
            (void)saveSnapshot(kSnapshotDirectory);
    }
    hoverProbe_.reset();
    followLayout();
    const float menuHeight = drawMenuBar();
    measure();
    const float statusHeight = drawStatusBar(shownStatusLine());
    Layout l = defaultLayout(menuHeight, statusHeight);
    PanelVisibility& show = settings_.panels;
    // The timeline is a strip under the panels, full width: nothing is placed over it, and it stays in
    // front of a panel the user moved there. The frame holds the replay it draws, so nothing in the frame can
    // end it; a source chosen in the frame is opened after it (pendingSource_).
    const std::shared_ptr<devices::replay::ReplayControl> replay = instrument_.replay();
    const bool timeline = replay && show.timeline;
    const float stripHeight =
        timeline ? std::min(timelineStripHeight(companions_.size()), l.size.y * 0.5f) : 0.0f;
    l.size.y -= stripHeight;
    workOrigin_ = l.origin;
    workSize_ = l.size;

    if (show.controls)
        drawControls(l.leftWidth, l.size.y);
    const float cloudWidth = l.size.x - l.leftWidth - l.rightWidth;
    const float strip = show.stats || show.log ? std::clamp(l.size.y * 0.3f, 160.0f, 320.0f) : 0.0f;
    if (show.cloud)
        drawCloud(l.leftWidth, 0, cloudWidth, l.size.y - strip);
    drawSidePanels(l.size.x - l.rightWidth, l.rightWidth, l.size.y);
    drawBottomStrip(l.leftWidth, l.size.y - strip, cloudWidth, strip);
    if (show.source)
        drawSourcePicker(l.leftWidth + 40.0f, 40.0f);
    if (show.sources)
        drawSources(l.leftWidth + 100.0f, 100.0f);
    if (show.quality)
        drawQuality(l.leftWidth + 20.0f, 20.0f);
    if (show.cameraControls)
        drawCameraControls(l.leftWidth + 60.0f, 60.0f);
    if (show.timing) {
        placePanel(kTimingTitle, l.leftWidth + 80.0f, 80.0f, 440.0f, 560.0f);
        drawTimingPanel(instrument_.timing(), &show.timing,
                        companions_.skewRows(instrument_, shown(), settings_.sources.pairingToleranceMs));
    }
    if (timeline)
        drawTimeline(*replay, {l.origin.x, l.origin.y + l.size.y}, {l.size.x, stripHeight});
    if (replay)
        handleReplayKeys(*replay);
    drawToasts(logs_.snapshot(), statusHeight);
    if (hoverProbe_)
        showProbeTooltip(*hoverProbe_);
    drawHelpWindows();
    raiseOverlays();
    if (auto spec = std::exchange(pendingSource_, std::nullopt))
        (void)openSource(*spec);
}

void Viewer::toggleRecording() {
    if (const engine::RecordingStatus r = instrument_.recording(); r.recording) {
        // A finished take is one click away in Recent (the instrument says where it went).
        if (instrument_.stopRecording())
            rememberSource(settings_, "replay:" + r.path);
        return;
    }
    devices::recording::RecordingOptions options;
    options.color = settings_.record.jpegColor ? devices::recording::ColorStorage::Jpeg
                                               : devices::recording::ColorStorage::AsCaptured;
    options.jpegQuality = settings_.record.jpegQuality;
    // A failure (a missing folder, a full disk) is logged by the instrument and shown as a toast.
    (void)instrument_.startTake(settings_.record.directory, options);
}

void Viewer::drawControls(float width, float height) {
    placePanel(kControlsTitle, 0, 0, width, height);
    const ControlsContext context{true,
                                  true,
                                  presenter_.anchors().size(),
                                  shown() && shown()->frame->pose,
                                  instrument_.accumulation().size(),
                                  cloudPathText(),
                                  shown() ? shown()->cloud.factor : 1,
                                  presenter_.pointsShown(),
                                  instrument_.recording(),
                                  &recordState_,
                                  infraredAvailable()};
    const ControlsResult r = drawControlsPanel(settings_, context, &settings_.panels.controls);
    if (r.snapshot)
        (void)saveSnapshot(kSnapshotDirectory);
    if (r.resetLayout)
        resetLayout();
    if (r.toggleRecording)
        toggleRecording();
    if (r.clearAccumulation)
        instrument_.accumulation().clear();
    if (r.clearAnchors)
        presenter_.anchors().clear();
    if (r.undoAnchor)
        presenter_.anchors().undo();
}

void Viewer::drawCloud(float x, float y, float w, float h) {
    placePanel(kCloudTitle, x, y, w, h);
    const bool gizmo = placeGizmo();
    const CloudPanelResult r =
        drawCloudPanel(renderer_.cloudTarget(), settings_.cloud, cloudOverlay(), cloudMessage(),
                       zoomed_ == kCloudTitle, &settings_.panels.cloud, gizmo ? &cloudGizmo_ : nullptr);
    afterPanel(kCloudTitle, r.panel);
    if (gizmo && r.gizmoStep) {
        frame::RigidTransform& correction = companions_[*sourcesPanel_.gizmo].look.correction;
        correction = frame::compose(*r.gizmoStep, correction);
    }
    measurementLabels_ = r.labels;
    const render::RenderTarget& target = renderer_.cloudTarget();
    if (r.wantedWidth > 0 && r.wantedHeight > 0 &&
        (r.wantedWidth != target.width() || r.wantedHeight != target.height()))
        resizeCloud(r.wantedWidth, r.wantedHeight);
    onCloudPointer(r);
}

// Places the gizmo at the chosen companion's camera as the fused cloud places it, seen as the cloud is
// drawn: through the world into the main source's camera frame. False (and nothing held) while there is
// none to draw: no companion chosen, or it or the main source has no frame yet.
bool Viewer::placeGizmo() {
    const std::optional<std::size_t> chosen = sourcesPanel_.gizmo;
    const processing::ShownFramePtr* own =
        chosen && *chosen < companions_.size() ? &companions_[*chosen].presenter().shown() : nullptr;
    if (!own || !*own || !shown()) {
        cloudGizmo_.held.reset();
        return false;
    }
    const auto& t = placeInWorld(*(*own)->frame, companions_[*chosen].look.correction).translationMeters;
    cloudGizmo_.originWorld = {t[0], t[1], t[2]};
    const glm::dmat4 worldToMain =
        glm::inverse(toMatrix(frame::poseFromRigid(placeInWorld(*shown()->frame, {}))));
    cloudGizmo_.worldToClip = glm::dmat4(presenter_.cloudViewProjection()) * worldToMain;
    return true;
}

// The right column, `height` tall, shared by the image panels shown.
void Viewer::drawSidePanels(float x, float w, float height) {
    const std::vector<std::string_view> column = rightColumn();
    const float h = height / static_cast<float>(std::max<std::size_t>(column.size(), 1));
    const auto place = [&](const char* title) {
        const auto slot = std::find(column.begin(), column.end(), std::string_view(title)) - column.begin();
        placePanel(title, x, static_cast<float>(slot) * h, w, h);
    };
    PanelVisibility& show = settings_.panels;
    // The pictures of the source picked over the images: its renderer's, its frame under the hover
    // readout. The Quality panel's region is the main source's alone.
    if (panelSource_ > companions_.size())
        panelSource_ = 0;
    const bool main = panelSource_ == 0;
    const render::ViewRenderer& renderer = main ? renderer_ : companions_[panelSource_ - 1].renderer();
    Presenter& presenter = main ? presenter_ : companions_[panelSource_ - 1].presenter();
    const processing::ShownFramePtr& frame = presenter.shown();
    const ProbeSource probe = probeSourceOf(frame);
    const RoiOverlay roi = main ? roiOverlay() : RoiOverlay{};
    SourceTabs tabs{{}, &panelSource_};
    for (std::size_t i = 0; !companions_.empty() && i <= companions_.size(); ++i)
        tabs.names.push_back(i == 0 ? "Source 1" : sourceName(i - 1));
    int dataPanelsWidth = 0;
    const auto afterDataPanel = [&](const char* title, const PanelResult& result) {
        afterPanel(title, result);
        dataPanelsWidth = std::max(dataPanelsWidth, result.shownWidth);
    };
    if (show.depth) {
        place(kDepthTitle);
        const DepthView& view = settings_.depthView;
        const bool gpu = renderer.colourOverDepthFromGpu();
        const bool overlay = view.colourOverlay && frame && (frame->colourOverDepth || gpu);
        const PanelImage colour = !overlay ? PanelImage{}
                                  : gpu    ? imageOf(renderer.colourOverDepthTarget())
                                           : imageOf(renderer.colourOverDepthTexture());
        afterDataPanel(kDepthTitle, drawDepthPanel(dataPanelImage(renderer.depthTarget(), renderer),
                                                   {colour, view.overlayOpacity}, presenter.depthLegend(),
                                                   probe, roi, &show.depth, tabs));
    }
    if (show.confidence) {
        place(kConfidenceTitle);
        const bool estimated = !probe.empty() && probe.depth->confidenceEstimated;
        const engine::Instrument& source = main ? instrument_ : companions_[panelSource_ - 1].instrument();
        const bool available = source.capabilities().confidence || estimated;
        afterDataPanel(kConfidenceTitle,
                       drawConfidencePanel(dataPanelImage(renderer.confidenceTarget(), renderer), available,
                                           estimated, probe, roi, &show.confidence, tabs));
    }
    if (show.camera) {
        place(kCameraTitle);
        const bool aligned = frame && renderer.alignsDepthOverCamera(presenter.demand().gpuCameraColours);
        const PanelImage depth = aligned ? imageOf(renderer.depthOverCameraTarget())
                                         : dataPanelImage(renderer.depthTarget(), renderer);
        const PanelResult r = drawCameraPanel(
            cameraImageOf(renderer), depth, settings_.camera, probe,
            frame && frame->frame && !frame->frame->rig ? roi : RoiOverlay{}, &show.camera, tabs);
        afterPanel(kCameraTitle, r);
        if (r.shownWidth > 0)
            presenter.setCameraShownWidth(r.shownWidth);
        // A single camera's depth overlay is the depth panel's image, shown at the camera panel's size.
        if (!aligned && settings_.camera.depthOverlay)
            dataPanelsWidth = std::max(dataPanelsWidth, r.shownWidth);
    }
    if (dataPanelsWidth > 0)
        presenter.setDataPanelsShownWidth(dataPanelsWidth);
    if (show.infrared && infraredAvailable()) {
        place(kInfraredTitle);
        const processing::IntensityRange range =
            shown() ? shown()->infraredRange : processing::IntensityRange{};
        afterPanel(kInfraredTitle, drawInfraredPanel(imageOf(renderer_.infraredTexture()), range, probe,
                                                     roiOverlay(), &show.infrared));
    }
    if (show.fog) {
        place(kFogTitle);
        drawFogPanel(imageOf(renderer_.fogTexture()), settings_.processing.fog, &show.fog);
    }
    if (show.aura) {
        place(kAuraTitle);
        drawAuraPanel(imageOf(renderer_.auraTexture()), settings_.processing.aura, &show.aura);
    }
}

// The strip under the cloud: the stats and the log side by side, or one of them across it.
void Viewer::drawBottomStrip(float x, float y, float w, float h) {
    PanelVisibility& show = settings_.panels;
    const float half = show.stats && show.log ? w / 2.0f : w;
    if (show.stats) {
        placePanel(kStatsTitle, x, y, half, h);
        drawStatsPanel(*measured_, &show.stats);
    }
    if (show.log) {
        placePanel(kLogTitle, x + w - half, y, half, h);
        drawLogPanel(logs_.snapshot(), logPanel_, &show.log);
    }
}

void Viewer::drawSources(float x, float y) {
    placePanel(kSourcesTitle, x, y, 480.0f, 560.0f);
    const engine::InstrumentStatus main = instrument_.status();
    std::vector<SourceRow> rows{
        {main.source, main.state.text(), main.frames, std::nullopt, std::nullopt, std::nullopt, true, nullptr,
         dataPanelImage(renderer_.depthTarget(), renderer_), cameraImageOf(renderer_)}};
    for (std::size_t i = 0; i < companions_.size(); ++i) {
        Companion& c = companions_[i];
        const engine::InstrumentStatus s = c.instrument().status();
        rows.push_back({s.source, s.state.text(), s.frames, companions_.overlap(i, shown()),
                        companions_.skewMs(i, instrument_, shown()),
                        c.skew.count() > 0 ? std::optional(c.skew.median()) : std::nullopt,
                        companions_.paired(i, instrument_, shown(), settings_.sources.pairingToleranceMs),
                        &c.look, dataPanelImage(c.renderer().depthTarget(), c.renderer()),
                        cameraImageOf(c.renderer())});
        rows.back().own = &c.own;
    }
    applySourcesActions(drawSourcesPanel(rows, sourcesPanel_, settings_.sources.pairingToleranceMs,
                                         &settings_.panels.sources));
}

void Viewer::applySourcesActions(const SourcesActions& actions) {
    if (actions.add)
        pendingAddition_ = actions.add;
    if (actions.remove) {
        pendingRemoval_ = actions.remove;
        sourcesPanel_.gizmo.reset(); // the rows after the one removed move up
    }
    if (actions.resetPlacement && *actions.resetPlacement < companions_.size())
        companions_[*actions.resetPlacement].look.correction = {};
    if (actions.savePlacements) {
        auto files = companions_.savePlacements(instrument_.spec(), kSnapshotDirectory);
        sourcesPanel_.message = files ? "wrote " + files->front() +
                                            (files->size() > 1 ? " and camchain.yaml" : "") +
                                            ": pose=" + files->front() + "#camera_N places source N+1 there"
                                      : "placements not saved: " + files.error().message;
        (files ? logInfo : logError)(sourcesPanel_.message);
    }
    if (!actions.refine)
        return;
    auto r = companions_.refine(*actions.refine, shown());
    char line[200];
    if (r)
        std::snprintf(line, sizeof line,
                      "ICP %s after %d iterations: %.1f mm -> %.1f mm; moved %.2f deg, %.1f mm",
                      processing::toString(r->status), r->iterations, r->before.medianMm, r->after.medianMm,
                      r->correctionDegrees, r->correctionMm);
    sourcesPanel_.message = r ? line : r.error().message;
    logInfo("source " + std::to_string(*actions.refine + 2) + ": " + sourcesPanel_.message);
}

void Viewer::drawSourcePicker(float x, float y) {
    placePanel(kSourceTitle, x, y, 420.0f, 360.0f);
    SourceList list{instrument_.spec(), liveSources_, {}, {}};
    for (const std::string& spec : settings_.recentSources)
        list.recent.push_back({spec, spec});
    list.builtIn = {{"Synthetic desk, 256x192 @ 60 Hz", "synthetic"},
                    {"Synthetic desk, 640x480 @ 30 Hz", "synthetic:640x480@30"},
                    {"Synthetic desk, moving camera (poses)", "synthetic:motion"},
                    {"Synthetic two-sensor camera, 848x480 depth + 1280x720 colour", "synthetic:rig=rgbd"}};
    // Opened once the frame is drawn: the panels after this one still draw the source they started with.
    if (auto chosen = drawSourcePanel(list, sourcePanel_, &settings_.panels.source))
        pendingSource_ = std::move(chosen);
}

// The Quality panel floats over the cloud, like the source picker: its figures are read beside the depth.
void Viewer::drawQuality(float x, float y) {
    placePanel(kQualityTitle, x, y, 360.0f, 470.0f);
    if (const processing::ShownFramePtr& s = shown(); s && s->frame)
        quality_.log.add(s->quality, s->frame->timestampNs);
    const processing::ShownQuality* q = quality();
    const PanelImage map = q && q->map ? imageOf(renderer_.qualityMapTexture()) : PanelImage{};
    const QualityPanelResult r =
        drawQualityPanel(q, settings_.quality, quality_, map, &settings_.panels.quality);
    qualityMapHover_ = r.mapHover;
    if (r.clear) {
        quality_.log.clear();
        quality_.savedTo.clear();
    }
    if (r.save)
        (void)saveQualityFigures(kSnapshotDirectory);
}

Expected<std::string> Viewer::saveQualityFigures(const std::string& parent) {
    auto dir = exporting::writeQualityLog(parent, quality_.log, instrument_.status().source,
                                          settingsToJson(settings_));
    if (!dir) {
        logError("quality figures not saved: " + dir.error().message);
        return dir;
    }
    quality_.savedTo = *dir;
    logNotice("quality figures of " + std::to_string(quality_.log.rows().size()) + " frames saved to " +
              *dir + " (figures.csv, figures.json)");
    return dir;
}

// The Camera controls panel floats over the cloud, so the effect of a change shows beside it. Its controls
// follow the source: a new source's are read when the panel next draws.
void Viewer::drawCameraControls(float x, float y) {
    if (!cameraControlsSpec_ || *cameraControlsSpec_ != instrument_.spec()) {
        cameraControls_ = {};
        cameraControls_.controls = instrument_.sensorControls();
        cameraControlsSpec_ = instrument_.spec();
    }
    placePanel(kCameraControlsTitle, x, y, 460.0f, 520.0f);
    drawCameraControlsPanel(cameraControls_, ImGui::GetTime(), &settings_.panels.cameraControls);
    for (const std::string& message : cameraControls_.refused)
        logWarning(message);
    cameraControls_.refused.clear();
    if (const auto mode = std::exchange(cameraControls_.chosenMode, std::nullopt))
        reopenInMode(devices::specWithDepthMode(instrument_.spec(), *mode));
    if (const auto mode = std::exchange(cameraControls_.chosenColorMode, std::nullopt))
        reopenInMode(devices::specWithColorMode(instrument_.spec(), *mode));
}

// The camera streams in the mode chosen without a restart: the source is opened again with it. A mode that
// does not fit its two-sensor calibration is refused when the camera opens, naming the calibration's field.
void Viewer::reopenInMode(const Expected<std::string>& spec) {
    if (!spec) {
        logWarning(spec.error().message);
        return;
    }
    // The same camera: the panel keeps its mode lists and what they show, with the new source's controls.
    if (!openSource(*spec))
        return;
    cameraControlsSpec_ = instrument_.spec();
    cameraControls_.controls = instrument_.sensorControls();
}

// The region measured, outlined on the image panels of the depth's field of view, on which a drag draws a
// new one while the Quality panel is shown.
RoiOverlay Viewer::roiOverlay() const {
    RoiOverlay overlay;
    overlay.drawable = settings_.panels.quality && shown() && shown()->depth.data;
    const processing::ShownQuality* q = quality();
    if (!overlay.drawable || !q || q->roi.width <= 0)
        return overlay;
    const float w = static_cast<float>(shown()->depth.width()),
                h = static_cast<float>(shown()->depth.height());
    overlay.outline = ImVec4(static_cast<float>(q->roi.x) / w, static_cast<float>(q->roi.y) / h,
                             static_cast<float>(q->roi.x + q->roi.width) / w,
                             static_cast<float>(q->roi.y + q->roi.height) / h);
    for (const auto& [x, y] : q->polygon)
        overlay.polygon.push_back({static_cast<float>(x) / w, static_cast<float>(y) / h});
    if (settings_.quality.causeOverlay && q->causeOverlay)
        overlay.causes = imageOf(renderer_.causeOverlayTexture());
    return overlay;
}

// Every depth pixel the rectangle touches is in the region (at least one).
void Viewer::setDrawnRoi(const ImVec4& f) {
    if (!shown() || !shown()->depth.data)
        return;
    const float w = static_cast<float>(shown()->depth.width()),
                h = static_cast<float>(shown()->depth.height());
    QualitySettings& q = settings_.quality;
    q.roiX = static_cast<int>(std::floor(f.x * w));
    q.roiY = static_cast<int>(std::floor(f.y * h));
    q.roiWidth = std::max(static_cast<int>(std::ceil(f.z * w)) - q.roiX, 1);
    q.roiHeight = std::max(static_cast<int>(std::ceil(f.w * h)) - q.roiY, 1);
    q.roiPercent = 0;
    q.polygon.clear();
    sanitize(q);
}

// The lasso's vertices in the shown depth's pixel coordinates; the region is the samples whose centres are
// inside it.
void Viewer::setDrawnPolygon(const std::vector<ImVec2>& fractions) {
    if (!shown() || !shown()->depth.data)
        return;
    const float w = static_cast<float>(shown()->depth.width()),
                h = static_cast<float>(shown()->depth.height());
    QualitySettings& q = settings_.quality;
    q.polygon.clear();
    for (const ImVec2& f : fractions) {
        q.polygon.push_back(f.x * w);
        q.polygon.push_back(f.y * h);
    }
    q.roiPercent = 0;
    sanitize(q);
}

void Viewer::drawTimeline(devices::replay::ReplayControl& replay, ImVec2 pos, ImVec2 size) {
    ImGui::SetNextWindowPos(pos, ImGuiCond_Always);
    ImGui::SetNextWindowSize(size, ImGuiCond_Always);
    const engine::ExportJob* job = instrument_.exportJob();
    TimelineView view{replay.status(), job && !job->finished(), 0, 0, companions_.timelineRows(instrument_)};
    if (job)
        std::tie(view.exportDone, view.exportTotal) = job->progress();
    applyTimeline(replay,
                  drawTimelinePanel(view, timelineState_, &settings_.panels.timeline,
                                    ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize |
                                        ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoSavedSettings));
    if (ImGuiWindow* strip = ImGui::FindWindowByName(kTimelineTitle))
        ImGui::BringWindowToDisplayFront(strip);
}

void Viewer::applyTimeline(devices::replay::ReplayControl& replay, const TimelineActions& a) {
    if (a.seekIndex)
        instrument_.seekReplay(*a.seekIndex);
    if (a.step != 0)
        instrument_.stepReplay(a.step);
    if (a.play)
        *a.play ? replay.play() : replay.pause();
    if (a.loop)
        replay.setLoop(*a.loop);
    if (a.speed)
        replay.setSpeed(*a.speed);
    if (a.cancelExport)
        instrument_.cancelExport();
    if (a.exportRange)
        startExport();
}

// The range is written as the instrument shows it (smoothed, upsampled, as the settings say) into the
// chosen folder, or where that exists already into the next free numbered one beside it: an export never
// writes over another. A relative folder is taken from where the tool runs now, once: the export's thread
// writes to that folder even if the working directory changes while it runs.
void Viewer::startExport() {
    std::error_code ec;
    std::filesystem::path chosen = std::filesystem::absolute(timelineState_.outDirectory.data(), ec);
    if (ec) {
        logError("export: " + std::string(timelineState_.outDirectory.data()) + ": " + ec.message());
        return;
    }
    if (!chosen.has_filename())
        chosen = chosen.parent_path(); // "out/" names the folder "out"
    const std::filesystem::path parent = chosen.has_parent_path() ? chosen.parent_path() : ".";
    auto dir = base::createFreshDirectory(parent.string(), chosen.filename().string());
    if (!dir) {
        logError("export: " + dir.error().message);
        return;
    }
    // The files hold what the panels show, not the Quality panel's figures: none are measured for them.
    engine::Demand demand = presenter_.demand();
    demand.quality.reset();
    if (!instrument_.startExport(static_cast<exporting::ExportFormat>(timelineState_.format), *dir,
                                 timelineState_.rangeStart, timelineState_.rangeEnd, demand)) {
        std::filesystem::remove(*dir, ec); // still empty: nothing was started
    }
}

// Space plays or pauses, the arrows step a frame, Home and End jump to the ends (as in video players).
void Viewer::handleReplayKeys(devices::replay::ReplayControl& replay) {
    if (ImGui::GetIO().WantTextInput)
        return;
    const auto pressed = [](ImGuiKey key) {
        return ImGui::IsKeyPressed(ImGui::GetKeyIndex(key), key != ImGuiKey_Space);
    };
    if (pressed(ImGuiKey_Space))
        replay.status().playing ? replay.pause() : replay.play();
    if (pressed(ImGuiKey_LeftArrow))
        instrument_.stepReplay(-1);
    if (pressed(ImGuiKey_RightArrow))
        instrument_.stepReplay(1);
    if (pressed(ImGuiKey_Home))
        instrument_.seekReplay(0);
    if (pressed(ImGuiKey_End))
        instrument_.seekReplay(std::max<std::size_t>(replay.status().count, 1) - 1);
}

// Hovering the cloud reads out the point under the mouse; a click drops an anchor on it. The first click
// of a double-click (which resets the view) must not leave an anchor behind.
void Viewer::onCloudPointer(const CloudPanelResult& r) {
    const ProbeSource source = probeSource();
    if (source.empty() || !r.hoverPixels)
        return;
    const double now = ImGui::GetTime();
    if (r.doubleClicked && lastAnchorTime_ >= 0.0 &&
        now - lastAnchorTime_ <= ImGui::GetIO().MouseDoubleClickTime) {
        presenter_.anchors().undo();
        lastAnchorTime_ = -1.0;
    }
    render::PickQuery query;
    query.viewProjection = presenter_.cloudViewProjection();
    query.cursorPixels = {r.hoverPixels->x, r.hoverPixels->y};
    const render::RenderTarget& target = renderer_.cloudTarget();
    query.imageSize = {static_cast<float>(target.width()), static_cast<float>(target.height())};
    query.radiusPixels = std::max(3.0f, settings_.cloud.pointSizePixels);
    query.minConfidence = settings_.cloud.minConfidence;
    query.nearMeters = settings_.cloud.nearMeters;
    const auto picked = render::pickCloudSample(*source.depth, source.intrinsics, query);
    if (!picked)
        return;
    hoverProbe_ = probeAt(source, picked->u, picked->v);
    if (r.clickPixels && !r.doubleClicked) {
        presenter_.anchors().add(picked->point, shown()->frame->pose);
        lastAnchorTime_ = now;
    }
}

// The last frame stays on screen, marked, while a live camera is away (seed 003's interruption).
std::string Viewer::cloudMessage() {
    const engine::InstrumentStatus s = instrument_.status();
    if (!s.running)
        return s.message;
    if (s.state == engine::SourceState{devices::DeviceState::Disconnected})
        return "Disconnected: showing the last frame; streaming resumes when the camera is back.";
    if (s.state == engine::SourceState{devices::DeviceState::Stalled})
        return "Stalled: the camera stopped delivering frames.";
    return {};
}

// The cloud is drawn in the shown frame's camera frame: the region's points, in that frame already, take
// the cloud's view as they are; the anchors, kept in the world, are brought into it first.
CloudOverlay Viewer::cloudOverlay() const {
    CloudOverlay overlay;
    if (!shown())
        return overlay;
    // Outlined where the image panels outline it (roiOverlay).
    if (const processing::ShownQuality* q = quality();
        settings_.panels.quality && q && q->roi.width > 0 && shown()->depth.data)
        overlay.roiOutline =
            roiOutlineOnCloud(shown()->depth, *q, settings_.cloud, presenter_.cloudViewProjection());
    const Anchors& anchors = presenter_.anchors();
    if (anchors.empty())
        return overlay;
    for (const glm::vec3& p : anchors.inCameraFrame(shown()->frame->pose))
        overlay.anchors.push_back(cloudFraction(presenter_.cloudViewProjection() * glm::vec4(p, 1.0f)));
    for (std::size_t i = 0; i + 1 < anchors.size(); ++i)
        overlay.segments.emplace_back(static_cast<int>(i), formatLength(anchors.segmentMeters(i)));
    if (anchors.size() >= 3) {
        const std::size_t last = anchors.size() - 1;
        overlay.segments.emplace_back(static_cast<int>(last), formatLength(anchors.closingMeters()));
    }
    if (anchors.size() >= 3)
        overlay.summary = "area " + formatArea(anchors.areaSquareMeters());
    return overlay;
}

} // namespace dc::ui
