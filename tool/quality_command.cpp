// depthcloud quality: Intel Depth Quality Tool's figures of a flat target, measured over N frames of a source
// opened directly (no Session, no GL), printed one per line and optionally written as JSON.

#include "tool/quality_command.h"

#include "base/files.h"
#include "base/log.h"
#include "devices/source_spec.h"
#include "frame/jpeg_codec.h"
#include "processing/depth_quality.h"
#include "processing/edge_alignment.h"
#include "processing/registration.h"
#include "tool/options.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>

namespace dc::tool {

namespace {

using nlohmann::json;

// The figures in the order they are printed; every one may be an --expect key.
const char* const kFigures[] = {"fillRate",    "planeFitRmsMm",    "planeFitRmsPercent", "dqtPlaneFitRmsMm",
                                "subpixelRms", "zAccuracyPercent", "temporalNoiseMm",    "spatialNoiseMm",
                                "distanceMm",  "angleDeg",         "inlierFraction",     "alignmentPx",
                                "alignmentMm", "frames",           "planeFrames",        "alignmentFrames"};

// A live camera may take a while to deliver its first frame; a source that sends nothing this long failed.
constexpr std::chrono::seconds kNoFrameLimit{10};

struct Expectation {
    std::string text; // as written, for the message
    std::string key;
    std::string op;
    double value = 0.0;
};

std::vector<std::string> split(const std::string& text, char separator) {
    std::vector<std::string> parts;
    std::stringstream in(text);
    for (std::string part; std::getline(in, part, separator);)
        parts.push_back(part);
    return parts;
}

std::optional<double> parseNumber(const std::string& text) {
    std::size_t used = 0;
    try {
        const double v = std::stod(text, &used);
        if (used == text.size() && std::isfinite(v))
            return v;
    } catch (const std::exception&) {
    }
    return std::nullopt;
}

// "key<=value" items separated by commas; the reason when one is malformed.
std::string parseExpectations(const std::string& text, std::vector<Expectation>& out) {
    for (const std::string& item : split(text, ',')) {
        const std::size_t at = item.find_first_of("<>=");
        if (at == std::string::npos || at == 0)
            return "'" + item + "' is not KEY<=VALUE, KEY>=VALUE, KEY<VALUE, KEY>VALUE or KEY==VALUE";
        Expectation e{item, item.substr(0, at), {}, 0.0};
        const bool two = at + 1 < item.size() && item[at + 1] == '=';
        e.op = item.substr(at, two ? 2 : 1);
        if (e.op == "=")
            return "'" + item + "': use == for equality";
        if (std::find(std::begin(kFigures), std::end(kFigures), e.key) == std::end(kFigures))
            return "'" + item + "': unknown figure " + e.key;
        const auto v = parseNumber(item.substr(at + e.op.size()));
        if (!v)
            return "'" + item + "': the value is not a number";
        e.value = *v;
        out.push_back(e);
    }
    return {};
}

bool holds(double got, const Expectation& e) {
    if (e.op == "<=")
        return got <= e.value;
    if (e.op == ">=")
        return got >= e.value;
    if (e.op == "<")
        return got < e.value;
    if (e.op == ">")
        return got > e.value;
    return got == e.value;
}

std::optional<processing::Roi> parseRoi(const std::string& text) {
    const std::vector<std::string> parts = split(text, ',');
    if (parts.size() != 4)
        return std::nullopt;
    int v[4];
    for (int i = 0; i < 4; ++i) {
        const auto n = parseNumber(parts[static_cast<std::size_t>(i)]);
        if (!n || *n != std::floor(*n) || *n < 0 || *n > 1e6)
            return std::nullopt;
        v[i] = static_cast<int>(*n);
    }
    return processing::Roi{v[0], v[1], v[2], v[3]};
}

// "x,y;x,y;..." as at least 3 finite, non-negative vertices; none when it is not such a list.
std::optional<processing::Polygon> parsePolygon(const std::string& text) {
    processing::Polygon polygon;
    for (const std::string& vertex : split(text, ';')) {
        const std::vector<std::string> parts = split(vertex, ',');
        if (parts.size() != 2)
            return std::nullopt;
        const auto x = parseNumber(parts[0]);
        const auto y = parseNumber(parts[1]);
        if (!x || !y || !std::isfinite(*x) || !std::isfinite(*y) || *x < 0 || *y < 0)
            return std::nullopt;
        polygon.push_back({*x, *y});
    }
    if (polygon.size() < 3)
        return std::nullopt;
    return polygon;
}

constexpr const char* kPolygonForm = ": expected at least 3 vertices x,y;x,y;... (depth pixel coordinates)";

json medianOf(std::vector<double> values) {
    if (values.empty())
        return nullptr;
    std::sort(values.begin(), values.end());
    const std::size_t mid = values.size() / 2;
    return values.size() % 2 ? values[mid] : 0.5 * (values[mid - 1] + values[mid]);
}

// Per-frame figures over the run: each reported as its median over the frames that had a plane fit.
struct Collected {
    processing::FillBreakdown fill;
    std::map<std::string, std::vector<double>> figures;
    std::size_t frames = 0;
};

void collect(const processing::FrameQuality& q, Collected& c) {
    c.fill.roiSamples += q.fill.roiSamples;
    c.fill.valid += q.fill.valid;
    c.fill.noMeasurement += q.fill.noMeasurement;
    c.fill.outOfRange += q.fill.outOfRange;
    c.fill.lowConfidence += q.fill.lowConfidence;
    c.fill.flyingPixel += q.fill.flyingPixel;
    ++c.frames;
    if (!q.plane)
        return;
    const processing::PlaneFigures& f = *q.plane;
    c.figures["planeFitRmsMm"].push_back(f.planeFitRmsMm);
    c.figures["planeFitRmsPercent"].push_back(f.planeFitRmsPercent);
    c.figures["dqtPlaneFitRmsMm"].push_back(f.dqtPlaneFitRmsMm);
    c.figures["distanceMm"].push_back(f.distanceMm);
    c.figures["angleDeg"].push_back(f.angleDeg);
    c.figures["inlierFraction"].push_back(f.inlierFraction);
    if (f.subpixelRms)
        c.figures["subpixelRms"].push_back(*f.subpixelRms);
    if (f.expectedNoiseMm)
        c.figures["expectedNoiseMm"].push_back(*f.expectedNoiseMm);
    if (f.zAccuracyPercent)
        c.figures["zAccuracyPercent"].push_back(*f.zAccuracyPercent);
}

json report(const Collected& c, const processing::NoiseWindow& noise, const processing::Roi& roi,
            const processing::Polygon& polygon) {
    json j;
    j["fillRate"] = c.fill.fillRate();
    for (const char* key :
         {"planeFitRmsMm", "planeFitRmsPercent", "dqtPlaneFitRmsMm", "subpixelRms", "expectedNoiseMm",
          "zAccuracyPercent", "distanceMm", "angleDeg", "inlierFraction", "alignmentPx", "alignmentMm"}) {
        const auto it = c.figures.find(key);
        j[key] = it == c.figures.end() ? json(nullptr) : medianOf(it->second);
    }
    const auto temporal = noise.temporalNoiseMm();
    const auto spatial = noise.spatialNoiseMm();
    j["temporalNoiseMm"] = temporal ? json(*temporal) : json(nullptr);
    j["spatialNoiseMm"] = spatial ? json(*spatial) : json(nullptr);
    j["frames"] = c.frames;
    // How many frames each median is over: a frame without a plane (too few samples) or without an alignment
    // score (no colour, no depth edge) adds nothing to those figures.
    const auto framesOf = [&](const char* key) {
        const auto it = c.figures.find(key);
        return it == c.figures.end() ? std::size_t{0} : it->second.size();
    };
    j["planeFrames"] = framesOf("distanceMm");
    j["alignmentFrames"] = framesOf("alignmentPx");
    j["roi"] = {{"x", roi.x}, {"y", roi.y}, {"width", roi.width}, {"height", roi.height}};
    j["roiPolygon"] = polygon.empty() ? json(nullptr) : json(polygon);
    j["roiSamples"] = c.fill.roiSamples;
    json shortfall;
    const std::pair<const char*, std::size_t> causes[] = {{"noMeasurement", c.fill.noMeasurement},
                                                          {"outOfRange", c.fill.outOfRange},
                                                          {"lowConfidence", c.fill.lowConfidence},
                                                          {"flyingPixel", c.fill.flyingPixel}};
    for (const auto& [name, count] : causes)
        shortfall[name] = {{"count", count}, {"fraction", c.fill.fraction(count)}};
    j["shortfall"] = shortfall;
    return j;
}

// The parameters from the options; the reason (naming the argument) when one is bad.
std::string qualityParams(const QualityOptions& o, processing::QualityParams& p) {
    p.nearMeters = static_cast<float>(o.nearMeters);
    p.farMeters = static_cast<float>(o.farMeters);
    if (!(p.nearMeters < p.farMeters))
        return "--near-m must be less than --far-m";
    p.minConfidence = o.confidence == "high"     ? frame::Confidence::High
                      : o.confidence == "medium" ? frame::Confidence::Medium
                                                 : frame::Confidence::Low;
    if (o.groundTruthMm)
        p.groundTruthMeters = *o.groundTruthMm / 1000.0;
    if (o.baselineMm)
        p.baselineMeters = *o.baselineMm / 1000.0;
    p.designSubpixelRms = o.designSubpixelRms;
    return {};
}

struct Capture {
    Collected collected;
    std::optional<processing::NoiseWindow> noise;
    processing::Roi roi;
    processing::Polygon polygon;
    processing::CameraColourTable colourTable; // filled as colours are met, kept across frames
    frame::JpegDecoder jpeg;
};

// The polygon of --roi-polygon and its bounding box as the ROI; the reason if it leaves the depth map.
std::string startWithPolygon(const std::string& text, const frame::Plane<float>& depth,
                             processing::QualityParams& p) {
    const auto polygon = parsePolygon(text);
    if (!polygon)
        return "--roi-polygon " + text + kPolygonForm;
    for (const auto& [x, y] : *polygon) {
        if (x > depth.width || y > depth.height)
            return "--roi-polygon " + text + ": outside the " + std::to_string(depth.width) + "x" +
                   std::to_string(depth.height) + " depth map";
    }
    p.polygon = *polygon;
    p.roi = processing::polygonBounds(*polygon);
    if (!processing::roiInside(p.roi, depth.width, depth.height))
        return "--roi-polygon " + text + ": encloses no pixel";
    return {};
}

// The first frame fixes the ROI (from --roi, --roi-percent or --roi-polygon of its depth map); the reason if
// it cannot.
std::string startWith(const frame::Frame& f, const QualityOptions& o, processing::QualityParams& p,
                      Capture& c) {
    const frame::Plane<float>& depth = f.sceneDepth->depthMeters;
    if (!o.roiPolygon.empty()) {
        if (std::string problem = startWithPolygon(o.roiPolygon, depth, p); !problem.empty())
            return problem;
    } else if (o.roi.empty()) {
        p.roi = processing::centredRoi(depth.width, depth.height, o.roiPercent);
    } else {
        const auto roi = parseRoi(o.roi);
        if (!roi)
            return "--roi " + o.roi + ": expected X,Y,W,H (whole pixels)";
        if (!processing::roiInside(*roi, depth.width, depth.height))
            return "--roi " + o.roi + ": outside the " + std::to_string(depth.width) + "x" +
                   std::to_string(depth.height) + " depth map";
        p.roi = *roi;
    }
    c.roi = p.roi;
    c.polygon = p.polygon;
    c.noise.emplace(p, o.frames);
    return {};
}

// The colour-to-depth alignment of a frame with a camera image over the ROI, per frame like the other
// figures. A frame without an image adds nothing, nor does one without a matched depth edge (a flat target
// has none): the figure is then null rather than a number that measured nothing.
void collectAlignment(const frame::Frame& f, const processing::QualityParams& p, Capture& c) {
    if (f.capturedImage.empty())
        return;
    // Registration reads pixels as captured, so a camera's MJPEG is decoded first (other formats pass as
    // they are); it needs nothing of the frame but the image and the cameras.
    auto image = c.jpeg.decode(f.capturedImage);
    if (!image)
        return;
    frame::Frame colour;
    colour.capturedImage = std::move(*image);
    colour.cameraIntrinsics = f.cameraIntrinsics;
    colour.rig = f.rig;
    const frame::Plane<float>& depth = f.sceneDepth->depthMeters;
    const processing::RgbImage onDepth =
        processing::colourAlignedToDepth(colour, depth, depth.width, depth.height, c.colourTable);
    const auto a = processing::measureEdgeAlignment(depth, onDepth, f.depthIntrinsics(), p.roi, p.polygon);
    if (!a)
        return;
    c.collected.figures["alignmentPx"].push_back(a->medianPx);
    c.collected.figures["alignmentMm"].push_back(a->medianMm);
}

// Captures o.frames frames with depth and measures each; the failure, or a bad --roi (prefixed "--").
std::string capture(devices::Device& device, const QualityOptions& o, processing::QualityParams& p,
                    Capture& c) {
    auto lastFrame = std::chrono::steady_clock::now();
    while (c.collected.frames < static_cast<std::size_t>(o.frames)) {
        const devices::CaptureResult r = device.capture(std::chrono::milliseconds(500));
        if (r.kind == devices::CaptureResult::Kind::EndOfStream)
            break;
        if (r.kind == devices::CaptureResult::Kind::Disconnected ||
            r.kind == devices::CaptureResult::Kind::Error)
            return "the source failed: " + r.message;
        const bool usable = r.kind == devices::CaptureResult::Kind::Frame && r.frame && r.frame->sceneDepth &&
                            !r.frame->sceneDepth->depthMeters.empty();
        if (!usable) {
            if (std::chrono::steady_clock::now() - lastFrame > kNoFrameLimit)
                return "no depth frame from the source for 10 s";
            continue;
        }
        lastFrame = std::chrono::steady_clock::now();
        if (!c.noise) {
            if (std::string problem = startWith(*r.frame, o, p, c); !problem.empty())
                return problem;
        }
        const auto q = processing::measureFrameQuality(*r.frame->sceneDepth, r.frame->depthIntrinsics(), p);
        if (!q)
            return q.error().message;
        collect(*q, c.collected);
        collectAlignment(*r.frame, p, c);
        c.noise->add(*r.frame->sceneDepth, q->causes,
                     q->plane ? std::optional<double>(q->plane->planeFitRmsMm) : std::nullopt);
    }
    if (c.collected.frames == 0)
        return "the source ended before its first depth frame";
    return {};
}

void print(const json& j) {
    for (const char* key : kFigures)
        std::printf("%s %s\n", key, j[key].dump().c_str());
    for (const auto& [name, cause] : j["shortfall"].items())
        std::printf("shortfall.%s %s (%s)\n", name.c_str(), cause["count"].dump().c_str(),
                    cause["fraction"].dump().c_str());
}

// Exit 1 with one line naming the first expectation that does not hold.
int checkExpectations(const json& j, const std::vector<Expectation>& expectations) {
    for (const Expectation& e : expectations) {
        const json& got = j[e.key];
        if (!got.is_number())
            return commandFailed("quality",
                                 "expectation " + e.text + " failed: " + e.key + " was not measured");
        if (!holds(got.get<double>(), e))
            return commandFailed("quality",
                                 "expectation " + e.text + " failed: " + e.key + " = " + got.dump());
    }
    return kExitOk;
}

std::string checkArguments(const QualityOptions& o, std::vector<Expectation>& expectations) {
    if (std::string problem = parseExpectations(o.expect, expectations); !problem.empty())
        return "--expect " + problem;
    if (!o.roi.empty() && !parseRoi(o.roi))
        return "--roi " + o.roi + ": expected X,Y,W,H (whole pixels)";
    if (!o.roiPolygon.empty() && !parsePolygon(o.roiPolygon))
        return "--roi-polygon " + o.roiPolygon + kPolygonForm;
    std::error_code ec;
    if (!o.jsonPath.empty() && !o.overwrite && std::filesystem::exists(o.jsonPath, ec))
        return "--json " + o.jsonPath + " already exists (pass --overwrite to replace it)";
    return {};
}

} // namespace

CLI::App* addQualityCommand(CLI::App& app, QualityOptions& o) {
    CLI::App* cmd = app.add_subcommand(
        "quality", "Depth Quality Tool figures of a flat target (fill rate, plane fit, noise), headless");
    cmd->add_option("--source", o.source, std::string("what to measure: ") + devices::kSourceSpecHelp)
        ->capture_default_str();
    auto* roi = cmd->add_option("--roi", o.roi, "region of interest X,Y,W,H in depth pixels");
    auto* percent = cmd->add_option("--roi-percent", o.roiPercent,
                                    "centred ROI: percent of the depth map's width and height")
                        ->check(CLI::Range(1.0, 100.0))
                        ->excludes(roi)
                        ->capture_default_str();
    cmd->add_option(
           "--roi-polygon", o.roiPolygon,
           "region of interest: the depth pixels whose centres lie inside the polygon \"x,y;x,y;...\" "
           "(depth pixel coordinates, at least 3 vertices)")
        ->excludes(roi)
        ->excludes(percent);
    cmd->add_option("--frames", o.frames, "frames to measure (the temporal noise window)")
        ->check(CLI::Range(1, 100000))
        ->capture_default_str();
    cmd->add_option("--ground-truth-mm", o.groundTruthMm, "the target's true distance: Z accuracy")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--baseline-mm", o.baselineMm, "the stereo baseline: subpixel RMS and expected noise")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--design-subpixel", o.designSubpixelRms,
                    "the camera's design subpixel accuracy (pixels) for the expected noise")
        ->check(CLI::Range(0.001, 10.0))
        ->capture_default_str();
    cmd->add_option("--near-m", o.nearMeters, "samples nearer are out of range")->check(CLI::Range(0.0, 1e9));
    cmd->add_option("--far-m", o.farMeters, "samples farther are out of range")->check(CLI::Range(0.0, 1e9));
    cmd->add_option("--confidence", o.confidence, "lowest confidence counted as valid")
        ->check(CLI::IsMember({"low", "medium", "high"}))
        ->capture_default_str();
    cmd->add_option("--expect", o.expect,
                    "conditions that must hold, e.g. \"fillRate>=0.95,planeFitRmsMm<=2.0\"");
    cmd->add_option("--json", o.jsonPath, "also write the figures as JSON to this file");
    cmd->add_flag("--overwrite", o.overwrite, "replace the --json file if it exists");
    return cmd;
}

