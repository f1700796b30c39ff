#include "base/expected.h"
#include "tool/options.h"

#include <fstream>
#include <sstream>

namespace dc::tool {

Expected<ui::Settings> chosenSettings(ui::Settings saved, const ViewerOptions& options) {
    ui::Settings settings = std::move(saved);
    if (!options.settingsPath.empty()) {
        std::ifstream in(options.settingsPath);
        if (!in)
            return Error{"--settings " + options.settingsPath + ": cannot be read"};
        std::stringstream text;
        text << in.rdbuf();
        auto read = ui::settingsFromJson(text.str());
        if (!read)
            return Error{"--settings " + options.settingsPath + ": " + read.error().message};
        settings = std::move(*read);
    }
    for (const std::string& assignment : options.sets) {
        const auto scope = ui::sourceScope(assignment);
        if (scope && scope->first != 1)
            continue; // a further source's (furtherSourcesSettings)
        if (Status s = ui::applySetting(settings, scope ? scope->second : assignment); !s)
            return Error{"--set " + s.error().message};
    }
    if (options.confidence)
        settings.cloud.minConfidence = *options.confidence;
    return settings;
}

Expected<std::vector<ui::SourceSettings>> furtherSourcesSettings(const ui::Settings& main,
                                                                 const ViewerOptions& options) {
    std::vector<ui::SourceSettings> own(options.companions.size());
    for (const std::string& assignment : options.sets) {
        const auto scope = ui::sourceScope(assignment);
        if (!scope || scope->first == 1)
            continue;
        if (scope->first == 0 || scope->first > own.size() + 1)
            return Error{"--set " + assignment + ": there is no source " + std::to_string(scope->first) +
                         " (" + std::to_string(own.size() + 1) + " given with --source)"};
        if (Status s = ui::applySourceSetting(own[scope->first - 2], main, scope->second); !s)
            return Error{"--set " + assignment + ": " + s.error().message};
    }
    return own;
}

} // namespace dc::tool
