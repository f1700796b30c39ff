#pragma once

#include "base/expected.h"

#include <functional>
#include <string_view>

namespace dc::base {

// Runs `body` inside an exception barrier: whatever it throws (OpenCV throws cv::Exception, the standard
// library bad_alloc, a third-party library anything) comes back as an Error "<what>: <the exception's
// text>" instead of escaping. Every thread body of the project, and each item a long-lived thread works
// on, runs inside one, so no exception crosses a thread or ends the process.
Status guarded(std::string_view what, const std::function<void()>& body);

} // namespace dc::base
