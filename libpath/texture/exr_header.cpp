#include "texture/exr_header.h"

#include <OpenEXR/openexr.h>

#include <array>
#include <fstream>

#include "util/error.h"
#include "util/memory_budget.h"
#include "util/one_line.h"

namespace lt {

namespace {

// OpenEXRCore reports the reason of a failure through a callback; the context keeps the last one.
struct CoreMessages {
    std::string last;
};

void keepMessage(exr_const_context_t context, exr_result_t code, const char* message) {
    void* user = nullptr;
    if (exr_get_user_data(context, &user) == EXR_ERR_SUCCESS && user)
        static_cast<CoreMessages*>(user)->last = message ? message : exr_get_default_error_message(code);
}

} // namespace

std::vector<ExrPartLayout> scanExrHeaders(const std::string& path) {
    if (!isExrFile(path)) throw Error(path + ": not an EXR file (no EXR magic number, or not readable)");
    CoreMessages messages;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = keepMessage;
    init.user_data = &messages;
    init.flags = EXR_CONTEXT_FLAG_STRICT_HEADER;
    exr_context_t context = nullptr;
    const auto fail = [&](exr_result_t code) {
        const std::string why = messages.last.empty() ? exr_get_default_error_message(code) : messages.last;
        if (context) exr_finish(&context);
        throw Error(path + ": damaged EXR header: " + oneLine(why));
    };
    if (const exr_result_t code = exr_start_read(&context, path.c_str(), &init); code != EXR_ERR_SUCCESS) fail(code);
    int count = 0;
    if (const exr_result_t code = exr_get_count(context, &count); code != EXR_ERR_SUCCESS) fail(code);
    std::vector<ExrPartLayout> parts;
    for (int part = 0; part < count; ++part) {
        exr_attr_box2i_t window;
        const exr_attr_chlist_t* channels = nullptr;
        int32_t chunks = 0;
        for (const exr_result_t code :
             {exr_get_data_window(context, part, &window), exr_get_channels(context, part, &channels),
              exr_get_chunk_count(context, part, &chunks)})
            if (code != EXR_ERR_SUCCESS) fail(code);
        parts.push_back({window.min.x, window.min.y, int64_t(window.max.x) - window.min.x + 1,
                         int64_t(window.max.y) - window.min.y + 1, channels ? channels->num_channels : 0,
                         int64_t(chunks)});
    }
    exr_finish(&context);
    if (parts.empty()) throw Error(path + ": damaged EXR header: no part");
    return parts;
}

bool isExrFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::array<char, 4> magic{};
    return in.read(magic.data(), 4) && magic == std::array<char, 4>{0x76, 0x2f, 0x31, 0x01};
}

void requireExrMemory(const std::string& path) {
    const std::vector<ExrPartLayout> parts = scanExrHeaders(path);
    double planes = 0, tables = 0;
    for (const ExrPartLayout& part : parts) {
        tables += 8.0 * double(part.chunks);
        const ExrPartLayout& first = parts.front();
        if (part.minX == first.minX && part.minY == first.minY && part.width == first.width &&
            part.height == first.height)
            planes += double(part.channels);
    }
    const ExrPartLayout& first = parts.front();
    requireMemory(double(first.width) * double(first.height) * planes * sizeof(float) + tables,
                  path + ": an EXR of " + std::to_string(first.width) + "x" + std::to_string(first.height) +
                      " pixels and " + std::to_string(int64_t(planes)) + " channels");
}

} // namespace lt
