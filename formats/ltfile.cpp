// lt::file::Writer and Reader, the container of formats/SPEC.md. A payload is encoded into memory and
// written as one chunk (tag, length, payload, CRC-32); the reader pulls a whole chunk, checks its CRC, and
// only then decodes it, checking every count against the bytes left in the payload before allocating.
#include "formats/ltfile.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string_view>
#include <system_error>
#include <type_traits>

#include "util/error.h"
#include "util/temp_output.h"

namespace lt::file {
namespace {

constexpr std::array<unsigned char, 4> kMagic{'L', 'T', 'F', 0x01};
constexpr size_t kFileHeaderSize = 12;   // magic, version, kind
constexpr size_t kChunkHeaderSize = 12;  // tag, length
constexpr size_t kCrcSize = 4;
constexpr size_t kPathHeaderSize = 68;   // SPEC.md "PATH"
constexpr size_t kVertexSize = 104;
constexpr size_t kRoundHeaderSize = 44; // SPEC.md "CHST"
constexpr size_t kStateHeaderSize = 38;
constexpr size_t kStateLightVertexSize = 64;
constexpr size_t kStateSurfaceVertexSize = 25;
// Far above any real chunk (a 8192 x 8192 buffer with 64 planes is 16 GiB) yet below what a damaged
// high bit of the length declares; beyond this a chunk is called damaged without reading it.
constexpr uint64_t kMaxChunkLength = uint64_t(1) << 36;
constexpr uint64_t kMaxInfoLength = uint64_t(1) << 24;
// Payloads are read in pieces that at most double what has arrived, so a damaged length on a pipe costs
// no more memory than the data that is really there.
constexpr size_t kFirstReadPiece = size_t(1) << 20;

constexpr std::string_view kInfo = "INFO", kPath = "PATH", kChst = "CHST", kBufr = "BUFR", kSnap = "SNAP",
                           kStat = "STAT", kEnd = "END!";

enum class CombineCode : uint32_t { WeightedMean = 1, Sum = 2 };

std::string errnoText(int err) { return std::generic_category().message(err); }

// INFO is a flat object with a few nested levels; JSON nested thousands of levels deep is a damaged or
// hostile file, and copying, printing or freeing such a value recurses once per level (stack overflow).
constexpr int kMaxInfoNesting = 64;

const char* kindName(FileKind kind) { return kind == FileKind::Paths ? "paths" : "buffer"; }

uint32_t le32(const unsigned char* p) {
    return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}
uint64_t le64(const unsigned char* p) { return uint64_t(le32(p)) | uint64_t(le32(p + 4)) << 32; }
void putLe32(unsigned char* p, uint32_t v) {
    for (int i = 0; i < 4; ++i) p[i] = static_cast<unsigned char>(v >> (8 * i));
}
void putLe64(unsigned char* p, uint64_t v) {
    putLe32(p, static_cast<uint32_t>(v));
    putLe32(p + 4, static_cast<uint32_t>(v >> 32));
}

uint32_t crc(uint32_t running, const void* data, size_t n) {
    // zlib's crc32 of a null pointer is its initial value, not "nothing added" (an empty vector's data()
    // may be null).
    if (n == 0) return running;
    return static_cast<uint32_t>(crc32_z(running, static_cast<const Bytef*>(data), n));
}

// A tag as it appears in messages; a damaged tag may hold bytes that are not printable.
std::string printableTag(std::string_view tag) {
    std::string out;
    for (const char c : tag) {
        if (c >= 0x20 && c < 0x7f) {
            out += c;
        } else {
            char hex[8];
            std::snprintf(hex, sizeof hex, "\\x%02x", unsigned(static_cast<unsigned char>(c)));
            out += hex;
        }
    }
    return out;
}

// ---- encoding ----------------------------------------------------------------------------------

class Encoder {
public:
    Encoder() = default;
    // Appends to `out` instead of a string of its own.
    explicit Encoder(std::string& out) : out_(&out) {}
    Encoder(const Encoder&) = delete;
    Encoder& operator=(const Encoder&) = delete;

