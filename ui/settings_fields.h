#pragma once

#include "ui/settings.h"

#include <nlohmann/json.hpp>

#include <functional>
#include <optional>
#include <string>
#include <string_view>
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
    // A choice's names, the i-th naming the value stored as i (the file keeps the index, so files written
    // before the names existed still read); empty for a field that is not a choice.
    std::vector<std::string> names;
};

// The index `text` names among `field`'s names, compared without regard to case; none when it names none.
std::optional<int> choiceIndex(const SettingField& field, std::string_view text);

// Every field of Settings that is saved, in the file's order.
const std::vector<SettingField>& settingFields();

} // namespace dc::ui
