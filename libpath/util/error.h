// The one exception type of libpath. Its message names the file, line or field that is wrong, so a
// tool can print it as its single error line (nothing in libpath prints or exits).
#pragma once

#include <stdexcept>
#include <string>

namespace lt {

class Error : public std::runtime_error {
public:
    explicit Error(const std::string& message) : std::runtime_error(message) {}
};

} // namespace lt
