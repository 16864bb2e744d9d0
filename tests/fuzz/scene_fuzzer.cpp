// libFuzzer harness: the Mitsuba XML scene parser and the scene builder behind it (scene/scene.h loadScene),
// everything a tool does with a scene before rendering: syntax, includes, defaults, plugins, transforms,
// meshes, textures, emitters, the acceleration structure.
//
// Sandboxed: each input is loaded as scene.xml from a private directory that holds only it and the assets
// of tests/fuzz/assets (a mesh of each format, a texture, an included file), which the dictionary (scene.dict)
// names, so the file references the fuzzer builds reach those. Absolute paths and ".." are not barred, but
// neither the corpus nor the dictionary holds one.
#include <filesystem>

#include "fuzz_input.h"
#include "scene/scene.h"

#ifndef LT_FUZZ_ASSETS
#error "LT_FUZZ_ASSETS: the directory of the scene harness's assets (CMakeLists.txt sets it)"
#endif

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    std::filesystem::copy(LT_FUZZ_ASSETS, lt::fuzz::privateDirectory(), std::filesystem::copy_options::recursive);
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string path = lt::fuzz::writeInput(data, size, "scene.xml");
    lt::fuzz::expectCleanRead([&] { (void)lt::loadScene(path); });
    return 0;
}
