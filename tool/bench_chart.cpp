// The error-versus-time chart of `depthcloud bench upsample`: one panel per scene group, a log time axis,
// one labelled marker per method, so the Pareto front (down and to the left) shows at a glance.

#include "frame/image_io.h"
#include "tool/bench_upsample.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace dc::tool::upsample {

namespace {

constexpr int kPanelWidth = 760, kPanelHeight = 560;
constexpr int kLeft = 70, kRight = 30, kTop = 50, kBottom = 55;
const cv::Scalar kInk(40, 40, 40), kGrid(225, 225, 225);
constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;

cv::Scalar colorOf(const std::string& method) {
    if (method.rfind("ours", 0) == 0)
        return method.find("He") != std::string::npos ? cv::Scalar(200, 120, 0) : cv::Scalar(180, 60, 0);
    if (method.rfind("opencv", 0) == 0)
        return {30, 30, 210};
    return {130, 130, 130};
}

struct Axes {
    double logMin, logMax, errorMax;
    cv::Rect area;

    cv::Point at(double ms, double error) const {
        const double fx = (std::log10(std::max(ms, 1e-3)) - logMin) / (logMax - logMin);
        const double fy = error / errorMax;
        return {area.x + static_cast<int>(fx * area.width),
                area.y + area.height - static_cast<int>(fy * area.height)};
    }
};

// 1, 2 or 5 times a power of ten, about a fifth of `range`.
double niceStep(double range) {
    const double raw = range / 5.0, decade = std::pow(10.0, std::floor(std::log10(raw)));
    for (double m : {1.0, 2.0, 5.0})
        if (m * decade >= raw)
            return m * decade;
    return 10.0 * decade;
}

Axes axesFor(const ChartPanel& panel, cv::Rect area) {
    double lo = 1e9, hi = 1e-9, errorMax = 1e-9;
    for (const ChartPoint& p : panel.points) {
        lo = std::min(lo, p.milliseconds);
        hi = std::max(hi, p.milliseconds);
        errorMax = std::max(errorMax, p.error);
    }
    const double logMin = std::floor(std::log10(std::max(lo, 1e-3)));
    const double logMax = std::max(std::ceil(std::log10(std::max(hi, 1e-3))), logMin + 1.0);
    const double step = niceStep(errorMax * 1.1);
    return {logMin, logMax, std::ceil(errorMax * 1.1 / step) * step, area};
}

void drawAxes(cv::Mat& image, const Axes& axes, const ChartPanel& panel) {
    for (double decade = axes.logMin; decade <= axes.logMax + 1e-9; decade += 1.0) {
        const int x = axes.at(std::pow(10.0, decade), 0.0).x;
        cv::line(image, {x, axes.area.y}, {x, axes.area.y + axes.area.height}, kGrid);
        char label[32];
        std::snprintf(label, sizeof label, "%g", std::pow(10.0, decade));
        cv::putText(image, label, {x - 10, axes.area.y + axes.area.height + 20}, kFont, 0.45, kInk);
    }
    const double step = niceStep(axes.errorMax);
    for (double e = 0.0; e <= axes.errorMax + 1e-9; e += step) {
        const int y = axes.at(1.0, e).y;
        cv::line(image, {axes.area.x, y}, {axes.area.x + axes.area.width, y}, kGrid);
        char label[32];
        std::snprintf(label, sizeof label, "%g", e);
        cv::putText(image, label, {axes.area.x - 45, y + 5}, kFont, 0.45, kInk);
    }
    cv::rectangle(image, axes.area, kInk);
    cv::putText(image, panel.title + "  (" + panel.errorLabel + " against time)", {axes.area.x, 30}, kFont,
                0.55, kInk, 1, cv::LINE_AA);
    cv::putText(image, "median time per frame, ms (log)",
                {axes.area.x + axes.area.width / 2 - 130, kPanelHeight - 12}, kFont, 0.5, kInk, 1,
                cv::LINE_AA);
}

bool overlaps(const std::vector<cv::Rect>& taken, const cv::Rect& box, const cv::Rect& area) {
    return (box & area) != box ||
           std::any_of(taken.begin(), taken.end(), [&](const cv::Rect& r) { return (r & box).area() > 0; });
}

// The label's place: beside its marker if free, else above or below it, else further out with a leader.
cv::Rect placeLabel(const cv::Point c, cv::Size text, const std::vector<cv::Rect>& taken,
                    const cv::Rect& area) {
    const int h = text.height + 4;
    for (int distance = 0; distance < 6; ++distance)
        for (int side : {1, -1})
            for (int row : {0, -1, 1}) {
                const int dy = row * (h + 2) * (distance + 1) - h / 2;
                const cv::Rect box(side > 0 ? c.x + 9 + 20 * distance : c.x - 9 - 20 * distance - text.width,
                                   c.y + dy, text.width, h);
                if (!overlaps(taken, box, area))
                    return box;
            }
    return {c.x + 9, c.y - h / 2, text.width, h};
}

void drawPanel(cv::Mat& image, const ChartPanel& panel) {
    const Axes axes =
        axesFor(panel, {kLeft, kTop, kPanelWidth - kLeft - kRight, kPanelHeight - kTop - kBottom});
    drawAxes(image, axes, panel);
    std::vector<cv::Rect> taken; // markers and placed labels
    for (const ChartPoint& p : panel.points) {
        const cv::Point c = axes.at(p.milliseconds, p.error);
        taken.emplace_back(c.x - 7, c.y - 7, 15, 15);
    }
    for (const ChartPoint& p : panel.points) {
        const cv::Point c = axes.at(p.milliseconds, p.error);
        cv::circle(image, c, 6, colorOf(p.label), cv::FILLED, cv::LINE_AA);
        int baseline = 0;
        const cv::Size text = cv::getTextSize(p.label, kFont, 0.42, 1, &baseline);
        const cv::Rect box = placeLabel(c, text, taken, axes.area);
        taken.push_back(box);
        const cv::Point anchor(box.x < c.x ? box.x + box.width : box.x, box.y + box.height / 2);
        if (std::abs(anchor.x - c.x) > 12 || std::abs(anchor.y - c.y) > 8)
            cv::line(image, c, anchor, colorOf(p.label), 1, cv::LINE_AA);
        cv::putText(image, p.label, {box.x, box.y + text.height + 1}, kFont, 0.42, colorOf(p.label), 1,
                    cv::LINE_AA);
    }
}

} // namespace

Status writeChart(const std::string& path, const std::vector<ChartPanel>& panels) {
    cv::Mat image(kPanelHeight, kPanelWidth * static_cast<int>(std::max<std::size_t>(panels.size(), 1)),
                  CV_8UC3, cv::Scalar(255, 255, 255));
    for (std::size_t i = 0; i < panels.size(); ++i) {
        cv::Mat panel = image(cv::Rect(static_cast<int>(i) * kPanelWidth, 0, kPanelWidth, kPanelHeight));
        drawPanel(panel, panels[i]);
    }
    cv::Mat rgba;
    cv::cvtColor(image, rgba, cv::COLOR_BGR2RGBA);
    return frame::writeRgbaPng(path, rgba.cols, rgba.rows, rgba.ptr<std::uint8_t>(0));
}

} // namespace dc::tool::upsample
