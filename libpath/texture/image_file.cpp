#include "texture/image_file.h"

#include <OpenImageIO/imageio.h>
#include <OpenImageIO/strutil.h>

#include "math/error.h"

namespace lt {

namespace {
// OpenImageIO's messages may span lines; the project's errors are one line.
std::string oneLine(std::string message) {
    while (!message.empty() && (message.back() == '\n' || message.back() == '\r'))
        message.pop_back();
    for (char& c : message)
        if (c == '\n' || c == '\r') c = ' ';
    return message;
}
} // namespace

ImageFile readImageFile(const std::string& filename) {
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    auto in = OIIO::ImageInput::open(filename, &config);
    if (!in) throw Error(filename + ": cannot read image (" + oneLine(OIIO::geterror()) + ")");
    const OIIO::ImageSpec& spec = in->spec();
    ImageFile image;
    image.width = spec.width;
    image.height = spec.height;
    image.channels = spec.nchannels;
    image.channelNames.assign(spec.channelnames.begin(), spec.channelnames.end());
    image.channelNames.resize(size_t(image.channels));
    if (image.width <= 0 || image.height <= 0 || image.channels <= 0)
        throw Error(filename + ": cannot read image (empty image)");
    image.pixels.resize(size_t(image.width) * size_t(image.height) * size_t(image.channels));
    if (!in->read_image(0, 0, 0, image.channels, OIIO::TypeDesc::FLOAT, image.pixels.data()))
        throw Error(filename + ": cannot read image (" + oneLine(in->geterror()) + ")");
    in->close();
    image.floatFormat = spec.format.is_floating_point();
    image.saysLinear = OIIO::Strutil::iequals(spec.get_string_attribute("oiio:ColorSpace"), "Linear");
    return image;
}

} // namespace lt
