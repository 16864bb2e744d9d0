#include "texture/image_file.h"

#include <dlfcn.h>
#include <unistd.h>

#include <filesystem>

#include "math/error.h"

namespace lt {

namespace {

// The directories searched for the module, in order: the running executable's (the tools' bin/), then the
// build tree's bin/ (LT_MODULE_DIR, for the test runner beside it).
std::vector<std::filesystem::path> moduleDirectories() {
    std::vector<std::filesystem::path> dirs;
    std::error_code ec;
    const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec) dirs.push_back(exe.parent_path());
#ifdef LT_MODULE_DIR
    dirs.emplace_back(LT_MODULE_DIR);
#endif
    return dirs;
}

// Loads the module once (later calls reuse it) and returns its entry point; throws naming what failed.
ImageReaderEntry imageReader() {
    static const ImageReaderEntry entry = [] {
        std::string tried;
        for (const auto& dir : moduleDirectories()) {
            const std::string path = (dir / kImageReaderModule).string();
            if (access(path.c_str(), F_OK) != 0) {
                tried += (tried.empty() ? "" : ", ") + path;
                continue;
            }
            void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
            if (!handle) throw Error(std::string("cannot load the image reader module: ") + dlerror());
            void* symbol = dlsym(handle, kImageReaderEntry);
            if (!symbol) throw Error(path + ": no entry point " + kImageReaderEntry + " (a stale build?)");
            return reinterpret_cast<ImageReaderEntry>(symbol);
        }
        throw Error(std::string("cannot find the image reader module ") + kImageReaderModule + " (looked for " +
                    tried + "; it is built beside the tools)");
    }();
    return entry;
}

} // namespace

ImageFile readImageFile(const std::string& filename) {
    ImageReaderEntry read;
    try {
        read = imageReader();
    } catch (const Error& e) {
        throw Error(filename + ": cannot read image (" + e.what() + ")");
    }
    ImageFile image;
    std::string error;
    if (!read(filename.c_str(), &image, &error)) throw Error(filename + ": cannot read image (" + error + ")");
    return image;
}

} // namespace lt
