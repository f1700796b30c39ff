// Test binaries are not beside the video module, which depthcloud finds beside itself. However they are
// run (by ctest, by hand, by the sanitizer scripts), they load the build's own module, unless
// DC_VIDEO_MODULE already names another; the programs they start inherit it.

#include <cstdlib>

namespace {

[[maybe_unused]] const bool kVideoModuleNamed = ::setenv("DC_VIDEO_MODULE", DC_TEST_VIDEO_MODULE, 0) == 0;

} // namespace
