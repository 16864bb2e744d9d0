// libFuzzer harness: the Mitsuba serialized mesh loader with its validation (scene/mesh.h): the first and the
// second mesh of the file, as a scene's shape with shapeIndex 0 or 1 reads them (the dictionary of offsets at
// the file's end is read either way).
#include "fuzz_input.h"
#include "scene/mesh.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string path = lt::fuzz::writeInput(data, size, "input.serialized");
    for (int shapeIndex : {0, 1})
        lt::fuzz::expectCleanRead([&] {
            lt::MeshLoadReport report;
            (void)lt::loadSerialized(path, shapeIndex, report);
        });
    return 0;
}
