#include "devices/source_spec.h"
#include "devices/synthetic/synthetic_device.h"

#include <gtest/gtest.h>

namespace dc::devices {
namespace {

const SyntheticConfig& configOf(const std::unique_ptr<Device>& d) {
    return dynamic_cast<const SyntheticDevice&>(*d).config();
}

TEST(SourceSpec, SyntheticDefaultsToLidarLikeDepth) {
    auto d = openSourceSpec("synthetic");
    ASSERT_TRUE(d.ok());
    EXPECT_EQ(configOf(*d).depthWidth, 256);
    EXPECT_EQ(configOf(*d).depthHeight, 192);
    EXPECT_DOUBLE_EQ(configOf(*d).fps, 60.0);
}

TEST(SourceSpec, SyntheticModeAndOptions) {
    auto d = openSourceSpec("synthetic:640x480@30:motion:exact");
    ASSERT_TRUE(d.ok()) << d.error().message;
    EXPECT_EQ(configOf(*d).depthWidth, 640);
    EXPECT_EQ(configOf(*d).depthHeight, 480);
    EXPECT_DOUBLE_EQ(configOf(*d).fps, 30.0);
    EXPECT_TRUE(configOf(*d).motion);
    EXPECT_FALSE(configOf(*d).noise);
    auto sizeOnly = openSourceSpec("synthetic:320x240");
    ASSERT_TRUE(sizeOnly.ok());
    EXPECT_DOUBLE_EQ(configOf(*sizeOnly).fps, 60.0);
}

TEST(SourceSpec, MalformedModesNameTheProblem) {
    for (const char* bad : {"synthetic:640", "synthetic:640x", "synthetic:x480", "synthetic:640x480@",
                            "synthetic:640x480@abc", "synthetic:-5x4", "synthetic:0x480",
                            "synthetic:640x480@0", "synthetic:640x480@-3", "synthetic:64ox480"}) {
        auto d = openSourceSpec(bad);
        ASSERT_FALSE(d.ok()) << bad;
        EXPECT_NE(d.error().message.find("malformed mode"), std::string::npos) << bad;
    }
}

TEST(SourceSpec, UnknownSourceIsRejectedWithTheGrammar) {
    auto d = openSourceSpec("kinect");
    ASSERT_FALSE(d.ok());
    EXPECT_NE(d.error().message.find("unknown source 'kinect'"), std::string::npos);
    EXPECT_NE(d.error().message.find("synthetic[:WxH"), std::string::npos);
}

} // namespace
} // namespace dc::devices
