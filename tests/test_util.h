// Helpers shared by the tests: temporary directories and files, paths of the shipped scenes.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace lt::test {

// A fresh directory under the system temp dir, removed with everything in it at scope exit.
struct TempDir {
    std::filesystem::path path;
    TempDir() {
        static int counter = 0;
        path = std::filesystem::temp_directory_path() /
               ("lt_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
        std::filesystem::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(path, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;

    // Write a file (binary, exactly the given bytes) and return its full path.
    std::string write(const std::string& name, const std::string& contents) const {
        const auto p = path / name;
        std::filesystem::create_directories(p.parent_path());
        std::ofstream(p, std::ios::binary) << contents;
        return p.string();
    }
    [[nodiscard]] std::string file(const std::string& name) const { return (path / name).string(); }
};

// The shared public scenes (cornell-box, veach-mis, veach-bidir) beside the repository.
inline std::string sharedScene(const std::string& name) {
    return std::string(LT_SOURCE_DIR) + "/../shared/scenes/" + name + "/scene.xml";
}
inline std::string shippedScene(const std::string& name) {
    return std::string(LT_SOURCE_DIR) + "/scenes/" + name + "/scene.xml";
}

} // namespace lt::test