    template <class T> void put(T value) {
        if constexpr (std::is_floating_point_v<T>) {
            using Bits = std::conditional_t<sizeof(T) == 4, uint32_t, uint64_t>;
            put(std::bit_cast<Bits>(value));
        } else if constexpr (std::is_enum_v<T>) {
            put(static_cast<std::underlying_type_t<T>>(value));
        } else if constexpr (std::endian::native == std::endian::little) {
            out_->append(reinterpret_cast<const char*>(&value), sizeof(T));
        } else {
            const auto bits = static_cast<std::make_unsigned_t<T>>(value);
            for (size_t i = 0; i < sizeof(T); ++i)
                *out_ += static_cast<char>(bits >> (8 * i));
        }
    }
    template <class T, size_t N> void put(const std::array<T, N>& values) {
        for (const T& v : values) put(v);
    }
    void putString(const std::string& s) {
        put(static_cast<uint32_t>(s.size()));
        *out_ += s;
    }
    template <class T> void putArray(const std::vector<T>& values) {
        if constexpr (std::endian::native == std::endian::little) {
            out_->append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
        } else {
            for (const T& v : values) put(v);
        }
    }
    [[nodiscard]] const std::string& bytes() const { return *out_; }

private:
    std::string own_;
    std::string* out_ = &own_;
};

void encodePaths(Encoder& e, std::span<const PathRecord> paths, const std::string& file) {
    if (paths.size() > UINT32_MAX) throw Error(file + ": more than 2^32-1 paths in one batch");
    e.put(static_cast<uint32_t>(paths.size()));
    for (const PathRecord& path : paths) {
        if (path.vertices.size() > UINT32_MAX) throw Error(file + ": a path with more than 2^32-1 vertices");
        e.put(static_cast<uint32_t>(path.vertices.size()));
        e.put(path.raster);
        e.put(path.s);
        e.put(path.t);
        e.put(path.contribution);
        e.put(path.pdf);
        e.put(path.misWeight);
        e.put(path.weight);
        e.put(path.rngStream);
        e.put(path.rngOffset);
        for (const VertexRecord& v : path.vertices) {
            e.put(v.kind);
            e.put(v.lobe);
            e.put(v.flags);
            e.put(v.reserved);
            e.put(v.shape);
            e.put(v.prim);
            e.put(v.coords);
            e.put(v.p);
            e.put(v.ng);
            e.put(v.ns);
            e.put(v.bsdf);
            e.put(v.light);
            e.put(v.roughness);
            e.put(v.pdfFwd);
            e.put(v.pdfRev);
        }
    }
}

// Only what re-creates a chain state's vertices (records.h ChainState): the light vertex, then the
// surface vertices; the camera vertex is implied.
void encodeChainState(Encoder& e, const ChainState& s) {
    if (s.vertices.size() < 2 || s.vertices.size() > UINT16_MAX)
        throw Error("a chain state with " + std::to_string(s.vertices.size()) + " vertices");
    e.put(s.chain);
    e.put(s.credit);
    e.put(s.raster);
    e.put(s.f);
    e.put(s.target);
    e.put(static_cast<uint16_t>(s.vertices.size()));
    const VertexRecord& l = s.vertices.front();
    e.put(l.light);
    e.put(l.shape);
    e.put(l.prim);
    e.put(l.coords);
    e.put(l.p);
    e.put(l.ng);
    for (size_t i = 1; i + 1 < s.vertices.size(); ++i) {
        const VertexRecord& v = s.vertices[i];
        e.put(v.lobe);
        e.put(v.shape);
        e.put(v.prim);
        e.put(v.coords);
    }
}

void encodeRoundHeader(Encoder& e, const ChainRound& r, uint64_t states, const std::string& file) {
    if (states > UINT32_MAX) throw Error(file + ": more than 2^32-1 chain states in one round");
    e.put(r.mutations);
    e.put(r.b);
    e.put(r.bSamples);
    e.put(r.wallSeconds);
    e.put(r.cpuSeconds);
    e.put(static_cast<uint32_t>(states));
}

// A buffer's header: its size, channels, combine rule, weight and channel names (the planes follow).
void encodeBufferHeader(Encoder& e, const Buffer& b, const std::string& file) {
    const uint64_t pixels = uint64_t(b.width) * b.height;
    if (b.planes.size() != b.channels.size())
        throw Error(file + ": buffer has " + std::to_string(b.channels.size()) + " channel names but " +
                    std::to_string(b.planes.size()) + " planes");
    for (size_t c = 0; c < b.planes.size(); ++c)
        if (b.planes[c].size() != pixels)
            throw Error(file + ": buffer plane \"" + b.channels[c] + "\" has " + std::to_string(b.planes[c].size()) +
                        " values for " + std::to_string(b.width) + "x" + std::to_string(b.height) + " pixels");
    if (!b.sampleCounts.empty() && b.sampleCounts.size() != pixels)
        throw Error(file + ": buffer has " + std::to_string(b.sampleCounts.size()) + " sample counts for " +
                    std::to_string(pixels) + " pixels");
    if (!(std::isfinite(b.weight) && b.weight >= 0))
        throw Error(file + ": buffer merge weight " + std::to_string(b.weight) + " is not finite and >= 0");
    CombineCode combine;
    if (b.combine == "weighted-mean") combine = CombineCode::WeightedMean;
    else if (b.combine == "sum") combine = CombineCode::Sum;
    else throw Error(file + ": unknown buffer combine rule \"" + b.combine + "\" (weighted-mean or sum)");

    e.put(b.width);
    e.put(b.height);
    e.put(static_cast<uint32_t>(b.channels.size()));
    e.put(combine);
    e.put(uint32_t(b.sampleCounts.empty() ? 0 : 1));
    e.put(b.weight);
    for (const std::string& name : b.channels)
        e.putString(name);
}

template <class T> std::string_view bytesOf(const std::vector<T>& values) {
    return {reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T)};
}

// A buffer's payload as the pieces of a chunk, after what `e` already holds: the header in e, then the
// planes and sample counts. The format is little-endian; on such a machine the arrays are handed out as
// they lie in memory, so a large image is not copied a second time to be written (a 1024^2 RGB buffer
// with its counts is 16 MiB).
std::vector<std::string_view> bufferPieces(Encoder& e, const Buffer& b, const std::string& file) {
    encodeBufferHeader(e, b, file);
    if constexpr (std::endian::native == std::endian::little) {
        std::vector<std::string_view> pieces{e.bytes()};
        for (const auto& plane : b.planes)
            pieces.push_back(bytesOf(plane));
        pieces.push_back(bytesOf(b.sampleCounts));
        return pieces;
    } else {
        for (const auto& plane : b.planes)
            e.putArray(plane);
        e.putArray(b.sampleCounts);
        return {e.bytes()};
    }
}

std::vector<std::string_view> snapshotPieces(Encoder& e, const Snapshot& s, const std::string& file) {
    e.put(s.wallSeconds);
    e.put(s.cpuSeconds);
    e.put(s.samples);
    e.put(s.overheadSeconds);
    return bufferPieces(e, s.buffer, file);
}

void encodeStats(Encoder& e, const StatTable& t, const std::string& file) {
    if (t.values.size() != t.rows.size())
        throw Error(file + ": statistics table \"" + t.name + "\" has " + std::to_string(t.rows.size()) +
                    " row names but " + std::to_string(t.values.size()) + " rows");
    for (size_t r = 0; r < t.values.size(); ++r)
        if (t.values[r].size() != t.columns.size())
            throw Error(file + ": statistics table \"" + t.name + "\" row \"" + t.rows[r] + "\" has " +
                        std::to_string(t.values[r].size()) + " values for " + std::to_string(t.columns.size()) +
                        " columns");
    e.putString(t.name);
    e.put(static_cast<uint32_t>(t.columns.size()));
    e.put(static_cast<uint32_t>(t.rows.size()));
    for (const std::string& c : t.columns) e.putString(c);
    for (const std::string& r : t.rows) e.putString(r);
    for (const auto& row : t.values) e.putArray(row);
}

// ---- decoding ----------------------------------------------------------------------------------

// What is wrong inside a payload; the Reader adds the file, chunk and offset.
struct PayloadError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

class Decoder {
public:
    explicit Decoder(std::string_view bytes) : bytes_(bytes) {}

