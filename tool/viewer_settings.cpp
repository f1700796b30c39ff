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
    for (const std::string& assignment : options.sets)
        if (Status s = ui::applySetting(settings, assignment); !s)
            return Error{"--set " + s.error().message};
    if (options.confidence)
        settings.cloud.minConfidence = *options.confidence;
    return settings;
}

} // namespace dc::tool
