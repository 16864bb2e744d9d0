#include "image/buffer_source.h"

#include <optional>
#include <variant>

#include "formats/ltfile.h"
#include "image/image_io.h"
#include "util/error.h"

namespace lt {

BufferSource loadBuffer(const std::string& path) {
    if (path != "-" && isExrFile(path)) return {readExr(path), nullptr, path, "EXR"};
    // Stream the chunks and keep only the last of each kind: snapshots can be many full-size buffers.
    file::Reader reader(path, file::FileKind::Buffer);
    std::optional<file::Buffer> last;
    std::optional<file::Buffer> lastSnapshot;
    size_t snapshots = 0;
    for (;;) {
        file::Chunk chunk = reader.next();
        if (std::holds_alternative<file::End>(chunk)) break;
        if (auto* b = std::get_if<file::Buffer>(&chunk)) last = std::move(*b);
        if (auto* s = std::get_if<file::Snapshot>(&chunk)) {
            lastSnapshot = std::move(s->buffer);
            ++snapshots;
        }
    }
    if (last) return {std::move(*last), reader.info(), reader.name(), "BUFR"};
    if (lastSnapshot)
        return {std::move(*lastSnapshot), reader.info(), reader.name(),
                "SNAP " + std::to_string(snapshots) + " of " + std::to_string(snapshots)};
    throw Error(reader.name() + ": holds no buffer (no BUFR or SNAP chunk)");
}

} // namespace lt