    template <class T> T get() {
        if constexpr (std::is_floating_point_v<T>) {
            using Bits = std::conditional_t<sizeof(T) == 4, uint32_t, uint64_t>;
            return std::bit_cast<T>(get<Bits>());
        } else {
            need(1, sizeof(T), "a value");
            std::make_unsigned_t<T> bits = 0;
            for (size_t i = 0; i < sizeof(T); ++i)
                bits |= static_cast<std::make_unsigned_t<T>>(static_cast<unsigned char>(bytes_[pos_ + i])) << (8 * i);
            pos_ += sizeof(T);
            return static_cast<T>(bits);
        }
    }
    template <class T, size_t N> void get(std::array<T, N>& values) {
        for (T& v : values) v = get<T>();
    }
    std::string getString(const char* what) {
        const uint32_t n = get<uint32_t>();
        need(n, 1, what);
        std::string s(bytes_.substr(pos_, n));
        pos_ += n;
        return s;
    }
    template <class T> void getArray(std::vector<T>& values, uint64_t count, const char* what) {
        need(count, sizeof(T), what);
        values.resize(size_t(count));
        if (values.empty()) return;   // data() may be null, which memcpy must not get
        if constexpr (std::endian::native == std::endian::little) {
            std::memcpy(values.data(), bytes_.data() + pos_, values.size() * sizeof(T));
            pos_ += values.size() * sizeof(T);
        } else {
            for (T& v : values) v = get<T>();
        }
    }
    // Before allocating for `count` items of `size` bytes: are they there?
    void need(uint64_t count, uint64_t size, const char* what) const {
        const uint64_t left = bytes_.size() - pos_;
        if (size != 0 && count > left / size)
            throw PayloadError(std::string(what) + " need " + std::to_string(count) + " x " + std::to_string(size) +
                               " bytes but the payload has " + std::to_string(left) + " left");
    }
    void expectEnd() const {
        if (pos_ != bytes_.size())
            throw PayloadError(std::to_string(bytes_.size() - pos_) + " bytes left over after the content");
    }

private:
    std::string_view bytes_;
    size_t pos_ = 0;
};

std::vector<PathRecord> decodePaths(Decoder& d) {
    const uint32_t count = d.get<uint32_t>();
    d.need(count, kPathHeaderSize, "the paths");
    std::vector<PathRecord> paths(count);
    for (PathRecord& path : paths) {
        const uint32_t vertices = d.get<uint32_t>();
        d.get(path.raster);
        path.s = d.get<uint16_t>();
        path.t = d.get<uint16_t>();
        d.get(path.contribution);
        path.pdf = d.get<double>();
        path.misWeight = d.get<double>();
        path.weight = d.get<double>();
        path.rngStream = d.get<uint64_t>();
        path.rngOffset = d.get<uint64_t>();
        d.need(vertices, kVertexSize, "the vertices");
        path.vertices.resize(vertices);
        for (VertexRecord& v : path.vertices) {
            const uint8_t kind = d.get<uint8_t>();
            if (kind > uint8_t(VertexKind::PortalCrossing))
                throw PayloadError("a vertex of unknown kind " + std::to_string(kind));
            v.kind = VertexKind(kind);
            v.lobe = d.get<uint8_t>();
            v.flags = d.get<uint8_t>();
            v.reserved = d.get<uint8_t>();
            v.shape = d.get<int32_t>();
            v.prim = d.get<uint32_t>();
            d.get(v.coords);
            d.get(v.p);
            d.get(v.ng);
            d.get(v.ns);
            v.bsdf = d.get<int32_t>();
            v.light = d.get<int32_t>();
            v.roughness = d.get<float>();
            v.pdfFwd = d.get<double>();
            v.pdfRev = d.get<double>();
        }
    }
    d.expectEnd();
    return paths;
}

ChainRound decodeChainRound(Decoder& d) {
    ChainRound r;
    d.need(1, kRoundHeaderSize, "the round's figures");
    r.mutations = d.get<uint64_t>();
    r.b = d.get<double>();
    r.bSamples = d.get<uint64_t>();
    r.wallSeconds = d.get<double>();
    r.cpuSeconds = d.get<double>();
    const uint32_t count = d.get<uint32_t>();
    d.need(count, kStateHeaderSize + kStateLightVertexSize, "the chain states");
    r.states.resize(count);
    for (ChainState& s : r.states) {
        s.chain = d.get<uint32_t>();
        s.credit = d.get<double>();
        d.get(s.raster);
        d.get(s.f);
        s.target = d.get<float>();
        const uint16_t vertices = d.get<uint16_t>();
        if (vertices < 2) throw PayloadError("a chain state with " + std::to_string(vertices) + " vertices");
        s.vertices.resize(vertices);
        VertexRecord& l = s.vertices.front();
        l.kind = VertexKind::Light;
        l.light = d.get<int32_t>();
        l.shape = d.get<int32_t>();
        l.prim = d.get<uint32_t>();
        d.get(l.coords);
        d.get(l.p);
        d.get(l.ng);
        d.need(vertices - 2u, kStateSurfaceVertexSize, "the vertices");
        for (size_t i = 1; i + 1 < s.vertices.size(); ++i) {
            VertexRecord& v = s.vertices[i];
            v.kind = VertexKind::Surface;
            v.lobe = d.get<uint8_t>();
            v.shape = d.get<int32_t>();
            v.prim = d.get<uint32_t>();
            d.get(v.coords);
        }
        s.vertices.back().kind = VertexKind::Camera;
    }
    d.expectEnd();
    return r;
}

// A buffer runs to the end of its payload (BUFR, or SNAP after the snapshot's header).
Buffer decodeBuffer(Decoder& d) {
    Buffer b;
    b.width = d.get<uint32_t>();
    b.height = d.get<uint32_t>();
    const uint32_t channels = d.get<uint32_t>();
    const uint32_t combine = d.get<uint32_t>();
    const uint32_t hasCounts = d.get<uint32_t>();
    b.weight = d.get<double>();
    if (combine == uint32_t(CombineCode::WeightedMean)) b.combine = "weighted-mean";
    else if (combine == uint32_t(CombineCode::Sum)) b.combine = "sum";
    else throw PayloadError("unknown combine rule " + std::to_string(combine));
    if (hasCounts > 1) throw PayloadError("sample-count flag " + std::to_string(hasCounts) + " is neither 0 nor 1");
    d.need(channels, 4, "the channel names");
    b.channels.resize(channels);
    for (std::string& name : b.channels) name = d.getString("a channel name");
    const uint64_t pixels = uint64_t(b.width) * b.height;
    b.planes.resize(channels);
    for (auto& plane : b.planes) d.getArray(plane, pixels, "the planes");
    if (hasCounts) d.getArray(b.sampleCounts, pixels, "the sample counts");
    d.expectEnd();
    return b;
}

Snapshot decodeSnapshot(Decoder& d) {
    Snapshot s;
    s.wallSeconds = d.get<double>();
    s.cpuSeconds = d.get<double>();
    s.samples = d.get<uint64_t>();
    s.overheadSeconds = d.get<double>();
    s.buffer = decodeBuffer(d);
    return s;
}

StatTable decodeStats(Decoder& d) {
    StatTable t;
    t.name = d.getString("the table name");
    const uint32_t columns = d.get<uint32_t>();
    const uint32_t rows = d.get<uint32_t>();
    d.need(columns, 4, "the column names");
    t.columns.resize(columns);
    for (std::string& c : t.columns) c = d.getString("a column name");
    d.need(rows, 4, "the row names");
    t.rows.resize(rows);
    for (std::string& r : t.rows) r = d.getString("a row name");
    d.need(uint64_t(rows) * columns, 8, "the values");
    t.values.resize(rows);
    for (auto& row : t.values) d.getArray(row, columns, "the values");
    d.expectEnd();
    return t;
}

} // namespace

