#pragma once

#include "ui/presenter.h"

#include <string>
#include <vector>

namespace dc::tool {

// summary.json: what a run measured (frames, rates, per-stage medians, points, drops), and each further
// source's own figures under "companions".
std::string summaryJson(const ui::ViewerSummary& summary, const std::string& renderer,
                        const std::string& mode, const std::vector<ui::ViewerSummary>& companions = {});

} // namespace dc::tool
