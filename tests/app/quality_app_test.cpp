// depthcloud quality on the synthetic source: exit 0 when every expectation holds, 1 when one fails, 2 for a
// bad argument (one line naming it); the JSON has every figure, finite where it was measured.

#include "tool_in_temp_dir.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>

namespace {

using dc::test::lines;
using dc::test::readFile;
using dc::test::RunResult;

class Quality : public dc::test::ToolInTempDir {
protected:
    RunResult run(const std::string& arguments) const { return runTool("quality " + arguments); }
};

const char* const kFigures[] = {"fillRate",        "planeFitRmsMm",  "planeFitRmsPercent", "dqtPlaneFitRmsMm",
                                "temporalNoiseMm", "spatialNoiseMm", "distanceMm",         "angleDeg",
                                "inlierFraction",  "frames"};

TEST_F(Quality, HeldExpectationsExitZeroAndTheJsonHasEveryFigure) {
    const RunResult r = run("--source synthetic:64x48 --frames 6 --ground-truth-mm 1000 --baseline-mm 50 "
                            "--expect \"fillRate>=0.5,frames==6\" --json q.json");
    ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
    EXPECT_NE(r.out.find("planeFitRmsMm "), std::string::npos) << r.out;
    const nlohmann::json j = nlohmann::json::parse(readFile(dir_ / "q.json"));
    for (const char* key : kFigures) {
        ASSERT_TRUE(j.contains(key)) << key;
        ASSERT_TRUE(j[key].is_number()) << key << " = " << j[key];
        EXPECT_TRUE(std::isfinite(j[key].get<double>())) << key;
    }
    EXPECT_TRUE(j["subpixelRms"].is_number());
    EXPECT_TRUE(j["expectedNoiseMm"].is_number());
    EXPECT_TRUE(j["zAccuracyPercent"].is_number());
    EXPECT_EQ(j["frames"], 6);
    for (const char* cause : {"noMeasurement", "outOfRange", "lowConfidence", "flyingPixel"}) {
        EXPECT_TRUE(j["shortfall"][cause]["count"].is_number()) << cause;
        EXPECT_TRUE(j["shortfall"][cause]["fraction"].is_number()) << cause;
    }
}

// The whole chain a test bench runs: the synthetic wall 1.2 m away, turned 15 degrees, 1 mm of noise.
TEST_F(Quality, TheSyntheticWallIsMeasuredAtItsDistanceTiltAndNoise) {
    const RunResult r = run("--source synthetic:320x240:plane=1.2,15,1 --frames 20 --ground-truth-mm 1200 "
                            "--expect \"fillRate==1,planeFitRmsMm<=1.05,planeFitRmsMm>=0.9\" --json q.json");
    ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
    const nlohmann::json j = nlohmann::json::parse(readFile(dir_ / "q.json"));
    EXPECT_NEAR(j["distanceMm"].get<double>(), 1200.0, 0.5);
    EXPECT_NEAR(j["angleDeg"].get<double>(), 15.0, 0.1);
    EXPECT_NEAR(j["zAccuracyPercent"].get<double>(), 0.0, 0.05);
    EXPECT_NEAR(j["temporalNoiseMm"].get<double>(), 1.0, 0.06);
}

TEST_F(Quality, FiguresWithoutWhatTheyNeedAreNull) {
    const RunResult r = run("--source synthetic:64x48 --frames 2 --json q.json");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(readFile(dir_ / "q.json"));
    EXPECT_TRUE(j["subpixelRms"].is_null());
    EXPECT_TRUE(j["expectedNoiseMm"].is_null());
    EXPECT_TRUE(j["zAccuracyPercent"].is_null());
}

// The two-sensor synthetic camera is registered exactly by construction. With exact depth what is left is
// the pixel grid (each depth pixel takes the colour of the colour pixel nearest its projection, and the edges
// are found to a fraction of a pixel): measured 0.04 px, bound at a quarter. The sensor's noise mixes the
// returns of both sides at every silhouette, which moves depth edges by up to a pixel: measured 0.94 px.
TEST_F(Quality, TheSyntheticRigsColourLiesOnItsDepthEdges) {
    const RunResult exact = run("--source synthetic:rig=rgbd:exact --frames 5 --json exact.json");
    ASSERT_EQ(exact.exitCode, 0) << exact.err;
    EXPECT_NE(exact.out.find("alignmentPx "), std::string::npos) << exact.out;
    const nlohmann::json j = nlohmann::json::parse(readFile(dir_ / "exact.json"));
    ASSERT_TRUE(j["alignmentPx"].is_number()) << j["alignmentPx"];
    ASSERT_TRUE(j["alignmentMm"].is_number()) << j["alignmentMm"];
    EXPECT_TRUE(std::isfinite(j["alignmentPx"].get<double>()));
    EXPECT_TRUE(std::isfinite(j["alignmentMm"].get<double>()));
    EXPECT_LE(j["alignmentPx"].get<double>(), 0.25);
    EXPECT_EQ(j["alignmentFrames"], 5) << "every frame has colour and the desk's edges";
    EXPECT_EQ(j["planeFrames"], 5);
    const RunResult noisy = run("--source synthetic:rig=rgbd --frames 5 --expect \"alignmentPx<=1.5\"");
    EXPECT_EQ(noisy.exitCode, 0) << noisy.out << noisy.err;
}

// A depth topic replayed alone has no camera image, and a flat target no depth edge: nothing to align, so
// null, where the same recording with its colour topic has a figure.
TEST_F(Quality, AlignmentIsNullWithoutAColourImageOrADepthEdge) {
    ASSERT_EQ(runTool("record --source synthetic:64x48 --frames 3 take.dcrec").exitCode, 0);
    ASSERT_EQ(runTool("export --source replay:take.dcrec --format mcap --out take.mcap").exitCode, 0);
    const RunResult depthOnly =
        run("--source replay:take.mcap:topics=/camera/camera/depth/image_rect_raw --frames 3 --json d.json");
    if (depthOnly.err.find("built without ROS") != std::string::npos)
        GTEST_SKIP() << depthOnly.err;
    ASSERT_EQ(depthOnly.exitCode, 0) << depthOnly.err;
    const nlohmann::json d = nlohmann::json::parse(readFile(dir_ / "d.json"));
    EXPECT_TRUE(d["alignmentPx"].is_null()) << d["alignmentPx"];
    EXPECT_TRUE(d["alignmentMm"].is_null()) << d["alignmentMm"];
    EXPECT_EQ(d["alignmentFrames"], 0);
    ASSERT_EQ(run("--source replay:take.mcap --frames 3 --json c.json").exitCode, 0);
    EXPECT_TRUE(nlohmann::json::parse(readFile(dir_ / "c.json"))["alignmentPx"].is_number());
    ASSERT_EQ(run("--source synthetic:64x48:plane=1,0,1 --frames 2 --json p.json").exitCode, 0);
    EXPECT_TRUE(nlohmann::json::parse(readFile(dir_ / "p.json"))["alignmentPx"].is_null());
}

TEST_F(Quality, AFailedExpectationExitsOneNamingItAndItsValue) {
    const RunResult r = run("--source synthetic:64x48 --frames 2 --expect \"frames>=1,fillRate>1\"");
    EXPECT_EQ(r.exitCode, 1) << r.err;
    EXPECT_NE(r.err.find("fillRate>1 failed: fillRate = "), std::string::npos) << r.err;
    EXPECT_EQ(lines(r.err), 1u) << r.err;
    const RunResult unmeasured = run("--source synthetic:64x48 --frames 2 --expect \"zAccuracyPercent<=1\"");
    EXPECT_EQ(unmeasured.exitCode, 1) << unmeasured.err;
    EXPECT_NE(unmeasured.err.find("zAccuracyPercent was not measured"), std::string::npos) << unmeasured.err;
}

TEST_F(Quality, BadArgumentsExitTwoWithOneLineNamingTheArgument) {
    struct Case {
        const char* args;
        const char* mentions;
    };
    const Case cases[] = {
        {"--expect \"noSuchFigure<=1\"", "--expect"},
        {"--expect \"fillRate=1\"", "--expect"},
        {"--expect \"fillRate>=high\"", "--expect"},
        {"--roi 1,2,3", "--roi"},
        {"--source synthetic:64x48 --roi 60,0,10,10", "--roi"},
        {"--roi 0,0,8,8 --roi-percent 20", "--roi"},
        {"--roi-polygon \"1,2;3,4\"", "--roi-polygon"},
        {"--roi-polygon \"a,1;2,3;4,5\"", "--roi-polygon"},
        {"--roi-polygon \"1,2,3;4,5;6,7\"", "--roi-polygon"},
        {"--source synthetic:64x48 --roi-polygon \"0,0;70,0;0,10\"", "--roi-polygon"},
        {"--roi 0,0,8,8 --roi-polygon \"0,0;8,0;0,8\"", "--roi-polygon"},
        {"--roi-percent 20 --roi-polygon \"0,0;8,0;0,8\"", "--roi-polygon"},
        {"--frames 0", "--frames"},
        {"--source nowhere:at:all", "--source"},
    };
    for (const Case& c : cases) {
        const RunResult r = run(c.args);
        EXPECT_EQ(r.exitCode, 2) << c.args << "\n" << r.err;
        EXPECT_NE(r.err.find(c.mentions), std::string::npos) << c.args << "\n" << r.err;
        EXPECT_EQ(lines(r.err), 1u) << c.args << "\n" << r.err;
    }
}

// The triangle (4, 4), (40, 4), (4, 30): pixel (x, y) is in it when its centre is, i.e. x >= 4, y >= 4 and
// 26 (x - 3.5) + 36 (y - 3.5) < 936 (the slope's equation; never equal at a centre, 26 x + 36 y being even).
TEST_F(Quality, APolygonRegionCountsTheSamplesWhoseCentresAreInsideIt) {
    const RunResult r =
        run("--source synthetic:64x48 --frames 1 --roi-polygon \"4,4;40,4;4,30\" --json p.json");
    ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
    const nlohmann::json j = nlohmann::json::parse(readFile(dir_ / "p.json"));
    EXPECT_EQ(j["roiPolygon"], nlohmann::json::parse("[[4, 4], [40, 4], [4, 30]]"));
    std::size_t inside = 0;
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 64; ++x)
            inside += x >= 4 && y >= 4 && 26 * x + 36 * y < 1153;
    EXPECT_EQ(j["roiSamples"].get<std::size_t>(), inside);
    EXPECT_EQ(j["roi"], nlohmann::json::parse(R"({"x": 4, "y": 4, "width": 36, "height": 26})"));
    const RunResult rectangle = run("--source synthetic:64x48 --frames 1 --roi 4,4,36,26 --json r.json");
    ASSERT_EQ(rectangle.exitCode, 0) << rectangle.err;
    const nlohmann::json k = nlohmann::json::parse(readFile(dir_ / "r.json"));
    EXPECT_TRUE(!k.contains("roiPolygon") || k["roiPolygon"].is_null());
    EXPECT_EQ(k["roiSamples"], 36 * 26);
}

TEST_F(Quality, AnExistingJsonIsKeptUnlessOverwriteIsGiven) {
    std::ofstream(dir_ / "q.json") << "an earlier run";
    const RunResult r = run("--source synthetic:64x48 --frames 2 --json q.json");
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_NE(r.err.find("--json q.json already exists"), std::string::npos) << r.err;
    EXPECT_EQ(readFile(dir_ / "q.json"), "an earlier run");
    const RunResult replaced = run("--source synthetic:64x48 --frames 2 --json q.json --overwrite");
    EXPECT_EQ(replaced.exitCode, 0) << replaced.err;
    EXPECT_TRUE(nlohmann::json::parse(readFile(dir_ / "q.json")).contains("fillRate"));
}

} // namespace
