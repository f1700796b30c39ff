// Several sources at once, headless: each source's points placed in one world by its pose (pose=, a Kalibr
// camchain's cameras, a synthetic camera's place in its scene) and written as one cloud.ply, source after
// source; each source's panels in a folder of its own; each source's frames counted on their own in
// summary.json, with its overlap figure against the first source. `depthcloud export` given several
// recordings: one PLY per frame of the first, each further recording's frame nearest in time placed beside
// it.

#include "tool_in_temp_dir.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <regex>
#include <string>
#include <tuple>
#include <vector>

namespace {

using dc::test::readFile;
using dc::test::RunResult;
using Point = std::array<float, 3>;

// Camera A where the synthetic camera usually stands; B 20 cm to its right, turned 8 degrees back towards
// it (as the align tests place them).
const std::string kA = "synthetic:320x240";
const std::string kB = "synthetic:320x240:view=0.2,0,0,0,-0.0697564737441253,0,0.9975640502598242";
// 3 degrees about the skew axis (1, 2, -1) and (2, -2, 1) cm: a wrong placement of B.
const std::string kError =
    "pose=0.02,-0.02,0.01,0.010686694396250128,0.021373388792500257,-0.010686694396250128,0.9996573249755573";

// cloud.ply's points, split by source as its comments count them ("N points of SPEC").
std::vector<std::vector<Point>> plySources(const std::string& bytes) {
    const std::string end = "end_header\n";
    const auto body = bytes.find(end);
    if (body == std::string::npos)
        return {};
    std::vector<std::size_t> counts;
    const std::string header = bytes.substr(0, body);
    const std::regex comment("comment (\\d+) points of ");
    for (auto it = std::sregex_iterator(header.begin(), header.end(), comment); it != std::sregex_iterator();
         ++it)
        counts.push_back(std::stoul((*it)[1]));
    std::vector<std::vector<Point>> sources;
    std::size_t at = body + end.size();
    for (std::size_t n : counts) {
        std::vector<Point> points(n);
        for (std::size_t i = 0; i < n && at + 16 <= bytes.size(); ++i, at += 16)
            std::memcpy(points[i].data(), bytes.data() + at, 12);
        sources.push_back(std::move(points));
    }
    return sources;
}

// The median distance from each of `points` to the nearest of `to` (a 2 cm grid searched one cell around, so
// at least 2 cm):
// how far one source's points lie from the other's, with no knowledge of how either was placed.
double medianNearestMm(const std::vector<Point>& points, const std::vector<Point>& to) {
    constexpr float kCell = 0.02f;
    using Key = std::tuple<int, int, int>;
    const auto key = [](const Point& p) {
        return Key{static_cast<int>(std::floor(p[0] / kCell)), static_cast<int>(std::floor(p[1] / kCell)),
                   static_cast<int>(std::floor(p[2] / kCell))};
    };
    std::map<Key, std::vector<Point>> grid;
    for (const Point& p : to)
        grid[key(p)].push_back(p);
    std::vector<double> nearest;
    for (std::size_t i = 0; i < points.size(); i += 7) {
        const auto [x, y, z] = key(points[i]);
        double best = kCell;
        for (int dx = -1; dx <= 1; ++dx)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dz = -1; dz <= 1; ++dz) {
                    const auto cell = grid.find({x + dx, y + dy, z + dz});
                    if (cell == grid.end())
                        continue;
                    for (const Point& q : cell->second)
                        best = std::min(best, std::hypot(static_cast<double>(q[0] - points[i][0]),
                                                         static_cast<double>(q[1] - points[i][1]),
                                                         static_cast<double>(q[2] - points[i][2])));
                }
        nearest.push_back(best);
    }
    if (nearest.empty())
        return 1e9;
    std::nth_element(nearest.begin(), nearest.begin() + static_cast<std::ptrdiff_t>(nearest.size() / 2),
                     nearest.end());
    return 1000.0 * nearest[nearest.size() / 2];
}

class Sources : public dc::test::ToolInTempDir {
protected:
    // A headless run of `sources` into out/; its summary.json, or null when the run failed.
    nlohmann::json run(const std::vector<std::string>& sources, int frames = 8) {
        std::filesystem::remove_all(dir_ / "out");
        std::string arguments = "--headless --out out --frames " + std::to_string(frames);
        for (const std::string& s : sources)
            arguments += " --source \"" + s + "\"";
        const RunResult r = runTool(arguments);
        EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
        return r.exitCode == 0 ? nlohmann::json::parse(readFile(dir_ / "out/summary.json"))
                               : nlohmann::json();
    }
};

