#pragma once

#include "base/expected.h"
#include "ui/settings.h"

#include <cstddef>
#include <optional>
#include <string>
#include <utility>

namespace dc::ui {

// A further source's processing and cloud confidence. While it follows the main source it takes the main
// source's; given its own (the Sources panel's "Own processing", or --set sourceN.NAME=VALUE), it keeps
// them whatever the main source's become.
struct SourceSettings {
    bool followsMain = true;
    processing::ProcessingSettings processing;
    frame::Confidence minConfidence = frame::Confidence::Low;
};

// What a further source processes and draws with: the main source's settings, less what only the main
// source does (the Quality panel's region, accumulation), with its own processing and confidence when
// it has them.
Settings furtherSourceSettings(const Settings& main, const SourceSettings& own);

// Takes the main source's processing and confidence while `own` follows them, so that "Own processing"
// starts from what the source was shown with.
void followMain(SourceSettings& own, const Settings& main);

// "sourceN.SECTION.KEY=VALUE" names source N (2 or more: the first --source is source 1) and the
// assignment without its prefix; none for an assignment without that prefix.
std::optional<std::pair<std::size_t, std::string>> sourceScope(const std::string& assignment);

// Applies an unprefixed assignment to a further source's own settings: a processing.* setting or
// cloud.minConfidence, as named in the settings file. The first one takes the main source's values as
// its start. Any other name is an error saying what a further source takes.
Status applySourceSetting(SourceSettings& own, const Settings& main, const std::string& assignment);

} // namespace dc::ui