// ---- Writer ------------------------------------------------------------------------------------

struct Writer::Impl {
    std::string name;       // what the user asked for, used in every message
    std::string tempPath;   // empty when writing to stdout
    int fd = -1;
    FileKind kind = FileKind::Paths;
    bool finished = false;
    bool failed = false;   // after a failed write the file is unusable; refuse to go on

    ~Impl() {
        if (!tempPath.empty()) {
            if (fd >= 0) ::close(fd);
            if (!finished) ::unlink(tempPath.c_str());
        }
    }

    [[noreturn]] void fail(const std::string& what, int err) {
        failed = true;
        throw Error(name + ": " + what + " (" + errnoText(err) + ")");
    }

    void writeBytes(const void* data, size_t n) {
        const char* p = static_cast<const char*>(data);
        while (n > 0) {
            const ssize_t w = ::write(fd, p, n);
            if (w < 0) {
                if (errno == EINTR) continue;
                fail("cannot write", errno);
            }
            p += w;
            n -= size_t(w);
        }
    }

    void writeChunk(std::string_view tag, const std::string& payload) {
        const std::string_view pieces[] = {payload};
        writeChunk(tag, pieces);
    }
    // A chunk whose payload is the pieces one after another.
    void writeChunk(std::string_view tag, std::span<const std::string_view> payload) {
        if (finished) throw Error(name + ": write after finish()");
        if (failed) throw Error(name + ": cannot write after an earlier write failed");
        uint64_t length = 0;
        for (const auto& p : payload)
            length += p.size();
        if (length > kMaxChunkLength)
            throw Error(name + ": a " + std::string(tag) + " chunk of " + std::to_string(length) +
                        " bytes is larger than the format allows (" + std::to_string(kMaxChunkLength) + ")");
        std::array<unsigned char, kChunkHeaderSize> head;
        std::memcpy(head.data(), tag.data(), 4);
        putLe64(head.data() + 4, length);
        uint32_t running = crc(0, head.data(), head.size());
        for (const auto& p : payload)
            running = crc(running, p.data(), p.size());
        std::array<unsigned char, kCrcSize> sum;
        putLe32(sum.data(), running);
        writeBytes(head.data(), head.size());
        for (const auto& p : payload)
            writeBytes(p.data(), p.size());
        writeBytes(sum.data(), sum.size());
    }

