// The one reading of a number a user wrote (a scene attribute, an option's value, an item of a list in an
// option): decimal or scientific notation, surrounding white space and a leading '+' allowed, the whole text
// used up. std::from_chars, so the locale never changes what "0.5" means.
#pragma once

#include <cctype>
#include <charconv>
#include <optional>
#include <string_view>

namespace lt {

// The number the text holds, infinities and NaN included ("inf", "nan": callers that need a finite value say
// so in their own words); nothing when the text is not one number or its magnitude is beyond a double's range.
inline std::optional<double> numberFromText(std::string_view text) {
    const auto space = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
    while (!text.empty() && space(text.front()))
        text.remove_prefix(1);
    while (!text.empty() && space(text.back()))
        text.remove_suffix(1);
    if (!text.empty() && text.front() == '+') {
        text.remove_prefix(1);
        if (!text.empty() && text.front() == '-') return std::nullopt; // "+-1"
    }
    if (text.empty()) return std::nullopt;
    double value = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
    return value;
}

} // namespace lt
