#include "scene/missing_file.h"

#include <strings.h>

#include <optional>
#include <system_error>

namespace lt {

namespace {

namespace fs = std::filesystem;

// The existing path that equals `path` but for letter case, component by component.
std::optional<fs::path> caseInsensitiveMatch(const fs::path& path) {
    fs::path found = path.has_root_path() ? path.root_path() : fs::path();
    std::error_code ec;
    for (const fs::path& part : path.relative_path()) {
        const fs::path dir = found.empty() ? fs::path(".") : found;
        if (fs::exists(found / part, ec) && !ec) {
            found /= part;
            continue;
        }
        std::optional<fs::path> next;
        for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
            if (strcasecmp(it->path().filename().c_str(), part.c_str()) == 0) {
                next = found / it->path().filename();
                break;
            }
        if (!next) return std::nullopt;
        found = *next;
    }
    return found;
}

} // namespace

std::string didYouMean(const fs::path& path) {
    std::error_code ec;
    if (fs::exists(path, ec)) return {};
    const auto other = caseInsensitiveMatch(path);
    return other && *other != path ? " (did you mean " + other->string() + "?)" : "";
}

} // namespace lt
