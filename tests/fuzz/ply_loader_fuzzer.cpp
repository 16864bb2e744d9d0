// libFuzzer harness: the PLY mesh loader with its validation (scene/mesh.h), as a scene's shape reads it.
#include "fuzz_input.h"
#include "scene/mesh.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string path = lt::fuzz::writeInput(data, size, "input.ply");
    lt::fuzz::expectCleanRead([&] {
        lt::MeshLoadReport report;
        (void)lt::loadPly(path, report);
    });
    return 0;
}
