#include "devices/source_spec.h"
#include "devices/synthetic/synthetic_device.h"

#include <gtest/gtest.h>

#include <utility>

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

TEST(SourceSpec, APlaneTakesItsDistanceTiltAndNoise) {
    auto d = openSourceSpec("synthetic:640x480:plane=1.5,10,2");
    ASSERT_TRUE(d.ok()) << d.error().message;
    ASSERT_TRUE(configOf(*d).flatTarget.has_value());
    EXPECT_EQ(*configOf(*d).flatTarget, (FlatTarget{1.5, 10.0, 2.0}));
    auto defaultNoise = openSourceSpec("synthetic:plane=0.8,-30");
    ASSERT_TRUE(defaultNoise.ok()) << defaultNoise.error().message;
    EXPECT_EQ(*configOf(*defaultNoise).flatTarget, (FlatTarget{0.8, -30.0, 1.0}));
}

TEST(SourceSpec, ABadPlaneNamesWhatIsWrong) {
    const std::pair<const char*, const char*> cases[] = {
        {"synthetic:plane=", "malformed plane=''"},
        {"synthetic:plane=1.5", "malformed plane='1.5'"},
        {"synthetic:plane=1.5,x", "malformed plane='1.5,x'"},
        {"synthetic:plane=1.5,10,1,4", "malformed plane='1.5,10,1,4'"},
        {"synthetic:plane=0,10", "plane distance must be in (0, 5] m"},
        {"synthetic:plane=6,10", "plane distance must be in (0, 5] m"},
        {"synthetic:plane=1,86", "plane tilt must be within 85 degrees"},
        {"synthetic:plane=1,10,-1", "plane noise must be in [0, 100] mm"}};
    for (const auto& [spec, message] : cases) {
        auto d = openSourceSpec(spec);
        ASSERT_FALSE(d.ok()) << spec;
        EXPECT_NE(d.error().message.find(message), std::string::npos) << spec << ": " << d.error().message;
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