int runQuality(const QualityOptions& o) {
    setLogQuiet(true);
    std::vector<Expectation> expectations;
    processing::QualityParams params;
    std::string problem = checkArguments(o, expectations);
    if (problem.empty())
        problem = qualityParams(o, params);
    if (!problem.empty())
        return commandFailed("quality", problem, kExitBadArguments);
    auto device = devices::openSourceSpec(o.source);
    if (!device)
        return commandFailed("quality", "--source: " + device.error().message, kExitBadArguments);
    if (Status s = (*device)->open(); !s)
        return commandFailed("quality", s.error().message);
    if (Status s = (*device)->start(); !s)
        return commandFailed("quality", s.error().message);
    Capture c;
    problem = capture(**device, o, params, c);
    (void)(*device)->stop();
    (*device)->close();
    if (!problem.empty())
        return commandFailed("quality", problem,
                             problem.rfind("--", 0) == 0 ? kExitBadArguments : kExitFailure);
    const json j = report(c.collected, *c.noise, c.roi, c.polygon);
    print(j);
    if (!o.jsonPath.empty()) {
        if (Status s = base::writeTextFile(o.jsonPath, j.dump(2) + "\n"); !s)
            return commandFailed("quality", "--json " + o.jsonPath + ": " + s.error().message);
    }
    return checkExpectations(j, expectations);
}

} // namespace dc::tool
