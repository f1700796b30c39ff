#pragma once

#include "engine/demand.h"
#include "frame/jpeg_codec.h"
#include "processing/pipeline.h"
#include "processing/point_colours.h"
#include "processing/registration.h"
#include "processing/shown_frame.h"

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

namespace dc::engine {

// Stage names beyond the pipeline's, as the stats show them.
inline constexpr std::string_view kCameraDecodeStage = "camera decode";
inline constexpr std::string_view kPointColoursStage = "point colours";
inline constexpr std::string_view kCameraImageStage = "camera image";
inline constexpr std::string_view kInfraredImageStage = "infrared image";
inline constexpr std::string_view kEffectsImageStage = "effects image";
inline constexpr std::string_view kFogStage = "fog";
inline constexpr std::string_view kAuraStage = "aura";
inline constexpr std::string_view kAlignedDepthStage = "aligned depth";
inline constexpr std::string_view kColourOverlayStage = "colour overlay";
inline constexpr std::string_view kDepthRangeStage = "depth range";
inline constexpr std::string_view kPointCountStage = "point count";
inline constexpr std::string_view kDecimationStage = "decimation";
inline constexpr std::string_view kPanelSamplesStage = "panel samples";
inline constexpr std::string_view kQualityStage = "depth quality";

// Turns one frame and one demand into the ShownFrame the GL thread draws, running only the stages the
// demand needs and, of those, only the ones whose inputs changed since the last run (each stage remembers
// the inputs of its last result): a colormap change redoes nothing here, an upsampling change redoes
// upsampling and what depends on the shown depth, and a new frame redoes what it feeds. Single-threaded;
// the frame processor owns one, export another.
class ProcessingGraph {
public:
    ProcessingGraph();

    // `newFrame`: the frame is a new capture, not the current one again (which temporal stages must not
    // count twice; they recognise it by its timestamp either way).
    processing::ShownFramePtr run(const frame::FramePtr& captured, const Demand& demand,
                                  std::uint64_t generation, bool newFrame);
    // Drops temporal state and every remembered result (a seek, a new source).
    void reset();
    // The fault-injection seam: called with a stage's name just before the stage runs; a test throws from
    // it to see a failing stage handled. None by default.
    using StageFault = std::function<void(std::string_view stage)>;
    void setStageFault(StageFault fault) { fault_ = std::move(fault); }
    // How many times `stage` has run: tests count work, not time.
    std::uint64_t runs(std::string_view stage) const;
    const std::map<std::string, std::uint64_t, std::less<>>& allRuns() const { return runs_; }

private:
    // The last result of one stage and the inputs it was made from. Inputs hold shared pointers, so an
    // input that still matches is the very same object, never a new one at a recycled address.
    template <class Key, class Value> struct Memo {
        std::optional<Key> key;
        Value value{};
        void clear() {
            key.reset();
            value = {};
        }
    };
    struct DepthKey {
        frame::FramePtr frame;
        processing::ProcessingSettings settings;
        processing::Needs needs;
        bool operator==(const DepthKey&) const;
    };
    struct ImageKey {
        std::shared_ptr<const std::vector<std::uint8_t>> bytes;
        int width = 0;
        int height = 0;
        bool operator==(const ImageKey&) const = default;
    };
    // A two-sensor frame's colours depend on the depth too (where each point lands in the colour image);
    // a single camera's on the image and the size alone, so smoothing does not redo them.
    struct ColoursKey {
        ImageKey image;
        std::shared_ptr<const frame::DepthData> registeredDepth;
        bool operator==(const ColoursKey&) const = default;
    };
    // The shown depth of a two-sensor frame in the colour image's geometry, at one size.
    struct AlignedKey {
        std::shared_ptr<const frame::DepthData> depth;
        std::shared_ptr<const frame::RigCalibration> rig;
        int width = 0;
        int height = 0;
        bool operator==(const AlignedKey&) const = default;
    };
    struct EffectKey {
        std::shared_ptr<const processing::RgbImage> image;
        std::shared_ptr<const frame::DepthData> depth;
        processing::FogSettings fog;
        processing::AuraSettings aura;
        std::int64_t timestampNs = 0;
        bool operator==(const EffectKey&) const = default;
    };
    struct CountKey {
        std::shared_ptr<const frame::DepthData> depth;
        frame::Confidence minConfidence = frame::Confidence::Low;
        float nearMeters = 0.0f;
        bool operator==(const CountKey&) const = default;
    };

