#include "render/colormap.h"

#include <cstdio>

#include <algorithm>
#include <cmath>

namespace dc::render {

namespace {

// One channel: 1 within 1/8 of `centre`, falling linearly to 0 at 3/8 from it.
float trapezoid(float t, float centre) {
    return std::clamp(1.5f - std::abs(4.0f * (t - centre)), 0.0f, 1.0f);
}

template <class F> ColormapStops sampled(F color) {
    ColormapStops stops{};
    for (int i = 0; i < kColormapStopCount; ++i)
        stops[static_cast<std::size_t>(i)] = color(static_cast<float>(i) / (kColormapStopCount - 1));
    return stops;
}

// Turbo (Mikhailov, Google 2019) sampled at sixteenths; viridis (matplotlib) at eighths, interpolated to
// sixteenths, which stays within a few 8-bit steps of the published tables.
constexpr ColormapStops kTurbo{{{0.136f, 0.091f, 0.107f},
                                {0.288f, 0.244f, 0.686f},
                                {0.269f, 0.415f, 0.935f},
                                {0.197f, 0.586f, 0.970f},
                                {0.148f, 0.740f, 0.881f},
                                {0.162f, 0.866f, 0.733f},
                                {0.250f, 0.953f, 0.573f},
                                {0.401f, 0.993f, 0.428f},
                                {0.589f, 0.982f, 0.313f},
                                {0.777f, 0.921f, 0.231f},
                                {0.932f, 0.814f, 0.177f},
                                {1.000f, 0.670f, 0.142f},
                                {1.000f, 0.502f, 0.114f},
                                {0.935f, 0.329f, 0.084f},
                                {0.786f, 0.175f, 0.047f},
                                {0.632f, 0.070f, 0.006f},
                                {0.566f, 0.050f, 0.000f}}};

constexpr std::array<std::array<float, 3>, 9> kViridisEighths{{{0.267f, 0.005f, 0.329f},
                                                               {0.283f, 0.141f, 0.458f},
                                                               {0.231f, 0.322f, 0.546f},
                                                               {0.164f, 0.471f, 0.558f},
                                                               {0.129f, 0.567f, 0.551f},
                                                               {0.135f, 0.659f, 0.518f},
                                                               {0.369f, 0.789f, 0.383f},
                                                               {0.678f, 0.865f, 0.190f},
                                                               {0.993f, 0.906f, 0.144f}}};

ColormapStops viridis() {
    ColormapStops stops{};
    for (std::size_t i = 0; i < stops.size(); ++i) {
        const auto& a = kViridisEighths[i / 2];
        const auto& b = kViridisEighths[std::min(i / 2 + 1, kViridisEighths.size() - 1)];
        for (std::size_t c = 0; c < 3; ++c)
            stops[i][c] = i % 2 == 0 ? a[c] : 0.5f * (a[c] + b[c]);
    }
    return stops;
}

} // namespace

std::array<float, 3> jetColor(float normalised) {
    const float t = normalised > 0.0f ? std::min(normalised, 1.0f) : 0.0f;
    return {trapezoid(t, 0.75f), trapezoid(t, 0.5f), trapezoid(t, 0.25f)};
}

const char* toString(Colormap colormap) {
    switch (colormap) {
    case Colormap::Jet:
        return "jet";
    case Colormap::Turbo:
        return "turbo";
    case Colormap::Viridis:
        return "viridis";
    case Colormap::Grayscale:
        return "grayscale";
    }
    return "jet";
}

const ColormapStops& colormapStops(Colormap colormap) {
    static const ColormapStops jet = sampled(jetColor);
    static const ColormapStops viridisStops = viridis();
    static const ColormapStops gray = sampled([](float t) { return std::array<float, 3>{t, t, t}; });
    switch (colormap) {
    case Colormap::Turbo:
        return kTurbo;
    case Colormap::Viridis:
        return viridisStops;
    case Colormap::Grayscale:
        return gray;
    case Colormap::Jet:
        break;
    }
    return jet;
}

std::array<float, 3> colormapColor(Colormap colormap, float normalised) {
    const ColormapStops& stops = colormapStops(colormap);
    const float x = (normalised > 0.0f ? std::min(normalised, 1.0f) : 0.0f) * (kColormapStopCount - 1);
    const int i = std::min(static_cast<int>(x), kColormapStopCount - 2);
    const float f = x - static_cast<float>(i);
    const auto& a = stops[static_cast<std::size_t>(i)];
    const auto& b = stops[static_cast<std::size_t>(i) + 1];
    return {a[0] + (b[0] - a[0]) * f, a[1] + (b[1] - a[1]) * f, a[2] + (b[2] - a[2]) * f};
}

std::string colormapGlsl(Colormap colormap) {
    std::string glsl = "\nconst vec3 colormapStops[17] = vec3[](";
    char stop[96];
    const ColormapStops& stops = colormapStops(colormap);
    for (std::size_t i = 0; i < stops.size(); ++i) {
        // Nine significant digits: the float each stop is on the CPU, exactly.
        std::snprintf(stop, sizeof stop, "%svec3(%.9g, %.9g, %.9g)", i == 0 ? "" : ", ", stops[i][0],
                      stops[i][1], stops[i][2]);
        glsl += stop;
    }
    return glsl + R"glsl();
vec3 colormapColor(float normalised) {
    float x = (normalised > 0.0 ? min(normalised, 1.0) : 0.0) * 16.0;
    int i = min(int(x), 15);
    return mix(colormapStops[i], colormapStops[i + 1], x - float(i));
}
)glsl";
}

} // namespace dc::render