    void requireKind(FileKind needed, std::string_view tag) const {
        if (kind != needed)
            throw Error(name + ": " + std::string(tag) + " chunks belong in a " + kindName(needed) +
                        " file, this is a " + kindName(kind) + " file");
    }
};

Writer::Writer(const std::string& path, FileKind kind, const nlohmann::json& info) : impl_(std::make_unique<Impl>()) {
    Impl& w = *impl_;
    w.kind = kind;
    w.name = path == "-" ? "<stdout>" : path;
    if (!info.is_object()) throw Error(w.name + ": INFO must be a JSON object, got " + std::string(info.type_name()));
    std::string infoText;
    try {
        infoText = info.dump();
    } catch (const nlohmann::json::exception& e) {
        throw Error(w.name + ": INFO cannot be written as UTF-8 JSON (" + e.what() + ")");
    }
    if (path == "-") {
        w.fd = STDOUT_FILENO;
    } else {
        removeStaleTemporaries(path);
        w.tempPath = temporaryName(path);
        w.fd = ::open(w.tempPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
        if (w.fd < 0) w.fail("cannot create temporary file " + w.tempPath, errno);
        lockAsWriting(w.fd);
    }
    std::array<unsigned char, kFileHeaderSize> header;
    std::memcpy(header.data(), kMagic.data(), 4);
    putLe32(header.data() + 4, kVersion);
    putLe32(header.data() + 8, uint32_t(kind));
    w.writeBytes(header.data(), header.size());
    w.writeChunk(kInfo, infoText);
}

Writer::~Writer() = default;
Writer::Writer(Writer&&) noexcept = default;
Writer& Writer::operator=(Writer&&) noexcept = default;

void Writer::writePaths(std::span<const PathRecord> paths) {
    impl_->requireKind(FileKind::Paths, kPath);
    Encoder e;
    encodePaths(e, paths, impl_->name);
    impl_->writeChunk(kPath, e.bytes());
}

void EncodedChainStates::add(const ChainState& state) {
    Encoder e(bytes_);
    encodeChainState(e, state);
    ++count_;
}

void Writer::writeChainRound(const ChainRound& round) {
    EncodedChainStates states;
    for (const ChainState& s : round.states)
        states.add(s);
    const EncodedChainStates* parts[] = {&states};
    writeChainRound(round, parts);
}

void Writer::writeChainRound(const ChainRound& figures, std::span<const EncodedChainStates* const> parts) {
    impl_->requireKind(FileKind::Paths, kChst);
    uint64_t states = 0;
    for (const auto* p : parts)
        states += p->count();
    Encoder header;
    encodeRoundHeader(header, figures, states, impl_->name);
    std::vector<std::string_view> pieces{header.bytes()};
    for (const auto* p : parts)
        pieces.push_back(p->bytes());
    impl_->writeChunk(kChst, pieces);
}

void Writer::writeBuffer(const Buffer& buffer) {
    impl_->requireKind(FileKind::Buffer, kBufr);
    Encoder e;
    impl_->writeChunk(kBufr, bufferPieces(e, buffer, impl_->name));
}

void Writer::writeSnapshot(const Snapshot& snapshot) {
    impl_->requireKind(FileKind::Buffer, kSnap);
    Encoder e;
    impl_->writeChunk(kSnap, snapshotPieces(e, snapshot, impl_->name));
}

void Writer::writeStats(const StatTable& stats) {
    Encoder e;
    encodeStats(e, stats, impl_->name);
    impl_->writeChunk(kStat, e.bytes());
}

void Writer::finish() {
    Impl& w = *impl_;
    w.writeChunk(kEnd, std::string());
    // fsync on a pipe or terminal (stdout) is meaningless and fails with EINVAL; on a file it is what
    // makes the rename below safe against a crash.
    if (::fsync(w.fd) != 0 && !(w.tempPath.empty() && (errno == EINVAL || errno == EROFS || errno == ENOTSUP)))
        w.fail("cannot sync to disk", errno);
    if (w.tempPath.empty()) {
        w.finished = true;
        return;
    }
    const int fd = w.fd;
    w.fd = -1;
    if (::close(fd) != 0) w.fail("cannot close " + w.tempPath, errno);
    if (::rename(w.tempPath.c_str(), w.name.c_str()) != 0) w.fail("cannot rename " + w.tempPath + " to it", errno);
    w.finished = true;
    // Make the rename itself durable. Failing here changes nothing the user can act on: the file is
    // complete under its name, so errors are ignored.
    const std::filesystem::path dir = std::filesystem::path(w.name).parent_path();
    const int dirFd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dirFd >= 0) {
        (void)::fsync(dirFd);
        ::close(dirFd);
    }
}

