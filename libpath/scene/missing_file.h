// The error for a file a scene names and the file system does not have. Scenes made on case-insensitive
// file systems ship `DARKOAK.jpg` and ask for `darkoak.JPG`; the message then names the file that exists.
#pragma once

#include <filesystem>
#include <string>

namespace lt {

// " (did you mean OTHER?)" when `path` does not exist and a path differing from it only in letter case
// does (each missing component matched case-insensitively in its directory); "" otherwise. Appended to
// the error that names the missing file.
[[nodiscard]] std::string didYouMean(const std::filesystem::path& path);

} // namespace lt
