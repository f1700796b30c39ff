// depthcloud align on two synthetic cameras viewing the one desk scene from known places (view=): with their
// true places the overlap figure is the scene's noise; a 3 degree / 3 cm error in B's pose= is reported and
// ICP recovers B's true placement; the placements it saves read back (OpenCV extrinsics and a Kalibr camchain
// alike) as what they say. Bad arguments exit 2 in one line and overwrite nothing.

#include "tool_in_temp_dir.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <vector>

namespace {

using dc::test::lines;
using dc::test::readFile;
using dc::test::RunResult;

// Camera A is the synthetic camera where it usually stands; B 20 cm to its right, turned 8 degrees back
// towards it about its vertical axis, so both see the apple, the book and most of the desk and wall.
const std::string kA = "synthetic:320x240";
const std::string kB = "synthetic:320x240:view=0.2,0,0,0,-0.0697564737441253,0,0.9975640502598242";
// 3 degrees about the skew axis (1, 2, -1) and (2, -2, 1) cm: B's placement, wrong.
const std::string kError =
    "pose=0.02,-0.02,0.01,0.010686694396250128,0.021373388792500257,-0.010686694396250128,0.9996573249755573";

class Align : public dc::test::ToolInTempDir {
protected:
    // Runs align with --json out.json; the JSON, or null when the run failed.
    nlohmann::json align(const std::string& b, const std::string& more = "") {
        std::filesystem::remove(dir_ / "out.json");
        const RunResult r =
            runTool("align --source " + kA + " --source \"" + b + "\" --json out.json " + more);
        EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
        return r.exitCode == 0 ? nlohmann::json::parse(readFile(dir_ / "out.json")) : nlohmann::json();
    }
};

// The angle (degrees) and the distance from the origin (mm) of a placement x, y, z, qx, qy, qz, qw.
double degreesOf(const nlohmann::json& p) {
    return 2.0 * std::acos(std::min(1.0, std::abs(p[6].get<double>()))) * 180.0 / M_PI;
}
double mmOf(const nlohmann::json& p) {
    return 1000.0 * std::hypot(p[0].get<double>(), p[1].get<double>(), p[2].get<double>());
}

TEST_F(Align, TheTruePlacesAgreeWithinTheScenesNoise) {
    const nlohmann::json j = align(kB);
    ASSERT_FALSE(j.is_null());
    // Two noisy maps, each with about 1.5 mm of noise at 1-2 m: a few mm between them, over most of A.
    EXPECT_GT(j["before"]["medianMm"].get<double>(), 0.5);
    EXPECT_LT(j["before"]["medianMm"].get<double>(), 5.0);
    EXPECT_GT(j["before"]["overlapFraction"].get<double>(), 0.6);
    EXPECT_LT(j["correctionDegrees"].get<double>(), 0.2);
    EXPECT_LT(j["correctionMm"].get<double>(), 2.0);
}

TEST_F(Align, AThreeDegreeErrorIsReportedAndIcpRecoversTheTruePlacement) {
    const nlohmann::json truth = align(kB);
    const nlohmann::json j = align(kB + ":" + kError, "--save rig.yaml --save-kalibr camchain.yaml");
    ASSERT_FALSE(j.is_null());
    ASSERT_FALSE(truth.is_null());
    EXPECT_EQ(j["status"], "refined");
    EXPECT_TRUE(j["converged"].get<bool>());
    EXPECT_GT(j["before"]["medianMm"].get<double>(), 3.0 * truth["before"]["medianMm"].get<double>());
    EXPECT_LE(j["after"]["medianMm"].get<double>(), 1.1 * truth["before"]["medianMm"].get<double>());
    EXPECT_NEAR(j["correctionDegrees"].get<double>(), 3.0, 0.2);
    // B's true placement is the identity (view= put it where it is): what ICP gives is within 0.2 deg, 2 mm.
    EXPECT_LE(degreesOf(j["placementB"]), 0.2) << j["placementB"];
    EXPECT_LE(mmOf(j["placementB"]), 2.0) << j["placementB"];
    EXPECT_EQ(j["placementA"], nlohmann::json::array({0, 0, 0, 0, 0, 0, 1}));

    // Read back, either file places B where ICP put it: nothing left to correct, the same figure both ways.
    const nlohmann::json opencv = align(kB + ":pose=rig.yaml#camera_1");
    const nlohmann::json kalibr = align(kB + ":pose=camchain.yaml#cam1");
    ASSERT_FALSE(opencv.is_null());
    ASSERT_FALSE(kalibr.is_null());
    EXPECT_NEAR(opencv["before"]["medianMm"].get<double>(), j["after"]["medianMm"].get<double>(), 1e-6);
    EXPECT_NEAR(kalibr["before"]["medianMm"].get<double>(), j["after"]["medianMm"].get<double>(), 1e-6);
    EXPECT_LT(opencv["correctionDegrees"].get<double>(), 0.05);
}

// A PLY's vertices: float x, y, z then four bytes (colour, confidence), little endian, as encodePly writes.
std::vector<std::array<float, 3>> plyPoints(const std::string& bytes) {
    const std::string end = "end_header\n";
    const auto body = bytes.find(end);
    const auto count = bytes.find("element vertex ");
    if (body == std::string::npos || count == std::string::npos)
        return {};
    const std::size_t n = std::stoul(bytes.substr(count + 15));
    std::vector<std::array<float, 3>> points(n);
    for (std::size_t i = 0; i < n && body + end.size() + 16 * (i + 1) <= bytes.size(); ++i)
        std::memcpy(points[i].data(), bytes.data() + body + end.size() + 16 * i, 12);
    return points;
}

// The fused cloud puts B where ICP found it: point for point (the synthetic cameras' samples do not change
// from run to run) within 2 mm of where the true placement puts it; the 3 degree error would be ~5 cm.
TEST_F(Align, TheFusedCloudPlacesBWhereIcpFoundIt) {
    ASSERT_FALSE(align(kB, "--ply truth.ply").is_null());
    ASSERT_FALSE(align(kB + ":" + kError, "--ply fused.ply").is_null());
    const auto truth = plyPoints(readFile(dir_ / "truth.ply"));
    const auto fused = plyPoints(readFile(dir_ / "fused.ply"));
    ASSERT_GT(truth.size(), 10000u);
    ASSERT_EQ(fused.size(), truth.size());
    std::vector<double> mm;
    for (std::size_t i = 0; i < truth.size(); ++i)
        mm.push_back(1000.0 * std::hypot(fused[i][0] - truth[i][0], fused[i][1] - truth[i][1],
                                         fused[i][2] - truth[i][2]));
    std::nth_element(mm.begin(), mm.begin() + static_cast<std::ptrdiff_t>(mm.size() / 2), mm.end());
    EXPECT_LE(mm[mm.size() / 2], 2.0);
}

TEST_F(Align, BadArgumentsExitTwoInOneLineAndOverwriteNothing) {
    { std::ofstream(dir_ / "rig.yaml") << "mine\n"; }
    const std::pair<std::string, std::string> cases[] = {
        {"align --source " + kA, "two sources"},
        {"align --source " + kA + " --source synthetic:320x240:view=1,2", "view=1,2"},
        {"align --source " + kA + " --source \"" + kB + "\" --save rig.yaml", "rig.yaml already exists"},
        {"align --source " + kA + " --source \"" + kB + ":motion\"", "view="},
    };
    for (const auto& [arguments, named] : cases) {
        const RunResult r = runTool(arguments);
        EXPECT_EQ(r.exitCode, 2) << arguments << "\n" << r.err;
        EXPECT_EQ(lines(r.err), 1u) << r.err;
        EXPECT_NE(r.err.find(named), std::string::npos) << r.err;
    }
    EXPECT_EQ(readFile(dir_ / "rig.yaml"), "mine\n");
}

TEST_F(Align, CamerasThatSeeNothingInCommonAreARunTimeFailure) {
    const RunResult r = runTool("align --source " + kA + " --source synthetic:320x240:view=0,0,0,0,1,0,0");
    EXPECT_EQ(r.exitCode, 1) << r.err;
    EXPECT_EQ(lines(r.err), 1u) << r.err;
    EXPECT_NE(r.err.find("too little overlap"), std::string::npos) << r.err;
}

} // namespace
