// libFuzzer harness: lt-reconstruct's input, an EXR (OpenEXR) or an lt buffer file, turned into the primal
// and gradient planes the Poisson solve takes (image/buffer_source.h, reconstruct/gradient_image.h).
#include "fuzz_input.h"
#include "image/buffer_source.h"
#include "reconstruct/gradient_image.h"

namespace {

void read(const std::string& path) {
    lt::fuzz::expectCleanRead([&] {
        const lt::BufferSource source = lt::loadBuffer(path);
        const lt::GradientImage image = lt::gradientImageFromBuffer(source.buffer, source.name);
        lt::validateGradientImage(image, source.name);
    });
}

} // namespace

// An lt buffer file is also read with its chunks' CRCs recomputed (fuzz_input.h); an EXR carries none.
extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    read(lt::fuzz::writeInput(data, size, "input"));
    if (size >= 4 && std::memcmp(data, "LTF\x01", 4) == 0) {
        const std::string fixed = lt::fuzz::withChunkChecksumsRecomputed(data, size);
        read(lt::fuzz::writeInput(reinterpret_cast<const uint8_t*>(fixed.data()), fixed.size(), "input"));
    }
    return 0;
}