const std::string& Writer::name() const { return impl_->name; }

// ---- Reader ------------------------------------------------------------------------------------

struct Reader::Impl {
    std::string name;
    int fd = -1;
    bool ownsFd = false;
    std::optional<uint64_t> fileSize;   // known for regular files: lengths are checked against it
    uint64_t offset = 0;                // bytes consumed so far
    std::vector<unsigned char> buf = std::vector<unsigned char>(size_t(1) << 16);
    size_t bufPos = 0, bufLen = 0;

    uint32_t version = 0;
    FileKind kind = FileKind::Paths;
    nlohmann::json info;
    int chunkIndex = 0;          // 1-based number of the chunk being read
    std::string lastTag;         // of the last complete chunk, for "truncated after" messages
    bool ended = false;

    // The chunk being read, for messages.
    std::string tag;
    uint64_t chunkOffset = 0;

    ~Impl() {
        if (ownsFd && fd >= 0) ::close(fd);
    }

    [[noreturn]] void chunkError(const std::string& what) const {
        throw Error(name + ": chunk " + std::to_string(chunkIndex) + " (" + printableTag(tag) + ") at byte " +
                    std::to_string(chunkOffset) + ": " + what);
    }
    [[noreturn]] void truncatedInChunk() const {
        const std::string tagPart = tag.size() == 4 ? " (" + printableTag(tag) + ")" : "";
        throw Error(name + ": truncated in chunk " + std::to_string(chunkIndex) + tagPart + " at byte " +
                    std::to_string(chunkOffset) + " (no END! marker: the file was cut short)");
    }

    // Reads up to n bytes; fewer only at the end of the input.
    size_t read(void* dst, size_t n) {
        auto* out = static_cast<unsigned char*>(dst);
        size_t done = 0;
        while (done < n) {
            if (bufPos == bufLen) {
                ssize_t got;
                do got = ::read(fd, buf.data(), buf.size());
                while (got < 0 && errno == EINTR);
                if (got < 0) throw Error(name + ": cannot read (" + errnoText(errno) + ")");
                if (got == 0) break;
                bufPos = 0;
                bufLen = size_t(got);
            }
            const size_t take = std::min(n - done, bufLen - bufPos);
            std::memcpy(out + done, buf.data() + bufPos, take);
            bufPos += take;
            done += take;
        }
        offset += done;
        return done;
    }

    void readHeader(std::optional<FileKind> expected) {
        std::array<unsigned char, kFileHeaderSize> h{};
        const size_t got = read(h.data(), h.size());
        if (std::memcmp(h.data(), kMagic.data(), std::min<size_t>(got, 4)) != 0)
            throw Error(name + ": not an lt file (bad magic)");
        if (got == 0) throw Error(name + ": truncated: the file is empty (not an lt file, or cut short)");
        if (got < h.size())
            throw Error(name + ": truncated in the header (" + std::to_string(got) + " of " +
                        std::to_string(h.size()) + " bytes)");
        version = le32(h.data() + 4);
        if (version == 0) throw Error(name + ": invalid version 0");
        if (version > kVersion)
            throw Error(name + ": version " + std::to_string(version) + " is newer than this lt (" +
                        std::to_string(kVersion) + ")");
        const uint32_t k = le32(h.data() + 8);
        if (k != uint32_t(FileKind::Paths) && k != uint32_t(FileKind::Buffer))
            throw Error(name + ": unknown file kind " + std::to_string(k) + " (1 is paths, 2 is buffer)");
        kind = FileKind(k);
        if (expected && *expected != kind)
            throw Error(name + ": expected a " + kindName(*expected) + " file, got a " + kindName(kind) + " file");
    }