TEST_F(Sources, TwoCamerasAtTheirTruePlacesFuseWhereTheySeeTheSameSurfaces) {
    const nlohmann::json truth = run({kA, kB});
    ASSERT_FALSE(truth.is_null());
    ASSERT_EQ(truth["companions"].size(), 1u);
    const nlohmann::json& overlap = truth["companions"][0]["overlap"];
    // The synthetic desk's depth noise is 1 mm + 1.5 mm per m^2 of depth (about 4.4 mm at 1.5 m): two noisy
    // maps agree within it over most of A's samples.
    EXPECT_GT(overlap["medianMm"].get<double>(), 0.3) << overlap;
    EXPECT_LT(overlap["medianMm"].get<double>(), 1.5 * 4.4) << overlap;
    EXPECT_GT(overlap["overlapFraction"].get<double>(), 0.6) << overlap;
    const auto placed = plySources(readFile(dir_ / "out/cloud.ply"));
    ASSERT_EQ(placed.size(), 2u);
    ASSERT_GT(placed[1].size(), 10'000u);
    const double truthMm = medianNearestMm(placed[1], placed[0]);
    // Nearest neighbours of two noisy samplings of one surface: about the noise, ~4.4 mm at 1.5 m.
    EXPECT_LT(truthMm, 1.5 * 4.4);

    // B's pose 3 degrees and 3 cm off: the figure and the points both say so.
    const nlohmann::json wrong = run({kA, kB + ":" + kError});
    ASSERT_FALSE(wrong.is_null());
    EXPECT_GT(wrong["companions"][0]["overlap"]["medianMm"].get<double>(),
              2.0 * overlap["medianMm"].get<double>());
    const auto misplaced = plySources(readFile(dir_ / "out/cloud.ply"));
    ASSERT_EQ(misplaced.size(), 2u);
    EXPECT_GT(medianNearestMm(misplaced[1], misplaced[0]), 2.0 * truthMm);
}

// A row-major rotation about z by `degrees` and a translation: a camera's placement.
struct Placement {
    std::array<double, 9> r;
    std::array<double, 3> t;
    Point apply(const Point& p) const {
        Point out;
        for (int i = 0; i < 3; ++i)
            out[i] = static_cast<float>(r[3 * i] * p[0] + r[3 * i + 1] * p[1] + r[3 * i + 2] * p[2] + t[i]);
        return out;
    }
};
Placement aboutY(double degrees, std::array<double, 3> t) {
    const double a = degrees * M_PI / 180.0;
    return {{std::cos(a), 0, std::sin(a), 0, 1, 0, -std::sin(a), 0, std::cos(a)}, t};
}
// a * b
Placement compose(const Placement& a, const Placement& b) {
    Placement out{};
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k)
                out.r[3 * i + j] += a.r[3 * i + k] * b.r[3 * k + j];
        out.t[i] = a.t[i];
        for (int k = 0; k < 3; ++k)
            out.t[i] += a.r[3 * i + k] * b.t[k];
    }
    return out;
}
Placement inverse(const Placement& p) {
    Placement out{};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            out.r[3 * i + j] = p.r[3 * j + i];
    for (int i = 0; i < 3; ++i)
        out.t[i] = -(out.r[3 * i] * p.t[0] + out.r[3 * i + 1] * p.t[1] + out.r[3 * i + 2] * p.t[2]);
    return out;
}
std::string matrixRows(const Placement& p) {
    char text[400];
    std::snprintf(text, sizeof text,
                  "  - [%.12f, %.12f, %.12f, %.12f]\n  - [%.12f, %.12f, %.12f, %.12f]\n"
                  "  - [%.12f, %.12f, %.12f, %.12f]\n  - [0.0, 0.0, 0.0, 1.0]\n",
                  p.r[0], p.r[1], p.r[2], p.t[0], p.r[3], p.r[4], p.r[5], p.t[1], p.r[6], p.r[7], p.r[8],
                  p.t[2]);
    return text;
}

