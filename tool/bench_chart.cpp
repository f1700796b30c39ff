// The error-versus-time chart of `depthcloud bench upsample`: one panel per scene group, a log time axis,
// one labelled marker per method, so the Pareto front (down and to the left) shows at a glance.

#include "devices/image_io.h"
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

Axes axesFor(const ChartPanel& panel, cv::Rect area) {
    double lo = 1e9, hi = 1e-9, errorMax = 1e-9;
    for (const ChartPoint& p : panel.points) {
        lo = std::min(lo, p.milliseconds);
        hi = std::max(hi, p.milliseconds);
        errorMax = std::max(errorMax, p.error);
    }
    const double logMin = std::floor(std::log10(std::max(lo, 1e-3)));
    const double logMax = std::max(std::ceil(std::log10(std::max(hi, 1e-3))), logMin + 1.0);
    return {logMin, logMax, errorMax * 1.15, area};
}

void drawAxes(cv::Mat& image, const Axes& axes, const ChartPanel& panel) {
    for (double decade = axes.logMin; decade <= axes.logMax + 1e-9; decade += 1.0) {
        const int x = axes.at(std::pow(10.0, decade), 0.0).x;
        cv::line(image, {x, axes.area.y}, {x, axes.area.y + axes.area.height}, kGrid);
        char label[32];
        std::snprintf(label, sizeof label, "%g", std::pow(10.0, decade));
        cv::putText(image, label, {x - 10, axes.area.y + axes.area.height + 20}, kFont, 0.45, kInk);
    }
    for (int i = 0; i <= 5; ++i) {
        const double e = axes.errorMax * i / 5.0;
        const int y = axes.at(1.0, e).y;
        cv::line(image, {axes.area.x, y}, {axes.area.x + axes.area.width, y}, kGrid);
        char label[32];
        std::snprintf(label, sizeof label, "%.2f", e);
        cv::putText(image, label, {axes.area.x - 55, y + 5}, kFont, 0.45, kInk);
    }
    cv::rectangle(image, axes.area, kInk);
    cv::putText(image, panel.title, {axes.area.x, 30}, kFont, 0.6, kInk, 1, cv::LINE_AA);
    cv::putText(image, "median time per frame, ms (log)",
                {axes.area.x + axes.area.width / 2 - 130, kPanelHeight - 12}, kFont, 0.5, kInk, 1,
                cv::LINE_AA);
    cv::putText(image, panel.errorLabel, {8, axes.area.y - 10}, kFont, 0.5, kInk, 1, cv::LINE_AA);
}

void drawPanel(cv::Mat& image, const ChartPanel& panel) {
    const Axes axes =
        axesFor(panel, {kLeft, kTop, kPanelWidth - kLeft - kRight, kPanelHeight - kTop - kBottom});
    drawAxes(image, axes, panel);
    std::vector<cv::Rect> labels; // placed labels, so later ones move down instead of overprinting
    for (const ChartPoint& p : panel.points) {
        const cv::Point c = axes.at(p.milliseconds, p.error);
        cv::circle(image, c, 6, colorOf(p.label), cv::FILLED, cv::LINE_AA);
        int baseline = 0;
        const cv::Size size = cv::getTextSize(p.label, kFont, 0.42, 1, &baseline);
        cv::Rect box(c.x + 9, c.y - size.height / 2 - 2, size.width, size.height + 4);
        if (box.x + box.width > image.cols - 2)
            box.x = c.x - 9 - size.width;
        while (std::any_of(labels.begin(), labels.end(),
                           [&](const cv::Rect& r) { return (r & box).area() > 0; }))
            box.y += size.height + 2;
        labels.push_back(box);
        cv::putText(image, p.label, {box.x, box.y + size.height + 1}, kFont, 0.42, colorOf(p.label), 1,
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
    return devices::writeRgbaPng(path, rgba.cols, rgba.rows, rgba.ptr<std::uint8_t>(0));
}

} // namespace dc::tool::upsample
