// libFuzzer harness: the one reader of lt's files (formats/ltfile.h), every chunk kind (INFO, PATH, CHST,
// BUFR, SNAP, STAT, END! and unknown ones), as lt-inspect, lt-image and lt-mutate read them, and every
// buffer through the check lt-image and lt-error apply before developing it.
#include "formats/ltfile.h"
#include "fuzz_input.h"
#include "image/image_io.h"

namespace {

void read(const std::string& path) {
    lt::fuzz::expectCleanRead([&] {
        const lt::file::Content content = lt::file::readAll(path);
        for (const lt::file::Buffer& buffer : content.buffers)
            lt::checkBuffer(buffer, content.name);
        for (const lt::file::Snapshot& snapshot : content.snapshots)
            lt::checkBuffer(snapshot.buffer, content.name);
    });
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    read(lt::fuzz::writeInput(data, size, "input.lt"));
    const std::string fixed = lt::fuzz::withChunkChecksumsRecomputed(data, size);
    read(lt::fuzz::writeInput(reinterpret_cast<const uint8_t*>(fixed.data()), fixed.size(), "input.lt"));
    return 0;
}
