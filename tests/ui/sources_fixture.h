#pragma once

// The window with several sources: a scratch folder for recordings made by the real recorder, the stamps
// a recording holds, and a second synthetic camera beside the first, tinted pure green so that its points
// can be counted in the cloud.

#include "devices/recording/recording_reader.h"
#include "ui_fixture.h"

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace dc::ui::test {

// 20 cm to the right of the synthetic camera, turned 8 degrees back towards it (as the align tests place it).
inline const std::string kBesideView = "view=0.2,0,0,0,-0.0697564737441253,0,0.9975640502598242";

// Pixels of a render target in exactly this colour.
inline std::size_t pixelsOf(const render::RenderTarget& target, std::uint8_t r, std::uint8_t g,
                            std::uint8_t b) {
    const std::vector<std::uint8_t> rgba = target.readRgba();
    std::size_t n = 0;
    for (std::size_t i = 0; i + 3 < rgba.size(); i += 4)
        n += rgba[i] == r && rgba[i + 1] == g && rgba[i + 2] == b;
    return n;
}

// The index in `stamps` nearest `t`, worked out here from the recordings' own stamps.
inline std::size_t nearest(const std::vector<std::int64_t>& stamps, std::int64_t t) {
    std::size_t best = 0;
    for (std::size_t i = 1; i < stamps.size(); ++i)
        if (std::llabs(stamps[i] - t) < std::llabs(stamps[best] - t))
            best = i;
    return best;
}

class SourcesTest : public UiTest {
protected:
    void SetUp() override {
        UiTest::SetUp();
        ASSERT_FALSE(HasFatalFailure());
        const std::string name = ::testing::UnitTest::GetInstance()->current_test_info()->name();
        dir_ = std::filesystem::temp_directory_path() /
               ("dc-sources-" + std::to_string(::getpid()) + "-" + name);
        std::filesystem::remove_all(dir_);
        std::filesystem::create_directories(dir_);
    }
    void TearDown() override {
        UiTest::TearDown();
        std::filesystem::remove_all(dir_);
    }

    // Records `frames` frames of the running synthetic source with the real recorder.
    std::string record(const std::string& name, std::uint64_t frames) {
        const std::string path = (dir_ / name).string();
        EXPECT_TRUE(instrument_->startRecording(path).ok());
        for (int i = 0; i < 400 && instrument_->recording().frames < frames; ++i)
            viewer_->update(0.0, std::chrono::milliseconds(20));
        EXPECT_TRUE(instrument_->stopRecording().ok());
        return path;
    }

    static std::vector<std::int64_t> stampsOf(const std::string& path) {
        auto reader = devices::recording::RecordingReader::open(path);
        EXPECT_TRUE(reader.ok());
        std::vector<std::int64_t> stamps;
        for (std::size_t i = 0; reader && i < reader->frameCount(); ++i)
            stamps.push_back(reader->timestampNs(i));
        return stamps;
    }

    // Two recordings of the running synthetic source, B made after A (20 and 30 frames): B's clock is offset
    // from A's by A's whole span and more, so the two share no instant. With each one's stamps.
    struct OffsetPair {
        std::string a, b;
        std::vector<std::int64_t> stampsA, stampsB;
    };
    OffsetPair recordOffsetPair() {
        OffsetPair p;
        p.a = record("a.dcrec", 20);
        p.b = record("b.dcrec", 30);
        p.stampsA = stampsOf(p.a);
        p.stampsB = stampsOf(p.b);
        EXPECT_GE(p.stampsA.size(), 20u);
        EXPECT_GE(p.stampsB.size(), 30u);
        EXPECT_TRUE(!p.stampsA.empty() && !p.stampsB.empty() && p.stampsB.front() > p.stampsA.back());
        return p;
    }

    // `main` ("synthetic:WxH...") opened, the same camera beside it added, tinted green, the view still;
    // null (with a failure) when either cannot open.
    Companion* openGreenPair(const std::string& main) {
        EXPECT_TRUE(viewer_->openSource(main).ok());
        const Status added = viewer_->addSource(main + ":" + kBesideView);
        EXPECT_TRUE(added.ok());
        if (!added || viewer_->companions().empty())
            return nullptr;
        Companion& b = viewer_->companions()[0];
        b.look.tinted = true;
        b.look.tint = {0.0f, 1.0f, 0.0f};
        viewer_->settings().cloud.motion.enabled = false;
        return &b;
    }
    std::size_t greenPixels() { return pixelsOf(renderer_.cloudTarget(), 0, 255, 0); }

    std::filesystem::path dir_;
};

} // namespace dc::ui::test
