#pragma once

#include "devices/synthetic/synthetic_device.h"

namespace dc::test {

// The synthetic two-sensor rig at a quarter of its sizes (212x120 depth, 320x180 colour), to keep tests
// quick.
inline devices::SyntheticConfig smallRigConfig() {
    devices::SyntheticConfig config = devices::syntheticRigConfig();
    config.depthWidth = 212;
    config.depthHeight = 120;
    config.cameraWidth = 320;
    config.cameraHeight = 180;
    return config;
}

} // namespace dc::test
