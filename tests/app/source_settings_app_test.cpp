// Each further source processed and filtered as its own --set sourceN.NAME=VALUE says, headless: its points
// in cloud.ply and its depth in summary.json change with its own settings and not with the main source's,
// and the main source's stay its own.

#include "tool_in_temp_dir.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <regex>
#include <string>
#include <vector>

namespace {

using dc::test::readFile;
using dc::test::RunResult;

const std::string kA = "synthetic:320x240";
const std::string kB = "synthetic:320x240:view=0.2,0,0,0,-0.0697564737441253,0,0.9975640502598242";

// Each source's point count in cloud.ply, as its header's comments ("N points of SPEC") give them.
std::vector<long> pointCounts(const std::string& ply) {
    const std::string header = ply.substr(0, ply.find("end_header\n"));
    std::vector<long> counts;
    const std::regex comment("comment (\\d+) points of ");
    for (auto it = std::sregex_iterator(header.begin(), header.end(), comment); it != std::sregex_iterator();
         ++it)
        counts.push_back(std::stol((*it)[1]));
    return counts;
}

class SourceSettings : public dc::test::ToolInTempDir {
protected:
    struct Run {
        std::vector<long> points; // per source
        nlohmann::json summary;
    };
    // Two sources headless with `sets` (each one --set); the points per source and summary.json.
    Run run(const std::vector<std::string>& sets) {
        std::filesystem::remove_all(dir_ / "out");
        std::string arguments = "--headless --out out --frames 6 --source " + kA + " --source \"" + kB + "\"";
        for (const std::string& s : sets)
            arguments += " --set " + s;
        const RunResult r = runTool(arguments);
        EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
        if (r.exitCode != 0)
            return {};
        return {pointCounts(readFile(dir_ / "out/cloud.ply")),
                nlohmann::json::parse(readFile(dir_ / "out/summary.json"))};
    }
};

TEST_F(SourceSettings, AFurtherSourcesConfidenceIsItsOwnAndLeavesTheMainSources) {
    const Run both = run({});
    ASSERT_EQ(both.points.size(), 2u);
    ASSERT_GT(both.points[1], 20'000);
    // Source 2 alone drawn from its high-confidence samples: far fewer of its points, the main's as they were
    // (the synthetic noise moves a count by a few samples between runs).
    const Run own = run({"source2.cloud.minConfidence=high"});
    ASSERT_EQ(own.points.size(), 2u);
    EXPECT_LT(own.points[1], both.points[1] / 2);
    EXPECT_NEAR(own.points[0], both.points[0], both.points[0] / 50);
    // The main source at high, source 2 kept at low: source 2 keeps its points.
    const Run mainHigh = run({"cloud.minConfidence=high", "source2.cloud.minConfidence=low"});
    ASSERT_EQ(mainHigh.points.size(), 2u);
    EXPECT_LT(mainHigh.points[0], both.points[0] / 2);
    EXPECT_NEAR(mainHigh.points[1], both.points[1], both.points[1] / 50);
    // Without a setting of its own, source 2 follows the main source's.
    const Run follows = run({"cloud.minConfidence=high"});
    ASSERT_EQ(follows.points.size(), 2u);
    EXPECT_LT(follows.points[1], both.points[1] / 2);
}

TEST_F(SourceSettings, AFurtherSourcesProcessingIsItsOwn) {
    // Source 2 upsampled to its camera's picture: its depth (and so its cloud) is denser; the main source's
    // depth is the sensor's.
    const Run r = run({"source2.processing.upsampling=true"});
    ASSERT_FALSE(r.summary.is_null());
    ASSERT_EQ(r.summary["companions"].size(), 1u);
    EXPECT_EQ(r.summary["depthWidth"].get<int>(), 320);
    EXPECT_GT(r.summary["companions"][0]["depthWidth"].get<int>(), 320) << r.summary["companions"][0];
    ASSERT_EQ(r.points.size(), 2u);
    EXPECT_GT(r.points[1], 2 * r.points[0]);
    // The main source upsampled instead: source 2 follows it unless it has its own processing.
    const Run mainUp = run({"processing.upsampling=true", "source2.processing.smoothing=true"});
    ASSERT_FALSE(mainUp.summary.is_null());
    EXPECT_GT(mainUp.summary["depthWidth"].get<int>(), 320);
    EXPECT_GT(mainUp.summary["companions"][0]["depthWidth"].get<int>(), 320)
        << "its own settings start from the main source's";
    const Run mainOnly = run({"processing.upsampling=true", "source2.processing.upsampling=false"});
    ASSERT_FALSE(mainOnly.summary.is_null());
    EXPECT_EQ(mainOnly.summary["companions"][0]["depthWidth"].get<int>(), 320);
}

TEST_F(SourceSettings, ASettingNoFurtherSourceTakesIsABadArgumentNamingIt) {
    const std::string sources = "--headless --out out --source " + kA + " --source \"" + kB + "\"";
    const RunResult noSource = runTool(sources + " --set source3.processing.smoothing=true");
    EXPECT_EQ(noSource.exitCode, 2);
    EXPECT_NE(noSource.err.find("--set source3.processing.smoothing=true: there is no source 3"),
              std::string::npos)
        << noSource.err;
    const RunResult view = runTool(sources + " --set source2.depthRange.automatic=false");
    EXPECT_EQ(view.exitCode, 2);
    EXPECT_NE(view.err.find("depthRange.automatic"), std::string::npos) << view.err;
    const RunResult value = runTool(sources + " --set source2.processing.upsampling=maybe");
    EXPECT_EQ(value.exitCode, 2);
    EXPECT_NE(value.err.find("processing.upsampling"), std::string::npos) << value.err;
    EXPECT_FALSE(std::filesystem::exists(dir_ / "out/summary.json"));
}

} // namespace