TEST_F(Sources, AKalibrCamchainWithThreeCamerasPlacesThreeSourcesAsItSays) {
    // Three cameras in the rig's frame (cam0's): cam1 10 cm right and turned 5 degrees, cam2 30 cm right
    // and turned -10 degrees. Kalibr chains them: cam_k's T_cn_cnm1 takes cam_(k-1)'s points into cam_k's
    // frame, i.e. inverse(placement_k) * placement_(k-1).
    const Placement p0 = aboutY(0, {0, 0, 0});
    const Placement p1 = aboutY(5, {0.1, 0, 0});
    const Placement p2 = aboutY(-10, {0.3, 0.01, -0.02});
    const std::string intrinsics = "  camera_model: pinhole\n  intrinsics: [300.0, 300.0, 160.0, 120.0]\n"
                                   "  distortion_model: radtan\n  distortion_coeffs: [0.0, 0.0, 0.0, 0.0]\n"
                                   "  resolution: [320, 240]\n";
    std::ofstream(dir_ / "camchain.yaml") << "cam0:\n"
                                          << intrinsics << "cam1:\n"
                                          << intrinsics << "  T_cn_cnm1:\n"
                                          << matrixRows(compose(inverse(p1), p0)) << "cam2:\n"
                                          << intrinsics << "  T_cn_cnm1:\n"
                                          << matrixRows(compose(inverse(p2), p1));
    // The same still, noise-free camera three times: each source's points are the first's, moved by
    // where the camchain puts its camera relative to cam0.
    const std::string exact = "synthetic:320x240:exact:pose=camchain.yaml#cam";
    const nlohmann::json j = run({exact + "0", exact + "1", exact + "2"}, 4);
    ASSERT_FALSE(j.is_null());
    ASSERT_EQ(j["companions"].size(), 2u);
    const auto sources = plySources(readFile(dir_ / "out/cloud.ply"));
    ASSERT_EQ(sources.size(), 3u);
    const Placement placements[] = {p0, p1, p2};
    for (std::size_t k = 1; k < 3; ++k) {
        ASSERT_EQ(sources[k].size(), sources[0].size());
        const Placement move = compose(placements[k], inverse(p0));
        double worst = 0.0;
        for (std::size_t i = 0; i < sources[0].size(); ++i) {
            const Point want = move.apply(sources[0][i]);
            for (int a = 0; a < 3; ++a)
                worst = std::max(worst, std::abs(static_cast<double>(want[a] - sources[k][i][a])));
        }
        EXPECT_LT(worst, 1e-4) << "source " << k + 1;
    }
    for (const char* file : {"cloud.png", "depth.png", "source-2/depth.png", "source-3/depth.png",
                             "source-3/confidence.png", "source-3/camera.png"})
        EXPECT_TRUE(std::filesystem::exists(dir_ / "out" / file)) << file;
}

TEST_F(Sources, EachSourceCountsItsOwnFrames) {
    // A replay of exactly 12 frames beside the live synthetic camera: its own count says 12 delivered, and
    // every one of them shown or dropped once it has ended.
    const RunResult rec = runTool("record --source synthetic:64x48@60 --frames 12 twelve.dcrec");
    ASSERT_EQ(rec.exitCode, 0) << rec.out << rec.err;
    const nlohmann::json j = run({"synthetic:160x120@30", "replay:twelve.dcrec"}, 30);
    ASSERT_FALSE(j.is_null());
    const nlohmann::json& replay = j["companions"][0];
    EXPECT_EQ(replay["framesDelivered"].get<int>(), 12) << replay;
    EXPECT_EQ(replay["frames"].get<int>() + replay["framesDropped"].get<int>(), 12) << replay;
    EXPECT_GE(replay["frames"].get<int>(), 1) << replay;
    EXPECT_EQ(replay["depthWidth"].get<int>(), 64);
    // The main source's own figures still add up, and are not the replay's.
    const int main = j["frames"].get<int>() + j["framesDropped"].get<int>();
    EXPECT_LE(main, j["framesDelivered"].get<int>());
    EXPECT_GE(main + 3, j["framesDelivered"].get<int>());
    EXPECT_EQ(j["frames"].get<int>(), 30);
}

TEST_F(Sources, ASecondSourceThatCannotOpenIsABadArgumentNamingIt) {
    const RunResult r =
        runTool("--headless --out out --source synthetic --source synthetic:320x240:view=1,2");
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(r.err.find("--source: synthetic:320x240:view=1,2"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir_ / "out/summary.json"));
}

