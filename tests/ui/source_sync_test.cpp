// Several sources, sync visible: under the main replay's scrubber the Timeline places each further
// replay's frames where their stamps fall on the common clock and marks the frame it shows; the Timing
// panel reads out each further source's skew from the main source (now, median, range, how many beyond the
// pairing tolerance). Every figure is checked against one worked out here from the recordings' own stamps
// or the companion's own samples; with one source neither panel shows any of it.

#include "sources_fixture.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace dc::ui::test {
namespace {

namespace fs = std::filesystem;

class SourceSyncTest : public SourcesTest {
protected:
    std::optional<std::size_t> shownIndex(const processing::ShownFramePtr& shown) const {
        if (!shown || !shown->frame->replay)
            return std::nullopt;
        return shown->frame->replay->index;
    }

    // What `draw` draws inside `title`'s window, as text (ImGui's log, which ends at the window's End).
    std::string textOf(const char* title, const std::function<void()>& draw) {
        const std::string path = ::testing::TempDir() + "source-sync-panel.txt";
        fs::remove(path); // ImGui appends to a log file
        gui_.newFrame(1.0f / 60.0f);
        bool open = true;
        ImGui::Begin(title, &open);
        ImGui::LogToFile(-1, path.c_str());
        draw();
        ImGui::End();
        gui_.render();
        std::ifstream in(path);
        return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    }
    std::string timelineText(std::vector<TimelineSourceRow> rows) {
        TimelineView view{instrument_->replay()->status(), false, 0, 0, std::move(rows)};
        TimelinePanelState state;
        return textOf(kTimelineTitle, [&] {
            bool open = true;
            drawTimelinePanel(view, state, &open);
        });
    }
    std::string timingText(const std::vector<SourceSkew>& rows) {
        const engine::TimingSummary timing = instrument_->timing();
        return textOf(kTimingTitle, [&] {
            bool open = true;
            drawTimingPanel(timing, &open, rows);
        });
    }
    float stripHeight() {
        frame(0.0);
        ImGuiWindow* strip = ImGui::FindWindowByName(kTimelineTitle);
        return strip && strip->Active ? strip->Size.y : 0.0f;
    }
};

// Where main-clock time `t` falls on a scrubber over `stamps`: the fractional index between the frames
// around it over the last index, found by walking the stamps; none outside them.
std::optional<double> placeOf(const std::vector<std::int64_t>& stamps, std::int64_t t) {
    if (t < stamps.front() || t > stamps.back())
        return std::nullopt;
    if (t == stamps.back())
        return 1.0;
    std::size_t j = 0;
    while (stamps[j + 1] <= t)
        ++j;
    const double index = static_cast<double>(j) +
                         static_cast<double>(t - stamps[j]) / static_cast<double>(stamps[j + 1] - stamps[j]);
    return index / static_cast<double>(stamps.size() - 1);
}

TEST_F(SourceSyncTest, TheTimelinePlacesAFurtherReplaysFramesByTheCommonClockAndMarksTheOneItShows) {
    const OffsetPair pair = recordOffsetPair();
    ASSERT_FALSE(HasFailure());
    const std::string& a = pair.a;
    const std::string& b = pair.b;
    const std::vector<std::int64_t>& stampsA = pair.stampsA;
    const std::vector<std::int64_t>& stampsB = pair.stampsB;
    ASSERT_TRUE(viewer_->openSource("replay:" + a + ":paused").ok());
    const float alone = stripHeight();
    ASSERT_GT(alone, 0.0f) << "the timeline is shown";
    ASSERT_TRUE(viewer_->addSource("replay:" + b + ":paused").ok());
    EXPECT_NEAR(stripHeight() - alone, ImGui::GetTextLineHeightWithSpacing(), 0.5f)
        << "the strip has room for the further source's row";

    // B's frames on A's clock: as long after A's first frame as after B's own first.
    std::vector<std::optional<double>> expected;
    for (const std::int64_t t : stampsB)
        expected.push_back(placeOf(stampsA, stampsA.front() + (t - stampsB.front())));
    const auto placed = static_cast<std::size_t>(
        std::count_if(expected.begin(), expected.end(), [](const auto& p) { return p.has_value(); }));
    ASSERT_GT(placed, 10u);
    ASSERT_LT(placed, stampsB.size()) << "B runs on past A's end: those frames have no place";

    for (const std::size_t target : {std::size_t{13}, std::size_t{3}}) {
        instrument_->seekReplay(target);
        const std::size_t want = nearest(stampsB, stampsB.front() + (stampsA[target] - stampsA.front()));
        ASSERT_TRUE(frameUntil([&] {
            return shownIndex(viewer_->shown()) == target &&
                   shownIndex(viewer_->companions()[0].presenter().shown()) == want;
        }));
        const std::vector<TimelineSourceRow> rows = viewer_->companions().timelineRows(*instrument_);
        ASSERT_EQ(rows.size(), 1u);
        const TimelineSourceRow& row = rows[0];
        EXPECT_EQ(row.name, "Source 2");
        EXPECT_TRUE(row.note.empty()) << row.note;
        EXPECT_EQ(row.places.first, 0u);
        ASSERT_EQ(row.places.positions.size(), placed);
        for (std::size_t k = 0; k < placed; ++k)
            EXPECT_NEAR(row.places.positions[k], *expected[k], 1e-12) << "frame " << k;
        EXPECT_EQ(row.shown, want) << "the marked frame is the one the companion shows";
        const std::string text = timelineText(rows);
        EXPECT_NE(text.find("Source 2: frame " + std::to_string(want)), std::string::npos) << text;
    }
}

TEST_F(SourceSyncTest, ALiveSourceBesideAReplayHasNoCommonClockAndSaysSo) {
    const std::string a = record("a.dcrec", 12);
    ASSERT_TRUE(viewer_->openSource("replay:" + a + ":paused").ok());
    ASSERT_TRUE(viewer_->addSource("synthetic:160x120").ok());
    ASSERT_TRUE(frameUntil([&] { return viewer_->companions()[0].presenter().shown() != nullptr; }));
    const std::vector<TimelineSourceRow> rows = viewer_->companions().timelineRows(*instrument_);
    ASSERT_EQ(rows.size(), 1u);
    EXPECT_TRUE(rows[0].places.positions.empty());
    EXPECT_NE(timelineText(rows).find("Source 2: live: no common clock with the replay"), std::string::npos);
    const std::vector<SourceSkew> skews =
        viewer_->companions().skewRows(*instrument_, viewer_->shown(), 5.0f);
    ASSERT_EQ(skews.size(), 1u);
    EXPECT_EQ(skews[0].recent.count, 0u);
    EXPECT_FALSE(skews[0].nowMs.has_value());
    EXPECT_NE(timingText(skews).find("Source 2: no common clock"), std::string::npos);
}

std::string line(const char* format, auto... values) {
    char text[200];
    std::snprintf(text, sizeof text, format, values...);
    return text;
}

TEST_F(SourceSyncTest, TheTimingPanelReadsOutEachFurtherSourcesSkewAsItsSamplesSay) {
    ASSERT_TRUE(viewer_->openSource("synthetic:160x120").ok());
    ASSERT_TRUE(viewer_->addSource("synthetic:160x120:" + kBesideView).ok());
    const Companion& b = viewer_->companions()[0];
    ASSERT_TRUE(frameUntil([&] { return b.skew.count() >= 30; })) << b.skew.count() << " skew samples";
    const std::vector<double> samples = b.skew.inOrder();
    // A tolerance half of the samples are beyond: the middle of their sizes.
    std::vector<double> sizes;
    for (const double s : samples)
        sizes.push_back(std::abs(s));
    std::sort(sizes.begin(), sizes.end());
    const float tolerance = static_cast<float>(sizes[sizes.size() / 2]);
    ASSERT_GT(tolerance, 0.0f);
    std::size_t beyond = 0;
    for (const double s : samples)
        beyond += std::abs(s) > tolerance ? 1 : 0;
    ASSERT_GT(beyond, 0u);
    ASSERT_LT(beyond, samples.size());

    const std::vector<SourceSkew> rows =
        viewer_->companions().skewRows(*instrument_, viewer_->shown(), tolerance);
    ASSERT_EQ(rows.size(), 1u);
    const SkewFigures& f = rows[0].recent;
    EXPECT_EQ(f.count, samples.size());
    EXPECT_DOUBLE_EQ(f.medianMs, b.skew.median());
    EXPECT_DOUBLE_EQ(f.minMs, *std::min_element(samples.begin(), samples.end()));
    EXPECT_DOUBLE_EQ(f.maxMs, b.skew.max());
    EXPECT_EQ(f.beyondTolerance, beyond);
    const auto now = viewer_->companions().skewMs(0, *instrument_, viewer_->shown());
    ASSERT_TRUE(now.has_value());
    EXPECT_EQ(rows[0].nowMs, now);
    // Every sample in a bin, and the tolerance's lines within the histogram's range.
    const engine::IntervalHistogram& h = f.histogram;
    ASSERT_FALSE(h.counts.empty());
    double inBins = 0.0;
    for (const float c : h.counts)
        inBins += c;
    EXPECT_EQ(inBins, static_cast<double>(samples.size()));
    EXPECT_LE(h.lowMs, -tolerance);
    EXPECT_GE(h.lowMs + h.binMs * static_cast<double>(h.counts.size()), tolerance - 1e-9);

    const std::string text = timingText(rows);
    const std::string shown[] = {
        "Sources: skew from the main source's frame",
        line("Source 2: now %+.2f ms", *now),
        line("median %+.2f ms, min %+.2f ms, max %+.2f ms (%zu frames)", b.skew.median(),
             *std::min_element(samples.begin(), samples.end()), b.skew.max(), samples.size()),
        line("beyond the pairing tolerance of %.2f ms: %zu of %zu frames", tolerance, beyond, samples.size()),
    };
    for (const std::string& l : shown)
        EXPECT_NE(text.find(l), std::string::npos) << "not shown: " << l << "\nshown:\n" << text;
    const std::string off = timingText(viewer_->companions().skewRows(*instrument_, viewer_->shown(), 0.0f));
    EXPECT_NE(off.find("pairing tolerance off"), std::string::npos) << off;
    EXPECT_EQ(off.find("beyond the pairing tolerance"), std::string::npos) << off;
}

TEST_F(SourceSyncTest, WithOneSourceNeitherPanelShowsTheSourcesParts) {
    const std::string a = record("a.dcrec", 12);
    ASSERT_TRUE(viewer_->openSource("replay:" + a + ":paused").ok());
    frame(0.0);
    const auto timeline = viewer_->companions().timelineRows(*instrument_);
    const auto timing = viewer_->companions().skewRows(*instrument_, viewer_->shown(), 5.0f);
    EXPECT_TRUE(timeline.empty());
    EXPECT_TRUE(timing.empty());
    const std::string timelineShown = timelineText(timeline);
    ASSERT_NE(timelineShown.find("frame 0 /"), std::string::npos) << "the panel was read: " << timelineShown;
    EXPECT_EQ(timelineShown.find("Source"), std::string::npos) << timelineShown;
    const std::string timingShown = timingText(timing);
    ASSERT_NE(timingShown.find("delivered"), std::string::npos) << "the panel was read: " << timingShown;
    EXPECT_EQ(timingShown.find("Source"), std::string::npos) << timingShown;
    EXPECT_EQ(timingShown.find("skew from the main source"), std::string::npos) << timingShown;
}

} // namespace
} // namespace dc::ui::test
