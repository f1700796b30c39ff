#pragma once

#include "ui/settings.h"

#include <nlohmann/json.hpp>

#include <functional>
#include <string>
#include <vector>

namespace dc::ui {

// One value of the settings file: settingsToJson writes and settingsFromJson reads every field through
// this one entry, so the two cannot disagree, and the round-trip test sets each entry to its example.
struct SettingField {
    std::string section; // the JSON object holding it ("cloud", "processing", ...); empty: the top level
    std::string key;
    std::function<nlohmann::json(const Settings&)> write;
    // Sets the field from its JSON value; a value of the wrong type, or an enumerator out of range where
    // the field keeps its value then, leaves the field as it was.
    std::function<void(const nlohmann::json&, Settings&)> read;
    nlohmann::json example; // a valid value other than the default
};

// Every field of Settings that is saved, in the file's order.
const std::vector<SettingField>& settingFields();

} // namespace dc::ui
