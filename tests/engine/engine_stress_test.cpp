// The frame processor under fire: a source delivering, the UI changing its demand and seeking, and results
// taken, all at once for DC_ENGINE_STRESS_SECONDS (default 1; the TSan tier runs it longer). Each result
// must answer the demand it names and never come from before a seek it was asked after.

#include "devices/source_spec.h"
#include "engine/frame_processor.h"
#include "engine/instrument.h"
#include "engine_test_support.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <map>
#include <unistd.h>

namespace dc::engine::test {
namespace {

using namespace std::chrono_literals;

double stressSeconds() {
    const char* s = std::getenv("DC_ENGINE_STRESS_SECONDS");
    return s ? std::atof(s) : 1.0;
}

// Four demands that differ in what the results must hold.
std::vector<Demand> demands() {
    std::vector<Demand> out(4);
    out[0].processing.smoothing = true;
    out[1].processing.upsampling = true;
    out[2].fog = true;
    out[2].cameraPanelWidth = 200;
    out[3].pointColours = false;
    out[3].confidencePanel = false;
    out[3].aura = true;
    return out;
}

TEST(EngineStressTest, DemandsSeeksAndFramesAtOnceKeepEveryResultConsistent) {
    StageStats stages;
    processing::AccumulationWorker accumulation;
    auto device = std::make_unique<ScriptedDevice>();
    ScriptedDevice& source = *device;
    auto session = std::make_shared<devices::Session>(std::move(device));
    ASSERT_TRUE(session->start().ok());
    FrameProcessor processor(stages, accumulation);
    processor.setSession(session);

    // The capture side, a replay decoding three frames ahead: each frame carries the seek generation of
    // three frames before, so the first frames after a seek are stale.
    std::atomic<std::uint64_t> seekGeneration{0};
    std::atomic<bool> stop{false};
    std::uint64_t pushed = 0;
    const std::vector<frame::FramePtr> frames = syntheticFrames(8);
    std::thread feeder([&] {
        std::deque<std::uint64_t> decodedUnder;
        while (!stop) {
            if (source.pending() < 2) {
                decodedUnder.push_back(seekGeneration.load());
                if (decodedUnder.size() > 3)
                    decodedUnder.pop_front();
                auto f = std::make_shared<frame::Frame>(
                    *asReplayed(frames[pushed % frames.size()], decodedUnder.front()));
                f->sequence = pushed;
                f->timestampNs = static_cast<std::int64_t>(pushed + 1) * 1'000'000;
                source.push(std::move(f));
                ++pushed;
            }
            std::this_thread::sleep_for(1ms); // a ~1 kHz source
        }
    });

    const std::vector<Demand> ds = demands();
    struct Asked {
        Demand demand;
        std::uint64_t seek; // seeks asked before this demand
    };
    std::map<std::uint64_t, Asked> asked;
    std::size_t next = 0;
    const auto ask = [&] {
        const Demand& d = ds[next++ % ds.size()];
        const std::uint64_t g = processor.setDemand(d);
        asked[g] = {d, seekGeneration.load()};
        return g;
    };
    ask();

    std::uint64_t lastGeneration = 0, lastSeek = 0, results = 0;
    ProcessorCounts lastCounts;
    const auto check = [&](const processing::ShownFrame& r) {
        ++results;
        ASSERT_TRUE(asked.contains(r.demandGeneration));
        const Asked& a = asked.at(r.demandGeneration);
        EXPECT_GE(r.demandGeneration, lastGeneration);
        EXPECT_GE(r.frame->replay->seekGeneration, a.seek) << "a frame decoded before a seek asked earlier";
        EXPECT_GE(r.frame->replay->seekGeneration, lastSeek);
        lastGeneration = r.demandGeneration;
        lastSeek = r.frame->replay->seekGeneration;
        ASSERT_TRUE(r.depth.data);
        EXPECT_EQ(r.depth.upsampled, a.demand.processing.upsampling);
        EXPECT_EQ(r.fog != nullptr, a.demand.fog);
        EXPECT_EQ(r.aura != nullptr, a.demand.aura);
        EXPECT_EQ(r.cameraImage != nullptr, a.demand.cameraPanelWidth > 0);
        EXPECT_EQ(r.cloud.colours != nullptr, a.demand.cloud && a.demand.pointColours);
    };

    // The clock starts once frames flow.
    const auto first = processor.waitFor(10s, [](const processing::ShownFrame&) { return true; });
    if (!first) {
        stop = true;
        feeder.join();
        FAIL() << "no result within 10 s";
    }
    check(**first);
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(stressSeconds());
    for (int i = 0; std::chrono::steady_clock::now() < end; ++i) {
        if (i % 3 == 0)
            ask();
        if (i % 17 == 0)
            processor.afterSeek(++seekGeneration);
        if (auto r = processor.take())
            check(**r);
        const ProcessorCounts c = processor.counts();
        EXPECT_GE(c.framesProcessed, lastCounts.framesProcessed);
        EXPECT_GE(c.framesSkipped, lastCounts.framesSkipped);
        EXPECT_GE(c.redone, lastCounts.redone);
        lastCounts = c;
        std::this_thread::sleep_for(2ms); // a fast UI frame
    }
    stop = true;
    feeder.join();
    // The frame the last seek asked for arrives, as a replay's always does.
    source.push(asReplayed(syntheticFrames(1, pushed).front(), seekGeneration.load()));
    ++pushed;
    // Once the source is silent, the last change is still answered, on the current frame.
    const std::uint64_t final = ask();
    const auto last =
        processor.waitFor(10s, [&](const processing::ShownFrame& r) { return r.demandGeneration == final; });
    ASSERT_TRUE(last);
    check(**last);

    ASSERT_TRUE(waitUntil([&] { return session->stats().framesCaptured == pushed; }));
    const auto settled = [&] {
        const devices::SessionStats s = session->stats();
        const ProcessorCounts c = processor.counts();
        return s.framesDropped + c.framesProcessed + c.framesSkipped == s.framesCaptured;
    };
    EXPECT_TRUE(waitUntil(settled)) << "every delivered frame is processed, skipped or dropped";
    EXPECT_GT(processor.counts().framesSkipped, 0u) << "seeks made frames stale";
    EXPECT_GT(results, 10u);
}

// The instrument as the UI drives it, with real sources: the synthetic camera's render-ahead threads and
// capture thread, a replay of a recording it made (decode thread, seeks), the processor, accumulation and
// the recorder, while this thread (the UI's) changes the demand, seeks and switches between the two.
TEST(EngineStressTest, RealSourcesSwitchedSoughtAndRedemandedFromTheUiThread) {
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / ("dc-engine-stress-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const std::string recording = (dir / "take.dcrec").string();
    const std::string synthetic = "synthetic:128x96@120:motion";
    auto device = devices::openSourceSpec(synthetic);
    ASSERT_TRUE(device.ok()) << device.error().message;
    Instrument instrument(std::move(*device), synthetic);
    std::vector<Demand> ds = demands();
    ds[0].accumulate = true;
    instrument.setDemand(ds[0]);
    instrument.start();
    ASSERT_TRUE(instrument.startRecording(recording).ok());
    ASSERT_TRUE(waitUntil([&] {
        instrument.update();
        return instrument.recording().frames >= 20;
    }));
    ASSERT_TRUE(instrument.stopRecording().ok());

    std::map<std::string, std::uint64_t> shown;
    const auto start = std::chrono::steady_clock::now();
    const auto end = start + std::chrono::duration<double>(stressSeconds());
    auto nextSwitch = start;
    // A source is switched away from once it has shown a frame, and the run goes on past its time until both
    // have (within a limit): a slow build (ASan, Debug) on a loaded machine takes longer than the switching
    // period, or the whole run, to start a source.
    bool shownSinceSwitch = false;
    const auto limit = start + 60s;
    const auto running = [&] {
        const auto now = std::chrono::steady_clock::now();
        return now < end || ((shown["synthetic"] == 0 || shown["replay"] == 0) && now < limit);
    };
    for (int i = 0; running(); ++i) {
        const Demand& d = ds[static_cast<std::size_t>(i) % ds.size()];
        const std::uint64_t generation = instrument.setDemand(d);
        if (std::chrono::steady_clock::now() >= nextSwitch && shownSinceSwitch) {
            nextSwitch = std::chrono::steady_clock::now() + 250ms;
            shownSinceSwitch = false;
            const std::string next = instrument.replay() ? synthetic : "replay:" + recording + ":loop";
            ASSERT_TRUE(instrument.openSource(next).ok()) << next;
        }
        if (instrument.replay() && i % 13 == 0)
            instrument.seekReplay(static_cast<std::size_t>(i) % 20);
        if (auto r = instrument.waitForResult(std::chrono::milliseconds(20), false)) {
            EXPECT_LE((*r)->demandGeneration, generation);
            ASSERT_TRUE((*r)->frame);
            instrument.presented(**r);
            ++shown[instrument.replay() ? "replay" : "synthetic"];
            shownSinceSwitch = true;
        }
    }
    EXPECT_GT(shown["synthetic"], 0u);
    EXPECT_GT(shown["replay"], 0u) << "the run lasted long enough to switch to the replay";
    std::filesystem::remove_all(dir);
}

} // namespace
} // namespace dc::engine::test