    static bool isKnown(std::string_view t) {
        return t == kInfo || t == kPath || t == kChst || t == kBufr || t == kSnap || t == kStat || t == kEnd;
    }

    // Reads the next chunk and checks its CRC. Returns the payload of a known chunk (tag in `tag`);
    // an unknown chunk is streamed through the CRC without being stored and std::nullopt returned.
    std::optional<std::string> readChunk() {
        ++chunkIndex;
        chunkOffset = offset;
        tag.clear();
        std::array<unsigned char, kChunkHeaderSize> head;
        const size_t got = read(head.data(), head.size());
        if (got == 0)
            throw Error(name + ": truncated at byte " + std::to_string(chunkOffset) + ", after " +
                        (lastTag.empty() ? "the header"
                                         : "chunk " + std::to_string(chunkIndex - 1) + " (" + printableTag(lastTag) + ")") +
                        " (no END! marker: the file was cut short)");
        if (got >= 4) tag.assign(reinterpret_cast<const char*>(head.data()), 4);
        if (got < head.size()) truncatedInChunk();
        const uint64_t length = le64(head.data() + 4);
        const bool known = isKnown(tag);

        if (tag == kEnd && length != 0) chunkError("length " + std::to_string(length) + ", the end marker must be empty");
        const uint64_t limit = tag == kInfo ? kMaxInfoLength : kMaxChunkLength;
        if (length > limit)
            chunkError("declared length " + std::to_string(length) + " exceeds the limit of " + std::to_string(limit) +
                       " bytes (the length is damaged)");
        if (fileSize && length + kCrcSize > *fileSize - offset)
            throw Error(name + ": truncated in chunk " + std::to_string(chunkIndex) + " (" + printableTag(tag) +
                        ") at byte " + std::to_string(chunkOffset) + ": its length " + std::to_string(length) +
                        " runs past the end of the file at byte " + std::to_string(*fileSize) +
                        " (no END! marker: the file was cut short, or the length is damaged)");

        uint32_t sum = crc(0, head.data(), head.size());
        std::optional<std::string> payload;
        if (known) {
            payload.emplace();
            while (payload->size() < length) {
                const size_t have = payload->size();
                const size_t piece = size_t(std::min<uint64_t>(length - have, std::max(have, kFirstReadPiece)));
                payload->resize(have + piece);
                if (read(payload->data() + have, piece) != piece) truncatedInChunk();
            }
            sum = crc(sum, payload->data(), payload->size());
        } else {
            std::array<unsigned char, 1 << 16> skip;
            for (uint64_t left = length; left > 0;) {
                const size_t piece = size_t(std::min<uint64_t>(left, skip.size()));
                if (read(skip.data(), piece) != piece) truncatedInChunk();
                sum = crc(sum, skip.data(), piece);
                left -= piece;
            }
        }
        std::array<unsigned char, kCrcSize> stored;
        if (read(stored.data(), stored.size()) != stored.size()) truncatedInChunk();
        if (le32(stored.data()) != sum) chunkError("checksum mismatch");
        lastTag = tag;
        return payload;
    }

    void readInfo() {
        const std::optional<std::string> payload = readChunk();
        if (tag != kInfo) chunkError("the first chunk must be INFO");
        // nlohmann's parser is iterative; its callback sees the depth of every object and array it opens
        // (0 for the outermost) and discards what is too deep, so no deep value is ever built.
        bool tooDeep = false;
        info = nlohmann::json::parse(
            *payload,
            [&](int depth, nlohmann::json::parse_event_t event, nlohmann::json&) {
                if ((event == nlohmann::json::parse_event_t::object_start ||
                     event == nlohmann::json::parse_event_t::array_start) &&
                    depth >= kMaxInfoNesting)
                    tooDeep = true;
                return !tooDeep;
            },
            /*allow_exceptions=*/false);
        if (tooDeep) chunkError("INFO nests deeper than " + std::to_string(kMaxInfoNesting) + " levels");
        if (info.is_discarded()) chunkError("INFO is not valid JSON");
        if (!info.is_object()) chunkError("INFO is not a JSON object");
    }

    void requireKind(FileKind needed) const {
        if (kind != needed)
            chunkError("a " + tag + " chunk belongs in a " + kindName(needed) + " file, this is a " + kindName(kind) +
                       " file");
    }

