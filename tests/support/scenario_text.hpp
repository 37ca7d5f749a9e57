// Editing a scenario's text before it is parsed (tests only): one key's value replaced in
// place, everything else kept, so a test runs a shipped .scn with a few values changed.
#pragma once

#include <cstddef>
#include <string>

namespace vtm::test {

// Replaces the value of the first line that starts with `key ` at or after `from`; false
// (text unchanged) when there is none, or when `before` is not npos and the line lies
// beyond it.
inline bool replaceScenarioLine(std::string& text, const std::string& key, const std::string& value,
                                std::size_t from = 0, std::size_t before = std::string::npos) {
    const std::size_t at = text.find("\n" + key + " ", from);
    if (at == std::string::npos || (before != std::string::npos && at > before)) return false;
    const std::size_t end = text.find('\n', at + 1);
    text.replace(at + 1, (end == std::string::npos ? text.size() : end) - at - 1, key + " " + value);
    return true;
}

// The first `key` of the text (a key at a line start, as the scenario format has them).
inline bool setScenarioValue(std::string& text, const std::string& key, const std::string& value) {
    return replaceScenarioLine(text, key, value);
}

// `key` inside [section] only.
inline bool setScenarioValueInSection(std::string& text, const std::string& section, const std::string& key,
                                      const std::string& value) {
    const std::size_t s = text.find("[" + section + "]");
    if (s == std::string::npos) return false;
    return replaceScenarioLine(text, key, value, s, text.find("\n[", s + 1));
}

}  // namespace vtm::test