    struct DecimationKey {
        std::shared_ptr<const frame::DepthData> depth;
        int factor = 1;
        frame::Confidence minConfidence = frame::Confidence::Low;
        float nearMeters = 0.0f;
        bool operator==(const DecimationKey&) const = default;
    };
    struct PanelSamplesKey {
        std::shared_ptr<const frame::DepthData> depth;
        int step = 1;
        bool operator==(const PanelSamplesKey&) const = default;
    };
    // The Quality panel's figures: of one shown depth, over one region, under one processing.
    struct QualityKey {
        std::shared_ptr<const frame::DepthData> depth;
        QualityDemand quality;
        processing::Roi roi; // quality's region fitted to the depth map
        processing::ProcessingSettings settings;
        bool operator==(const QualityKey&) const = default;
    };
    // Runs `make` for `key` unless the memo already holds its result; timed and counted under `stage`.
    template <class Key, class Value, class Make>
    const Value& cached(Memo<Key, Value>& memo, const Key& key, std::string_view stage, Make&& make);
    frame::FramePtr decodedFrame(const frame::FramePtr& captured, const Demand& demand);
    processing::ShownDepth shownDepth(const frame::FramePtr& frame, const Demand& demand);
    void addCameraImage(processing::ShownFrame& shown, const frame::Frame& frame, const Demand& demand);
    void addPointColours(processing::ShownFrame& shown, const frame::Frame& frame, const Demand& demand);
    void addDepthOverCamera(processing::ShownFrame& shown, const frame::Frame& frame, const Demand& demand);
    void addInfrared(processing::ShownFrame& shown, const frame::FramePtr& frame, const Demand& demand);
    void addEffects(processing::ShownFrame& shown, const frame::Frame& frame, const Demand& demand);
    std::shared_ptr<const frame::DepthData> colourViewDepth(const processing::ShownFrame& shown,
                                                            const frame::Frame& frame, int width, int height);
    void addDepthProducts(processing::ShownFrame& shown, const Demand& demand);
    processing::ShownCloud shownCloud(const processing::ShownFrame& shown, const Demand& demand);
    void addQuality(processing::ShownFrame& shown, const Demand& demand);
    void addPanelSamples(processing::ShownFrame& shown, const Demand& demand);
    std::shared_ptr<const processing::ShownQuality>
    measureQuality(const QualityKey& key, const frame::Intrinsics& intrinsics, const frame::Frame& frame);
    void addAlignment(processing::ShownQuality& quality, const frame::Frame& frame,
                      const frame::DepthData& depth, const frame::Intrinsics& intrinsics);

    processing::Pipeline pipeline_;
    processing::CameraColourTable colourTable_;
    frame::JpegDecoder jpegDecoder_;
    Memo<frame::FramePtr, frame::FramePtr> decoded_;
    Memo<DepthKey, processing::ShownDepth> depth_;
    Memo<ColoursKey, processing::PointColours> pointColours_;
    Memo<ColoursKey, std::shared_ptr<const processing::RgbImage>> cloudColours_; // of decimated samples
    Memo<std::shared_ptr<const processing::RgbImage>, std::shared_ptr<const processing::RgbaImage>>
        colourOverlay_;
    Memo<ImageKey, std::shared_ptr<const processing::RgbImage>> cameraImage_;
    Memo<ImageKey, std::shared_ptr<const processing::RgbImage>> effectsImage_;
    Memo<AlignedKey, std::shared_ptr<const frame::DepthData>> alignedDepth_;
    struct StretchedInfrared {
        std::shared_ptr<const processing::RgbImage> image;
        processing::IntensityRange range;
    };
    Memo<frame::FramePtr, StretchedInfrared> infraredImage_;
    Memo<EffectKey, std::shared_ptr<const processing::RgbaImage>> fog_;
    Memo<EffectKey, std::shared_ptr<const processing::RgbaImage>> aura_;
    Memo<std::shared_ptr<const frame::DepthData>, std::optional<processing::DepthRangeMeters>> range_;
    Memo<DecimationKey, processing::ShownCloud> cloud_;
    Memo<CountKey, std::size_t> count_;
    Memo<PanelSamplesKey, std::shared_ptr<const frame::DepthData>> panelSamples_;
    Memo<QualityKey, std::shared_ptr<const processing::ShownQuality>> quality_;
    // The noise window and the question it answers (QualityKey without the depth): frames enter it as
    // their figures are made, and a question that changes starts it over.
    std::optional<processing::NoiseWindow> noise_;
    std::optional<QualityKey> noiseKey_;
    std::optional<std::int64_t> noiseFedNs_; // the capture that entered it last (one re-delivered is not new)
    StageFault fault_;
    std::map<std::string, std::uint64_t, std::less<>> runs_;
    std::vector<processing::StageTiming>* timings_ = nullptr; // of the result being made
};

} // namespace dc::engine
