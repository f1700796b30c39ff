#pragma once

#include "ui/presenter.h"

#include <string>

namespace dc::tool {

// summary.json: what a run measured (frames, rates, per-stage medians, points, drops).
std::string summaryJson(const ui::ViewerSummary& summary, const std::string& renderer,
                        const std::string& mode);

} // namespace dc::tool
