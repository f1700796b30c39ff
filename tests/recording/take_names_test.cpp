#include "devices/recording/take_names.h"
#include "tests/recording/recording_test_support.h"

#include <gtest/gtest.h>

#include <fstream>

namespace dc::devices::recording {
namespace {

TEST(TakeNames, NumbersFromOneAndGoesPastTheHighestTakeThere) {
    test::TempDir dir;
    auto first = nextTakePath(dir.path());
    ASSERT_TRUE(first) << first.error().message;
    EXPECT_EQ(*first, dir.path("depthcloud-recording-001.dcrec"));

    for (const char* name : {"depthcloud-recording-001.dcrec", "depthcloud-recording-007.dcrec.partial",
                             "depthcloud-recording-3.dcrec", "depthcloud-recording-900.txt",
                             "other-recording-950.dcrec", "depthcloud-recording-x.dcrec"})
        std::ofstream(dir.path(name)) << "x";
    auto next = nextTakePath(dir.path());
    ASSERT_TRUE(next);
    EXPECT_EQ(*next, dir.path("depthcloud-recording-008.dcrec"))
        << "after an interrupted take 007, never over it; other names do not count";

    std::ofstream(dir.path("depthcloud-recording-999.dcrec")) << "x";
    EXPECT_EQ(*nextTakePath(dir.path()), dir.path("depthcloud-recording-1000.dcrec")) << "a fourth digit";
}

TEST(TakeNames, AMissingDirectoryIsAnError) {
    test::TempDir dir;
    auto next = nextTakePath(dir.path("gone"));
    ASSERT_FALSE(next);
    EXPECT_NE(next.error().message.find("gone"), std::string::npos);
}

} // namespace
} // namespace dc::devices::recording
