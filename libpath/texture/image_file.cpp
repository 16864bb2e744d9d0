#include "texture/image_file.h"

#include <dlfcn.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>

#include "util/error.h"
#include "texture/exr_header.h"

namespace lt {

namespace {

// The directories searched for the module, in order: $LT_MODULE_DIR when set, the running executable's (the
// tools' bin/), then the build tree's bin/ (LT_MODULE_DIR at compile time, for the test runner).
std::vector<std::filesystem::path> moduleDirectories() {
    std::vector<std::filesystem::path> dirs;
    if (const char* env = std::getenv("LT_MODULE_DIR"); env && *env) dirs.emplace_back(env);
    std::error_code ec;
    const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec) dirs.push_back(exe.parent_path());
#ifdef LT_MODULE_DIR
    dirs.emplace_back(LT_MODULE_DIR);
#endif
    return dirs;
}

// The entry point of the module at `path`, or nothing with the reason in `why` (not there, not loadable,
// another build's).
ImageReaderEntry openModule(const std::string& path, std::string& why) {
    if (access(path.c_str(), F_OK) != 0) {
        why = path + ": not there";
        return nullptr;
    }
    void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
        const char* e = dlerror();
        why = e ? e : path + ": cannot be loaded";
        return nullptr;
    }
    const auto abi = reinterpret_cast<ImageReaderAbi>(dlsym(handle, kImageReaderAbiEntry));
    const auto entry = reinterpret_cast<ImageReaderEntry>(dlsym(handle, kImageReaderEntry));
    if (!abi || !entry || abi() != kImageReaderAbi) {
        why = path + ": built for another version of lt";
        dlclose(handle);
        return nullptr;
    }
    return entry;
}

// Loads the module once (later calls reuse it; the first after a failure tries again) and returns its entry
// point; throws saying where it looked and what it found.
ImageReaderEntry imageReader() {
    static const ImageReaderEntry entry = [] {
        std::string tried;
        for (const auto& dir : moduleDirectories()) {
            std::string why;
            if (const ImageReaderEntry e = openModule((dir / kImageReaderModule).string(), why)) return e;
            tried += (tried.empty() ? "" : "; ") + why;
        }
        throw Error(std::string("no usable image reader module ") + kImageReaderModule + ", which is built beside " +
                    "the tools (" + tried + ")");
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
    // OpenImageIO reads EXRs through OpenEXR, which allocates what a header declares before reading it.
    if (isExrFile(filename)) requireExrMemory(filename);
    ImageFile image;
    std::string error;
    if (!read(filename.c_str(), &image, &error)) throw Error(filename + ": cannot read image (" + error + ")");
    return image;
}

} // namespace lt