// The number that `pattern`'s one group matches in a PLY's header; -1 when it matches nothing.
long long headerNumber(const std::string& bytes, const std::string& pattern) {
    const std::string header = bytes.substr(0, bytes.find("end_header\n"));
    std::smatch match;
    if (!std::regex_search(header, match, std::regex(pattern)))
        return -1;
    return std::stoll(match[1]);
}

std::vector<std::filesystem::path> filesIn(const std::filesystem::path& directory) {
    std::vector<std::filesystem::path> files;
    for (const auto& entry : std::filesystem::directory_iterator(directory))
        files.push_back(entry.path());
    std::sort(files.begin(), files.end());
    return files;
}

std::string plyName(long long index) {
    char name[32];
    std::snprintf(name, sizeof name, "%06lld.ply", index);
    return name;
}

TEST_F(Sources, ExportFusesTwoRecordingsInTheWorldFrame) {
    for (const auto& [spec, file] : {std::pair{kA, "a.dcrec"}, std::pair{kB, "b.dcrec"}}) {
        const RunResult r = runTool("record --source \"" + spec + "\" --frames 4 " + file);
        ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
    }
    // Each alone first: its valid points in each frame.
    for (const std::string name : {"a", "b"}) {
        const RunResult r = runTool("export --source replay:" + name + ".dcrec --out alone-" + name);
        ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
    }
    const RunResult fused = runTool("export --source replay:a.dcrec --source replay:b.dcrec --out fused");
    ASSERT_EQ(fused.exitCode, 0) << fused.out << fused.err;
    EXPECT_NE(fused.out.find("wrote 4 frames as ply, 2 sources fused"), std::string::npos) << fused.out;
    const auto files = filesIn(dir_ / "fused");
    ASSERT_EQ(files.size(), 4u);
    double truthMm = 0.0;
    for (std::size_t i = 0; i < files.size(); ++i) {
        const std::string bytes = readFile(files[i]);
        EXPECT_EQ(files[i].filename(), plyName(static_cast<long long>(i)));
        const long long b = headerNumber(bytes, "comment frame (\\d+) of replay:b\\.dcrec,");
        ASSERT_GE(b, 0) << files[i];
        const long long pointsA = headerNumber(
            readFile(dir_ / "alone-a" / plyName(static_cast<long long>(i))), "element vertex (\\d+)");
        const long long pointsB =
            headerNumber(readFile(dir_ / "alone-b" / plyName(b)), "element vertex (\\d+)");
        ASSERT_GT(pointsA, 10'000);
        ASSERT_GT(pointsB, 10'000);
        EXPECT_EQ(headerNumber(bytes, "comment (\\d+) points of replay:a\\.dcrec\n"), pointsA);
        EXPECT_EQ(headerNumber(bytes, "comment (\\d+) points of replay:b\\.dcrec\n"), pointsB);
        EXPECT_EQ(headerNumber(bytes, "element vertex (\\d+)"), pointsA + pointsB);
        const auto placed = plySources(bytes);
        ASSERT_EQ(placed.size(), 2u);
        // Nearest neighbours of two noisy samplings of one surface: about the noise, ~4.4 mm at 1.5 m.
        truthMm = std::max(truthMm, medianNearestMm(placed[1], placed[0]));
    }
    EXPECT_LT(truthMm, 1.5 * 4.4);

    // B's pose= 3 degrees and 3 cm off, after its recorded pose as the window applies it: its points leave
    // A's.
    const RunResult wrong =
        runTool("export --source replay:a.dcrec --source \"replay:b.dcrec:" + kError + "\" --out wrong");
    ASSERT_EQ(wrong.exitCode, 0) << wrong.out << wrong.err;
    const auto misplaced = plySources(readFile(dir_ / "wrong/000000.ply"));
    ASSERT_EQ(misplaced.size(), 2u);
    EXPECT_GT(medianNearestMm(misplaced[1], misplaced[0]), 2.0 * truthMm);
}

TEST_F(Sources, ExportPairsEachFrameWithTheFurtherSourcesFrameNearestInTime) {
    // A at 30 fps, then B at 10 fps: one after the other, so their spans do not overlap and they pair by
    // time since each one's first frame, as the window pairs them. Moving cameras: every frame differs.
    ASSERT_EQ(runTool("record --source synthetic:160x120@30:motion --frames 9 a.dcrec").exitCode, 0);
    ASSERT_EQ(runTool("record --source synthetic:160x120@10:motion --frames 4 b.dcrec").exitCode, 0);
    ASSERT_EQ(runTool("export --source replay:a.dcrec --out alone-a").exitCode, 0);
    ASSERT_EQ(runTool("export --source replay:b.dcrec --world --out alone-b").exitCode, 0);
    const RunResult fused = runTool("export --source replay:a.dcrec --source replay:b.dcrec --out fused");
    ASSERT_EQ(fused.exitCode, 0) << fused.out << fused.err;
    const auto timestamps = [this](const std::string& directory) {
        std::vector<long long> t;
        for (const auto& file : filesIn(dir_ / directory))
            t.push_back(headerNumber(readFile(file), "timestamp (\\d+) ns"));
        return t;
    };
    const std::vector<long long> a = timestamps("alone-a"), b = timestamps("alone-b");
    ASSERT_EQ(a.size(), 9u);
    ASSERT_EQ(b.size(), 4u);
    ASSERT_LT(a.back(), b.front()) << "the recordings overlap";
    bool differsFromIndex = false;
    for (std::size_t i = 0; i < a.size(); ++i) {
        std::size_t nearest = 0;
        for (std::size_t k = 1; k < b.size(); ++k)
            if (std::llabs((b[k] - b[0]) - (a[i] - a[0])) < std::llabs((b[nearest] - b[0]) - (a[i] - a[0])))
                nearest = k;
        differsFromIndex |= nearest != std::min<std::size_t>(i, b.size() - 1);
        const std::string bytes = readFile(dir_ / "fused" / plyName(static_cast<long long>(i)));
        EXPECT_EQ(headerNumber(bytes, "comment frame (\\d+) of replay:b\\.dcrec,"),
                  static_cast<long long>(nearest))
            << "frame " << i;
        // The points written are that frame's: B's export alone, in the world through its recorded pose.
        const auto written = plySources(bytes);
        ASSERT_EQ(written.size(), 2u);
        const std::string aloneBytes = readFile(dir_ / "alone-b" / plyName(static_cast<long long>(nearest)));
        ASSERT_EQ(static_cast<long long>(written[1].size()),
                  headerNumber(aloneBytes, "element vertex (\\d+)"));
        const std::size_t body = aloneBytes.find("end_header\n") + 11;
        double worst = 0.0;
        for (std::size_t p = 0; p < written[1].size(); ++p) {
            Point q;
            std::memcpy(q.data(), aloneBytes.data() + body + 16 * p, 12);
            for (int c = 0; c < 3; ++c)
                worst = std::max(worst, std::abs(static_cast<double>(q[c] - written[1][p][c])));
        }
        EXPECT_LT(worst, 1e-5) << "frame " << i;
    }
    EXPECT_TRUE(differsFromIndex) << "the test's rates pair no frame differently from its index";
}

TEST_F(Sources, ExportOfSeveralSourcesWritesPlyOnlyAndNamesASourceThatCannotOpen) {
    ASSERT_EQ(runTool("record --source synthetic:64x48 --frames 2 a.dcrec").exitCode, 0);
    const RunResult png =
        runTool("export --source replay:a.dcrec --source replay:a.dcrec --format png16 --out x");
    EXPECT_EQ(png.exitCode, 2);
    EXPECT_EQ(dc::test::lines(png.err), 1u) << png.err;
    EXPECT_NE(png.err.find("--format png16"), std::string::npos) << png.err;
    EXPECT_NE(png.err.find("--source"), std::string::npos) << png.err;
    EXPECT_FALSE(std::filesystem::exists(dir_ / "x"));
    const RunResult missing = runTool("export --source replay:a.dcrec --source replay:missing.dcrec --out x");
    EXPECT_EQ(missing.exitCode, 2);
    EXPECT_EQ(dc::test::lines(missing.err), 1u) << missing.err;
    EXPECT_NE(missing.err.find("--source: replay:missing.dcrec"), std::string::npos) << missing.err;
    EXPECT_FALSE(std::filesystem::exists(dir_ / "x"));
}

} // namespace
