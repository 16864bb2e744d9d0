// The module lt-image-reader.so (texture/image_file.h): OpenImageIO's reader behind one C entry point, built
// apart from libpath and loaded only when a scene reads an image.
#include <OpenImageIO/imageio.h>
#include <OpenImageIO/strutil.h>

#include <algorithm>
#include <exception>
#include <type_traits>

#include "util/one_line.h"
#include "texture/image_file.h"

namespace {

using lt::oneLine;

bool read(const std::string& filename, lt::ImageFile& image, std::string& error) {
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    auto in = OIIO::ImageInput::open(filename, &config);
    if (!in) {
        error = oneLine(OIIO::geterror());
        return false;
    }
    const OIIO::ImageSpec& spec = in->spec();
    image.width = spec.width;
    image.height = spec.height;
    image.channels = spec.nchannels;
    image.channelNames.assign(spec.channelnames.begin(), spec.channelnames.end());
    image.channelNames.resize(size_t(std::max(image.channels, 0)));
    if (image.width <= 0 || image.height <= 0 || image.channels <= 0) {
        error = "empty image";
        return false;
    }
    image.pixels.resize(size_t(image.width) * size_t(image.height) * size_t(image.channels));
    if (!in->read_image(0, 0, 0, image.channels, OIIO::TypeDesc::FLOAT, image.pixels.data())) {
        error = oneLine(in->geterror());
        return false;
    }
    in->close();
    image.floatFormat = spec.format.is_floating_point();
    image.saysLinear = OIIO::Strutil::iequals(spec.get_string_attribute("oiio:ColorSpace"), "Linear");
    return true;
}

} // namespace

extern "C" __attribute__((visibility("default"))) bool lt_read_image_file(const char* filename, lt::ImageFile* image,
                                                                          std::string* error) {
    try {
        return read(filename, *image, *error);
    } catch (const std::exception& e) {
        *error = oneLine(e.what());
    } catch (...) {
        *error = "unknown error";
    }
    return false;
}

extern "C" __attribute__((visibility("default"))) uint64_t lt_image_reader_abi() { return lt::kImageReaderAbi; }

// The entry points' types are those the loader casts to.
static_assert(std::is_same_v<decltype(&lt_read_image_file), lt::ImageReaderEntry>);
static_assert(std::is_same_v<decltype(&lt_image_reader_abi), lt::ImageReaderAbi>);