    Chunk next() {
        if (ended) return End{};
        for (;;) {
            const std::optional<std::string> payload = readChunk();
            if (!payload) continue;   // unknown chunk: skipped for forward compatibility (SPEC.md)
            if (tag == kEnd) {
                ended = true;
                return End{};
            }
            if (tag == kInfo) chunkError("a second INFO chunk");
            Decoder d(*payload);
            try {
                if (tag == kPath) {
                    requireKind(FileKind::Paths);
                    return decodePaths(d);
                }
                if (tag == kChst) {
                    requireKind(FileKind::Paths);
                    return decodeChainRound(d);
                }
                if (tag == kBufr) {
                    requireKind(FileKind::Buffer);
                    return decodeBuffer(d);
                }
                if (tag == kSnap) {
                    requireKind(FileKind::Buffer);
                    return decodeSnapshot(d);
                }
                return decodeStats(d);
            } catch (const PayloadError& e) {
                chunkError(e.what());
            }
        }
    }
};

Reader::Reader(const std::string& path, std::optional<FileKind> expected) : impl_(std::make_unique<Impl>()) {
    Impl& r = *impl_;
    if (path == "-") {
        r.name = "<stdin>";
        r.fd = STDIN_FILENO;
    } else {
        r.name = path;
        r.fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
        if (r.fd < 0) throw Error(path + ": cannot open (" + errnoText(errno) + ")");
        r.ownsFd = true;
    }
    struct stat st {};
    if (::fstat(r.fd, &st) == 0 && S_ISREG(st.st_mode)) {
        // stdin may be a regular file already partly read by someone else: lengths are checked
        // against what is left from here.
        const off_t at = ::lseek(r.fd, 0, SEEK_CUR);
        r.fileSize = uint64_t(st.st_size) - uint64_t(std::max<off_t>(at, 0));
    }
    r.readHeader(expected);
    r.readInfo();
}

Reader::~Reader() = default;
Reader::Reader(Reader&&) noexcept = default;
Reader& Reader::operator=(Reader&&) noexcept = default;

Chunk Reader::next() { return impl_->next(); }
FileKind Reader::kind() const { return impl_->kind; }
uint32_t Reader::version() const { return impl_->version; }
const nlohmann::json& Reader::info() const { return impl_->info; }
const std::string& Reader::name() const { return impl_->name; }
bool Reader::regularFile() const { return impl_->fileSize.has_value(); }

// ---- convenience -------------------------------------------------------------------------------

Content readAll(const std::string& path, std::optional<FileKind> expected) {
    Reader reader(path, expected);
    Content content;
    content.name = reader.name();
    content.version = reader.version();
    content.kind = reader.kind();
    content.info = reader.info();
    const auto count = [&](const char* tag) {
        const auto it = std::find_if(content.chunkCounts.begin(), content.chunkCounts.end(),
                                     [&](const auto& c) { return c.first == tag; });
        if (it == content.chunkCounts.end())
            content.chunkCounts.emplace_back(tag, 1);
        else
            ++it->second;
    };
    count("INFO");
    for (;;) {
        Chunk chunk = reader.next();
        if (std::holds_alternative<End>(chunk)) {
            count("END!");
            return content;
        }
        if (auto* paths = std::get_if<std::vector<PathRecord>>(&chunk)) {
            count("PATH");
            content.paths.insert(content.paths.end(), std::make_move_iterator(paths->begin()),
                                 std::make_move_iterator(paths->end()));
        } else if (auto* round = std::get_if<ChainRound>(&chunk)) {
            count("CHST");
            content.rounds.push_back(std::move(*round));
        } else if (auto* buffer = std::get_if<Buffer>(&chunk)) {
            count("BUFR");
            content.buffers.push_back(std::move(*buffer));
        } else if (auto* snapshot = std::get_if<Snapshot>(&chunk)) {
            count("SNAP");
            content.snapshots.push_back(std::move(*snapshot));
        } else {
            count("STAT");
            content.stats.push_back(std::move(std::get<StatTable>(chunk)));
        }
    }
}

StatTable valueTable(std::string name, const std::vector<std::pair<std::string, double>>& rows) {
    StatTable t{std::move(name), {"value"}, {}, {}};
    for (const auto& [row, value] : rows) {
        t.rows.push_back(row);
        t.values.push_back({value});
    }
    return t;
}

std::string hashHex(uint64_t hash) {
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
    return text;
}

void checkSceneHash(const nlohmann::json& info, uint64_t sceneHash, const std::string& file,
                    const std::string& scenePath) {
    const auto scene = info.find("scene");
    if (scene == info.end() || !scene->is_object() || !scene->contains("hash") || !(*scene)["hash"].is_string())
        throw Error(file + ": INFO has no scene hash, so it cannot be checked against the scene given");
    const std::string stored = (*scene)["hash"].get<std::string>();
    const std::string given = hashHex(sceneHash);
    if (stored == given) return;
    const auto storedPath = scene->find("path");
    const std::string madeFor =
        storedPath != scene->end() && storedPath->is_string() ? storedPath->get<std::string>() : "(unnamed)";
    throw Error(file + ": made for scene " + madeFor + " (hash " + stored + ") but the scene given is " +
                (scenePath.empty() ? "another" : scenePath) + " (hash " + given + ")");
}

} // namespace lt::file
