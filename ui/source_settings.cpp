#include "ui/source_settings.h"

#include <cctype>
#include <string_view>

namespace dc::ui {

Settings furtherSourceSettings(const Settings& main, const SourceSettings& own) {
    Settings s = main;
    s.panels.quality = false;
    s.accumulate.enabled = false;
    if (!own.followsMain) {
        s.processing = own.processing;
        s.cloud.minConfidence = own.minConfidence;
    }
    return s;
}

void followMain(SourceSettings& own, const Settings& main) {
    if (!own.followsMain)
        return;
    own.processing = main.processing;
    own.minConfidence = main.cloud.minConfidence;
}

std::optional<std::pair<std::size_t, std::string>> sourceScope(const std::string& assignment) {
    constexpr std::string_view kPrefix = "source";
    if (assignment.rfind(kPrefix, 0) != 0)
        return std::nullopt;
    std::size_t end = kPrefix.size();
    std::size_t number = 0;
    while (end < assignment.size() && std::isdigit(static_cast<unsigned char>(assignment[end])) &&
           number < 1000)
        number = number * 10 + static_cast<std::size_t>(assignment[end++] - '0');
    if (end == kPrefix.size() || end >= assignment.size() || assignment[end] != '.')
        return std::nullopt;
    return std::pair{number, assignment.substr(end + 1)};
}

Status applySourceSetting(SourceSettings& own, const Settings& main, const std::string& assignment) {
    const std::string name = assignment.substr(0, assignment.find('='));
    if (name.rfind("processing.", 0) != 0 && name != "cloud.minConfidence")
        return Error{"'" + name + "': a further source takes only processing.* and cloud.minConfidence"};
    followMain(own, main);
    Settings changed = furtherSourceSettings(main, {false, own.processing, own.minConfidence});
    if (Status s = applySetting(changed, assignment); !s)
        return s;
    own = {false, changed.processing, changed.cloud.minConfidence};
    return {};
}

} // namespace dc::ui
