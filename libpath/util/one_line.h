// Messages from libraries (OpenEXR, OpenImageIO) may span lines; the project's errors are one line each.
#pragma once

#include <string>

namespace lt {

// `message` with its line breaks turned into spaces and trailing ones dropped.
[[nodiscard]] inline std::string oneLine(std::string message) {
    for (char& c : message)
        if (c == '\n' || c == '\r') c = ' ';
    while (!message.empty() && message.back() == ' ')
        message.pop_back();
    return message;
}

} // namespace lt
