#pragma once

#include <cmath>

namespace dc::processing::reference {

// The references' own test for a depth sample that holds a measurement (positive and finite), written
// apart from the product's frame::isMeasured so that a mistake there is not copied into the expectation.
inline bool measured(double d) {
    return std::isfinite(d) && d > 0.0;
}

} // namespace dc::processing::reference
