// libFuzzer harness: the OBJ mesh loader with its validation (scene/mesh.h), as a scene's shape reads it.
#include "fuzz_input.h"
#include "scene/mesh.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string path = lt::fuzz::writeInput(data, size, "input.obj");
    lt::fuzz::expectCleanRead([&] {
        lt::MeshLoadReport report;
        (void)lt::loadObj(path, report);
    });
    return 0;
}
