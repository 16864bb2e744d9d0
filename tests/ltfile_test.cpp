// formats/ltfile: every chunk kind read back bit for bit; truncation at every byte and every single-bit
// flip of small files give one clean lt::Error naming the file; unknown chunks skipped (their CRC still
// checked); versions, kinds, scene hashes; streaming through pipes on stdin/stdout; no half-written file
// under the final name; damaged lengths rejected without allocating what they declare.
#include <fcntl.h>
#include <sys/resource.h>
#include <unistd.h>
#include <zlib.h>

#include <bit>
#include <catch2/catch.hpp>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <csignal>
#include <fstream>
#include <future>
#include <iostream>
#include <limits>
#include <random>
#include <thread>

#include "formats/ltfile.h"
#include "util/error.h"
#include "test_util.h"

namespace fs = std::filesystem;
using namespace lt;
using namespace lt::file;

namespace {

// ---- random content (fixed seed), including the float values a sloppy codec would change ---------

struct Random {
    std::mt19937_64 rng{20240611};

    template <class T> T integer(T lo, T hi) { return std::uniform_int_distribution<T>(lo, hi)(rng); }
    uint8_t byte() { return uint8_t(integer<unsigned>(0, 255)); }
    template <class T> T real() {
        switch (integer(0, 15)) {
        case 0: return T(-0.0);
        case 1: return std::numeric_limits<T>::infinity();
        case 2: return std::numeric_limits<T>::quiet_NaN();
        case 3: return std::numeric_limits<T>::denorm_min();
        case 4: return std::numeric_limits<T>::max();
        default: return T(std::uniform_real_distribution<double>(-1e3, 1e3)(rng));
        }
    }
    template <class T, size_t N> std::array<T, N> reals() {
        std::array<T, N> a;
        for (T& v : a) v = real<T>();
        return a;
    }
    std::string name() {
        static const std::string pieces[] = {"a", "R", ".", "dx", "primal", "\xc3\xa9", " ", "var"};
        std::string s;
        for (int n = integer(0, 4); n > 0; --n) s += pieces[integer<size_t>(0, std::size(pieces) - 1)];
        return s;
    }

    VertexRecord vertex() {
        VertexRecord v;
        v.kind = VertexKind(integer(0, 3));
        v.lobe = byte();
        v.flags = byte();
        v.reserved = byte();
        v.shape = integer<int32_t>(-1, 1 << 30);
        v.prim = integer<uint32_t>(0, UINT32_MAX);
        v.coords = reals<double, 2>();
        v.p = reals<double, 3>();
        v.ng = reals<float, 3>();
        v.ns = reals<float, 3>();
        v.bsdf = integer<int32_t>(INT32_MIN, INT32_MAX);
        v.light = integer<int32_t>(-1, 100);
        v.roughness = real<float>();
        v.pdfFwd = real<double>();
        v.pdfRev = real<double>();
        return v;
    }
    PathRecord path(int maxVertices = 7) {
        PathRecord p;
        for (int n = integer(0, maxVertices); n > 0; --n) p.vertices.push_back(vertex());
        p.raster = reals<float, 2>();
        p.s = integer<uint16_t>(0, UINT16_MAX);
        p.t = integer<uint16_t>(0, UINT16_MAX);
        p.contribution = reals<float, 3>();
        p.pdf = real<double>();
        p.misWeight = real<double>();
        p.weight = real<double>();
        p.rngStream = integer<uint64_t>(0, UINT64_MAX);
        p.rngOffset = integer<uint64_t>(0, UINT64_MAX);
        return p;
    }
    // A round of chain states holding only what CHST stores (records.h ChainState).
    ChainRound round(int maxStates = 6) {
        ChainRound r{integer<uint64_t>(0, UINT64_MAX),
                     real<double>(),
                     integer<uint64_t>(0, UINT64_MAX),
                     real<double>(),
                     real<double>(),
                     {}};
        for (int n = integer(0, maxStates); n > 0; --n) {
            ChainState st;
            st.chain = integer<uint32_t>(0, UINT32_MAX);
            st.credit = real<double>();
            st.raster = reals<float, 2>();
            st.f = reals<float, 3>();
            st.target = real<float>();
            st.vertices.resize(size_t(integer(2, 7)));
            for (size_t i = 0; i < st.vertices.size(); ++i) {
                const VertexRecord v = vertex();
                VertexRecord& k = st.vertices[i];
                k.kind = i == 0 ? VertexKind::Light
                                : (i + 1 == st.vertices.size() ? VertexKind::Camera : VertexKind::Surface);
                if (i + 1 == st.vertices.size()) continue;
                k.shape = v.shape;
                k.prim = v.prim;
                k.coords = v.coords;
                if (i == 0) {
                    k.light = v.light;
                    k.p = v.p;
                    k.ng = v.ng;
                } else {
                    k.lobe = v.lobe;
                }
            }
            r.states.push_back(std::move(st));
        }
        return r;
    }
    Buffer buffer(uint32_t maxSide = 6) {
        Buffer b;
        b.width = integer<uint32_t>(1, maxSide);
        b.height = integer<uint32_t>(1, maxSide);
        for (int c = integer(0, 4); c > 0; --c) {
            b.channels.push_back(name());
            b.planes.emplace_back(size_t(b.width) * b.height);
            for (float& v : b.planes.back()) v = real<float>();
        }
        if (integer(0, 1))
            for (uint32_t i = 0; i < b.width * b.height; ++i) b.sampleCounts.push_back(integer<uint32_t>(0, UINT32_MAX));
        b.weight = std::uniform_real_distribution<double>(0, 1e6)(rng);
        b.combine = integer(0, 1) ? "weighted-mean" : "sum";
        return b;
    }
    Snapshot snapshot() {
        Snapshot s;
        s.wallSeconds = real<double>();
        s.cpuSeconds = real<double>();
        s.samples = integer<uint64_t>(0, UINT64_MAX);
        s.overheadSeconds = real<double>();
        s.buffer = buffer();
        return s;
    }
    StatTable stats() {
        StatTable t;
        t.name = name();
        for (int c = integer(0, 4); c > 0; --c) t.columns.push_back(name());
        for (int r = integer(0, 3); r > 0; --r) {
            t.rows.push_back(name());
            t.values.emplace_back();
            for (size_t c = 0; c < t.columns.size(); ++c) t.values.back().push_back(real<double>());
        }
        return t;
    }
};

// ---- bitwise equality (NaN payloads and -0 must survive too) ----------------------------------------

bool same(const VertexRecord& a, const VertexRecord& b);
bool same(const PathRecord& a, const PathRecord& b);
bool same(const Buffer& a, const Buffer& b);
bool same(const Snapshot& a, const Snapshot& b);
bool same(const StatTable& a, const StatTable& b);

template <class T>
    requires std::is_arithmetic_v<T> || std::is_enum_v<T>
bool same(T a, T b) {
    if constexpr (std::is_same_v<T, float>) return std::bit_cast<uint32_t>(a) == std::bit_cast<uint32_t>(b);
    else if constexpr (std::is_same_v<T, double>) return std::bit_cast<uint64_t>(a) == std::bit_cast<uint64_t>(b);
    else return a == b;
}
bool same(const std::string& a, const std::string& b) { return a == b; }
template <class T, size_t N> bool same(const std::array<T, N>& a, const std::array<T, N>& b) {
    for (size_t i = 0; i < N; ++i)
        if (!same(a[i], b[i])) return false;
    return true;
}
template <class T> bool same(const std::vector<T>& a, const std::vector<T>& b) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i)
        if (!same(a[i], b[i])) return false;
    return true;
}

bool same(const VertexRecord& a, const VertexRecord& b) {
    return same(a.kind, b.kind) && same(a.lobe, b.lobe) && same(a.flags, b.flags) && same(a.reserved, b.reserved) &&
           same(a.shape, b.shape) && same(a.prim, b.prim) && same(a.coords, b.coords) && same(a.p, b.p) &&
           same(a.ng, b.ng) && same(a.ns, b.ns) && same(a.bsdf, b.bsdf) && same(a.light, b.light) &&
           same(a.roughness, b.roughness) && same(a.pdfFwd, b.pdfFwd) && same(a.pdfRev, b.pdfRev);
}
bool same(const PathRecord& a, const PathRecord& b) {
    return same(a.vertices, b.vertices) && same(a.raster, b.raster) && same(a.s, b.s) && same(a.t, b.t) &&
           same(a.contribution, b.contribution) && same(a.pdf, b.pdf) && same(a.misWeight, b.misWeight) &&
           same(a.weight, b.weight) && same(a.rngStream, b.rngStream) && same(a.rngOffset, b.rngOffset);
}
bool same(const Buffer& a, const Buffer& b) {
    return same(a.width, b.width) && same(a.height, b.height) && same(a.channels, b.channels) &&
           same(a.planes, b.planes) && same(a.sampleCounts, b.sampleCounts) && same(a.weight, b.weight) &&
           same(a.combine, b.combine);
}
bool same(const Snapshot& a, const Snapshot& b) {
    return same(a.wallSeconds, b.wallSeconds) && same(a.cpuSeconds, b.cpuSeconds) && same(a.samples, b.samples) &&
           same(a.overheadSeconds, b.overheadSeconds) && same(a.buffer, b.buffer);
}
bool same(const StatTable& a, const StatTable& b) {
    return same(a.name, b.name) && same(a.columns, b.columns) && same(a.rows, b.rows) && same(a.values, b.values);
}

// ---- raw bytes, for files the Writer would never produce ---------------------------------------------

std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

template <class T> std::string le(T value) {
    std::string s;
    for (size_t i = 0; i < sizeof(T); ++i) s += char(uint64_t(value) >> (8 * i));
    return s;
}

std::string fileHeader(uint32_t version, FileKind kind) { return std::string("LTF\x01", 4) + le(version) + le(uint32_t(kind)); }

// A chunk with a correct CRC (SPEC.md: CRC-32 of tag, length and payload), declaring `length`.
std::string chunkWithLength(const std::string& tag, uint64_t length, const std::string& payload) {
    const std::string head = tag + le(length);
    uLong sum = crc32(0, reinterpret_cast<const Bytef*>(head.data()), uInt(head.size()));
    sum = crc32(sum, reinterpret_cast<const Bytef*>(payload.data()), uInt(payload.size()));
    return head + payload + le(uint32_t(sum));
}
std::string chunk(const std::string& tag, const std::string& payload) {
    return chunkWithLength(tag, payload.size(), payload);
}

// Where the chunk after INFO starts in a file the Writer wrote.
size_t afterInfo(const std::string& bytes) {
    uint64_t infoLength = 0;
    for (int i = 7; i >= 0; --i) infoLength = infoLength << 8 | uint8_t(bytes[16 + i]);
    return 12 + 12 + size_t(infoLength) + 4;
}

const nlohmann::json kInfo = {{"producer", "ltfile_test"}, {"seed", 7}};

// Small files with every chunk kind their file kind allows (a few hundred bytes each).
std::string smallPathsFile(const test::TempDir& dir) {
    Random random;
    const std::string name = dir.file("small.ltp");
    Writer w(name, FileKind::Paths, kInfo);
    PathRecord p = random.path(0);
    p.vertices = {random.vertex(), random.vertex()};
    w.writePaths(std::span(&p, 1));
    w.writeChainRound(random.round(1));
    w.writeStats(StatTable{"t", {"proposed"}, {"lens"}, {{3}}});
    w.finish();
    return name;
}
std::string smallBufferFile(const test::TempDir& dir) {
    const std::string name = dir.file("small.lts");
    Writer w(name, FileKind::Buffer, kInfo);
    const Buffer b{2, 2, {"R"}, {{1, 2, 3, 4}}, {1, 1, 2, 2}, 6, "weighted-mean"};
    w.writeSnapshot(Snapshot{1.5, 2.5, 4, 0.25, b});
    w.writeBuffer(b);
    w.finish();
    return name;
}

std::string errorOf(const std::string& path, std::optional<FileKind> expected = std::nullopt) {
    return test::errorOf([&] { (void)readAll(path, expected); });
}

bool startsWith(const std::string& s, const std::string& prefix) { return s.rfind(prefix, 0) == 0; }

} // namespace

TEST_CASE("every chunk kind round-trips bit for bit", "[format]") {
    test::TempDir dir;
    Random random;

    std::vector<std::vector<PathRecord>> batches(4);
    for (auto& batch : batches)   // the first batch stays empty: an empty PATH chunk is valid
        for (int n = &batch == &batches[0] ? 0 : random.integer(1, 40); n > 0; --n) batch.push_back(random.path());
    std::vector<StatTable> tables{random.stats(), random.stats(), StatTable{}};
    nlohmann::json info = kInfo;
    info["parameters"] = {{"spp", 16}, {"name", "\xc3\xa9t\xc3\xa9"}};
    info["scene"] = {{"path", "scene.xml"}, {"hash", hashHex(0x0123456789abcdefULL)}};

    const std::string pathsFile = dir.file("p.ltp");
    {
        Writer w(pathsFile, FileKind::Paths, info);
        for (const auto& batch : batches) w.writePaths(batch);
        for (const auto& t : tables) w.writeStats(t);
        w.finish();
    }
    // The Reader hands back each batch as written, in order.
    {
        Reader r(pathsFile, FileKind::Paths);
        CHECK(r.version() == kVersion);
        CHECK(r.kind() == FileKind::Paths);
        CHECK(r.info() == info);
        for (const auto& batch : batches) {
            Chunk c = r.next();
            REQUIRE(std::holds_alternative<std::vector<PathRecord>>(c));
            CHECK(same(std::get<std::vector<PathRecord>>(c), batch));
        }
        for (const auto& t : tables) {
            Chunk c = r.next();
            REQUIRE(std::holds_alternative<StatTable>(c));
            CHECK(same(std::get<StatTable>(c), t));
        }
        CHECK(std::holds_alternative<End>(r.next()));
        CHECK(std::holds_alternative<End>(r.next()));
    }
    const Content paths = readAll(pathsFile);
    std::vector<PathRecord> all;
    for (const auto& batch : batches) all.insert(all.end(), batch.begin(), batch.end());
    CHECK(paths.kind == FileKind::Paths);
    CHECK(same(paths.paths, all));
    CHECK(same(paths.stats, tables));
    CHECK(paths.buffers.empty());
    CHECK_NOTHROW(checkSceneHash(paths.info, 0x0123456789abcdefULL, pathsFile));

    std::vector<Buffer> buffers{random.buffer(40), random.buffer(), Buffer{}};
    std::vector<Snapshot> snapshots{random.snapshot(), random.snapshot(), random.snapshot()};
    const std::string bufferFile = dir.file("b.lts");
    {
        Writer w(bufferFile, FileKind::Buffer, info);
        for (const auto& s : snapshots) w.writeSnapshot(s);
        for (const auto& b : buffers) w.writeBuffer(b);
        w.writeStats(tables[0]);
        w.finish();
    }
    const Content content = readAll(bufferFile, FileKind::Buffer);
    CHECK(content.kind == FileKind::Buffer);
    CHECK(content.info == info);
    CHECK(same(content.buffers, buffers));
    CHECK(same(content.snapshots, snapshots));
    CHECK(same(content.stats, std::vector<StatTable>{tables[0]}));
    CHECK(content.paths.empty());
}

TEST_CASE("chain-state rounds round-trip bit for bit, whole or encoded in pieces", "[format]") {
    test::TempDir dir;
    Random random;
    std::vector<ChainRound> rounds{random.round(0), random.round(), random.round(40)};
    const std::string file = dir.file("s.ltp");
    {
        Writer w(file, FileKind::Paths, kInfo);
        for (const auto& r : rounds)
            w.writeChainRound(r);
        // The same round from two chains' encodings.
        std::vector<EncodedChainStates> parts(2);
        for (size_t i = 0; i < rounds[2].states.size(); ++i)
            parts[i % 2 == 0 && i < 20 ? 0 : 1].add(rounds[2].states[i]);
        const EncodedChainStates* pieces[] = {&parts[0], &parts[1]};
        w.writeChainRound(rounds[2], pieces);
        w.finish();
    }
    const auto bits = [](const auto& v) {
        return std::vector<unsigned char>(reinterpret_cast<const unsigned char*>(&v),
                                          reinterpret_cast<const unsigned char*>(&v) + sizeof(v));
    };
    const auto same = [&](const ChainRound& a, const ChainRound& b) {
        bool ok = a.mutations == b.mutations && bits(a.b) == bits(b.b) && a.bSamples == b.bSamples &&
                  bits(a.wallSeconds) == bits(b.wallSeconds) && bits(a.cpuSeconds) == bits(b.cpuSeconds) &&
                  a.states.size() == b.states.size();
        for (size_t i = 0; ok && i < a.states.size(); ++i) {
            const ChainState &x = a.states[i], &y = b.states[i];
            ok = x.chain == y.chain && bits(x.credit) == bits(y.credit) && bits(x.raster) == bits(y.raster) &&
                 bits(x.f) == bits(y.f) && bits(x.target) == bits(y.target) && x.vertices.size() == y.vertices.size();
            for (size_t k = 0; ok && k < x.vertices.size(); ++k) {
                const VertexRecord &u = x.vertices[k], &v = y.vertices[k];
                ok = u.kind == v.kind && u.lobe == v.lobe && u.shape == v.shape && u.prim == v.prim &&
                     bits(u.coords) == bits(v.coords) && u.light == v.light && bits(u.p) == bits(v.p) &&
                     bits(u.ng) == bits(v.ng);
            }
        }
        return ok;
    };
    const Content c = readAll(file, FileKind::Paths);
    REQUIRE(c.rounds.size() == 4);
    for (size_t i = 0; i < 3; ++i)
        CHECK(same(c.rounds[i], rounds[i]));
    // Pieces keep their order: chain 0's states, then chain 1's.
    ChainRound pieced = rounds[2];
    pieced.states.clear();
    for (int part = 0; part < 2; ++part)
        for (size_t i = 0; i < rounds[2].states.size(); ++i)
            if ((i % 2 == 0 && i < 20) == (part == 0)) pieced.states.push_back(rounds[2].states[i]);
    CHECK(same(c.rounds[3], pieced));

    // A state of fewer than two vertices is refused by the writer, and by the reader (CRC recomputed).
    ChainRound bad = random.round(1);
    bad.states.assign(1, ChainState{});
    bad.states[0].vertices.resize(1);
    CHECK_THROWS_WITH(Writer(dir.file("x.ltp"), FileKind::Paths, kInfo).writeChainRound(bad),
                      Catch::Contains("a chain state with 1 vertices"));
    std::string payload = std::string(8 * 5, '\0') + le(uint32_t(1)) + std::string(36, '\0') + le(uint16_t(1));
    const std::string header = slurp(smallPathsFile(dir)).substr(0, afterInfo(slurp(smallPathsFile(dir))));
    dir.write("bad.ltp", header + chunk("CHST", payload + std::string(64, '\0')) + chunk("END!", ""));
    CHECK(errorOf(dir.file("bad.ltp")).find("a chain state with 1 vertices") != std::string::npos);
    dir.write("bad.ltp", header + chunk("CHST", std::string(8 * 5, '\0') + le(uint32_t(1000))) + chunk("END!", ""));
    CHECK(errorOf(dir.file("bad.ltp")).find("the chain states need 1000 x 102 bytes") != std::string::npos);
}

TEST_CASE("truncation at every byte gives a clean error naming the file", "[format]") {
    test::TempDir dir;
    for (const std::string& original : {smallPathsFile(dir), smallBufferFile(dir)}) {
        const std::string bytes = slurp(original);
        REQUIRE(bytes.size() < 1000);
        REQUIRE_NOTHROW(readAll(original));
        const std::string cut = dir.file("cut");
        for (size_t n = 0; n < bytes.size(); ++n) {
            dir.write("cut", bytes.substr(0, n));
            const std::string message = errorOf(cut);
            INFO("cut at " << n << ": " << message);
            CHECK(startsWith(message, cut + ": "));
            CHECK(message.find("truncated") != std::string::npos);
        }
    }
    // The exact wording for a cut inside a chunk and one between chunks.
    const std::string bytes = slurp(smallBufferFile(dir));
    const size_t second = afterInfo(bytes);
    dir.write("cut", bytes.substr(0, second + 20));
    // The SNAP is 97 bytes: 32 of snapshot header, then the buffer's 28 of header, 5 for the name "R",
    // 16 for its plane and 16 for the sample counts.
    CHECK(errorOf(dir.file("cut")) == dir.file("cut") + ": truncated in chunk 2 (SNAP) at byte " +
                                          std::to_string(second) +
                                          ": its length 97 runs past the end of the file at byte " +
                                          std::to_string(second + 20) +
                                          " (no END! marker: the file was cut short, or the length is damaged)");
    dir.write("cut", bytes.substr(0, second));
    CHECK(errorOf(dir.file("cut")) == dir.file("cut") + ": truncated at byte " + std::to_string(second) +
                                          ", after chunk 1 (INFO) (no END! marker: the file was cut short)");
}

TEST_CASE("every single-bit flip gives a clean error naming the file", "[format]") {
    test::TempDir dir;
    for (const std::string& original : {smallPathsFile(dir), smallBufferFile(dir)}) {
        const std::string bytes = slurp(original);
        const std::string flipped = dir.file("flipped");
        for (size_t bit = 0; bit < 8 * bytes.size(); ++bit) {
            std::string damaged = bytes;
            damaged[bit / 8] = char(damaged[bit / 8] ^ (1 << (bit % 8)));
            dir.write("flipped", damaged);
            const std::string message = errorOf(flipped);
            INFO("bit " << bit << ": " << message);
            CHECK(startsWith(message, flipped + ": "));
        }
    }
    const std::string bytes = slurp(smallBufferFile(dir));
    std::string damaged = bytes;
    damaged[afterInfo(bytes) + 12 + 40] ^= 0x10;   // inside the snapshot's planes
    dir.write("flipped", damaged);
    CHECK(errorOf(dir.file("flipped")) ==
          dir.file("flipped") + ": chunk 2 (SNAP) at byte " + std::to_string(afterInfo(bytes)) + ": checksum mismatch");
}

TEST_CASE("unknown chunks are skipped but their checksum is still checked", "[format]") {
    test::TempDir dir;
    const std::string original = smallPathsFile(dir);
    const std::string bytes = slurp(original);
    const size_t at = afterInfo(bytes);
    const std::string extra = chunk("XTRA", std::string(300, 'x'));
    const std::string withExtra = bytes.substr(0, at) + extra + chunk("zz\x01z", "") + bytes.substr(at);
    const std::string name = dir.write("extra.ltp", withExtra);

    const Content expected = readAll(original), got = readAll(name);
    CHECK(same(got.paths, expected.paths));
    CHECK(same(got.stats, expected.stats));
    CHECK(got.info == expected.info);

    for (size_t bit = 0; bit < 8 * extra.size(); ++bit) {
        std::string damaged = withExtra;
        damaged[at + bit / 8] = char(damaged[at + bit / 8] ^ (1 << (bit % 8)));
        dir.write("damaged.ltp", damaged);
        const std::string message = errorOf(dir.file("damaged.ltp"));
        INFO("bit " << bit << ": " << message);
        CHECK(startsWith(message, dir.file("damaged.ltp") + ": "));
        if (bit >= 8 * 12 && bit < 8 * (extra.size() - 4))   // in the payload: only the CRC can tell
            CHECK(message == dir.file("damaged.ltp") + ": chunk 2 (XTRA) at byte " + std::to_string(at) +
                                 ": checksum mismatch");
    }

    // INFO comes first, always: it is what every reader checks the file against.
    const std::string early = dir.write("early.ltp", bytes.substr(0, 12) + extra + bytes.substr(12));
    CHECK(errorOf(early) == early + ": chunk 1 (XTRA) at byte 12: the first chunk must be INFO");
}

TEST_CASE("versions, kinds and magic are checked", "[format]") {
    test::TempDir dir;
    const std::string bytes = slurp(smallPathsFile(dir));
    const std::string newer = dir.write("newer", fileHeader(7, FileKind::Paths) + bytes.substr(12));
    CHECK(errorOf(newer) == newer + ": version 7 is newer than this lt (1)");
    const std::string zero = dir.write("zero", fileHeader(0, FileKind::Paths) + bytes.substr(12));
    CHECK(errorOf(zero) == zero + ": invalid version 0");
    const std::string kind = dir.write("kind", bytes.substr(0, 8) + le(uint32_t(3)) + bytes.substr(12));
    CHECK(errorOf(kind) == kind + ": unknown file kind 3 (1 is paths, 2 is buffer)");
    const std::string png = dir.write("png", "\x89PNG\r\n\x1a\n....");
    CHECK(errorOf(png) == png + ": not an lt file (bad magic)");
    const std::string paths = smallPathsFile(dir);
    CHECK(errorOf(paths, FileKind::Buffer) == paths + ": expected a buffer file, got a paths file");
    const std::string buffer = smallBufferFile(dir);
    CHECK(errorOf(buffer, FileKind::Paths) == buffer + ": expected a paths file, got a buffer file");
    CHECK(errorOf(dir.file("missing")) == dir.file("missing") + ": cannot open (No such file or directory)");

    // A chunk in a file of the wrong kind, with a valid CRC.
    const std::string info = chunk("INFO", "{}");
    const std::string mixed = dir.write("mixed", fileHeader(1, FileKind::Paths) + info +
                                                     chunk("BUFR", "") + chunk("END!", ""));
    CHECK(errorOf(mixed) == mixed + ": chunk 2 (BUFR) at byte " + std::to_string(12 + info.size()) +
                                ": a BUFR chunk belongs in a buffer file, this is a paths file");
    const std::string notObject = dir.write("array", fileHeader(1, FileKind::Paths) + chunk("INFO", "[1]"));
    CHECK(errorOf(notObject) == notObject + ": chunk 1 (INFO) at byte 12: INFO is not a JSON object");
    // Valid JSON nested 200 000 levels deep (the probe's crash: copying or freeing it recursed off the
    // stack) is refused before it is parsed; 64 levels, inside a string brackets do not count, are read.
    const std::string deep =
        dir.write("deep", fileHeader(1, FileKind::Paths) +
                              chunk("INFO", "{\"a\":" + std::string(200000, '[') + std::string(200000, ']') + "}"));
    CHECK(errorOf(deep) == deep + ": chunk 1 (INFO) at byte 12: INFO nests deeper than 64 levels");
    const std::string nested =
        "{\"s\":\"" + std::string(100, '[') + "\",\"a\":" + std::string(63, '[') + std::string(63, ']') + "}";
    const std::string fine =
        dir.write("fine", fileHeader(1, FileKind::Paths) + chunk("INFO", nested) + chunk("END!", ""));
    CHECK(errorOf(fine) == "(no error)");
}

TEST_CASE("huge declared lengths are rejected without allocating them", "[format]") {
    test::TempDir dir;
    rusage before{};
    getrusage(RUSAGE_SELF, &before);
    const std::string head = fileHeader(1, FileKind::Buffer) + chunk("INFO", "{}");

    // A damaged high bit of a length: beyond any chunk the format allows.
    const std::string beyond = dir.write("beyond", head + chunkWithLength("BUFR", uint64_t(1) << 62, "abc"));
    CHECK(errorOf(beyond) == beyond + ": chunk 2 (BUFR) at byte " + std::to_string(head.size()) + ": declared length " +
                                 std::to_string(uint64_t(1) << 62) +
                                 " exceeds the limit of 68719476736 bytes (the length is damaged)");
    // Within the limit but past the end of a regular file.
    const std::string past = dir.write("past", head + chunkWithLength("BUFR", uint64_t(1) << 35, "abc"));
    CHECK(errorOf(past).find("runs past the end of the file") != std::string::npos);

    // On a pipe the size is unknown: the reader must meet the end of the data without having allocated
    // the 32 GiB the chunk declares.
    int fds[2];
    REQUIRE(::pipe(fds) == 0);
    const std::string stream = head + chunkWithLength("BUFR", uint64_t(1) << 35, std::string(1000, 'b'));
    REQUIRE(::write(fds[1], stream.data(), stream.size()) == ssize_t(stream.size()));
    ::close(fds[1]);
    const std::string pipeName = "/dev/fd/" + std::to_string(fds[0]);
    CHECK(errorOf(pipeName) == pipeName + ": truncated in chunk 2 (BUFR) at byte " + std::to_string(head.size()) +
                                   " (no END! marker: the file was cut short)");
    ::close(fds[0]);

    // Counts inside a payload with a valid CRC: 2^32-1 paths, a 65535 x 65535 buffer of 1000 planes,
    // a table of 2^32-1 x 2^32-1 values.
    const std::string pathsHead = fileHeader(1, FileKind::Paths) + chunk("INFO", "{}");
    const std::string manyPaths = dir.write("manyPaths", pathsHead + chunk("PATH", le(UINT32_MAX) + std::string(68, 0)));
    CHECK(errorOf(manyPaths) == manyPaths + ": chunk 2 (PATH) at byte " + std::to_string(pathsHead.size()) +
                                    ": the paths need 4294967295 x 68 bytes but the payload has 68 left");
    const std::string bigBuffer = dir.write(
        "bigBuffer", head + chunk("BUFR", le(uint32_t(65535)) + le(uint32_t(65535)) + le(uint32_t(1000)) +
                                              le(uint32_t(1)) + le(uint32_t(0)) + le(uint64_t(0)) +
                                              std::string(4000, 0)));
    CHECK(errorOf(bigBuffer).find(": the planes need 4294836225 x 4 bytes") != std::string::npos);
    const std::string bigTable =
        dir.write("bigTable", pathsHead + chunk("STAT", le(uint32_t(0)) + le(UINT32_MAX) + le(UINT32_MAX) + "xx"));
    CHECK(errorOf(bigTable).find(": the column names need 4294967295 x 4 bytes") != std::string::npos);

    // Peak memory is a high-water mark, so this only catches an allocation far above anything the
    // other tests do.
    rusage after{};
    getrusage(RUSAGE_SELF, &after);
    CHECK(after.ru_maxrss - before.ru_maxrss < 256 * 1024);   // kilobytes
}

TEST_CASE("a Writer leaves no file under the final name until finish()", "[format]") {
    test::TempDir dir;
    const std::string name = dir.file("out.lts");
    const auto entries = [&] {
        return std::distance(fs::directory_iterator(dir.path), fs::directory_iterator{});
    };
    {
        Writer w(name, FileKind::Buffer, kInfo);
        w.writeBuffer(Buffer{1, 1, {"Y"}, {{0.5f}}, {}, 1, "sum"});
        CHECK(!fs::exists(name));
        CHECK(fs::exists(name + ".partial-" + std::to_string(::getpid())));
    }
    CHECK(entries() == 0);

    // A write refused halfway (bad input) leaves nothing behind either.
    {
        Writer w(name, FileKind::Buffer, kInfo);
        CHECK_THROWS_WITH(w.writeBuffer(Buffer{2, 2, {"Y"}, {{0.5f}}, {}, 1, "sum"}),
                          name + ": buffer plane \"Y\" has 1 values for 2x2 pixels");
        CHECK_THROWS_WITH(w.writePaths({}), name + ": PATH chunks belong in a paths file, this is a buffer file");
        CHECK_THROWS_WITH(w.writeBuffer(Buffer{1, 1, {}, {}, {}, 1, "max"}),
                          name + ": unknown buffer combine rule \"max\" (weighted-mean or sum)");
    }
    CHECK(entries() == 0);

    {
        Writer w(name, FileKind::Buffer, kInfo);
        w.finish();
        CHECK_THROWS_WITH(w.writeStats({}), name + ": write after finish()");
    }
    CHECK(entries() == 1);
    CHECK(readAll(name).buffers.empty());

    CHECK_THROWS_WITH(Writer(dir.file("no/such/dir/x.lts"), FileKind::Paths, kInfo),
                      dir.file("no/such/dir/x.lts") + ": cannot create temporary file " +
                          dir.file("no/such/dir/x.lts") + ".partial-" + std::to_string(::getpid()) +
                          " (No such file or directory)");
    CHECK_THROWS_WITH(Writer(name, FileKind::Paths, nlohmann::json::array()),
                      name + ": INFO must be a JSON object, got array");
}

TEST_CASE("a disk-full write throws an error naming the file", "[format]") {
    // /dev/full fails every write with ENOSPC. A temporary file cannot be made there, so point stdout at it.
    if (!fs::exists("/dev/full")) return;
    const int saved = ::dup(STDOUT_FILENO);
    std::fflush(stdout);
    const int full = ::open("/dev/full", O_WRONLY);
    REQUIRE(full >= 0);
    ::dup2(full, STDOUT_FILENO);
    ::close(full);
    std::string message;
    try {
        Writer w("-", FileKind::Paths, kInfo);
    } catch (const Error& e) {
        message = e.what();
    }
    ::dup2(saved, STDOUT_FILENO);
    ::close(saved);
    CHECK(message == "<stdout>: cannot write (No space left on device)");
}

TEST_CASE("files stream through stdout and stdin as chunks are written", "[format]") {
    Random random;
    std::vector<PathRecord> first, second;
    for (int i = 0; i < 50; ++i) first.push_back(random.path());
    for (int i = 0; i < 500; ++i) second.push_back(random.path());   // more than a pipe holds (64 KiB)
    const StatTable stats = random.stats();

    int fds[2];
    REQUIRE(::pipe(fds) == 0);
    std::fflush(stdout);
    std::cout.flush();
    const int savedOut = ::dup(STDOUT_FILENO), savedIn = ::dup(STDIN_FILENO);
    ::dup2(fds[1], STDOUT_FILENO);
    ::dup2(fds[0], STDIN_FILENO);
    ::close(fds[0]);
    ::close(fds[1]);

    // A writer that fails (reader gone) must get EPIPE, not a signal that ends the test run.
    const auto oldSigpipe = std::signal(SIGPIPE, SIG_IGN);
    std::promise<void> firstSeen;
    bool released = false;
    const auto release = [&] {
        if (!released) firstSeen.set_value();
        released = true;
    };
    bool streamed = false;
    std::exception_ptr writerError, readerError;
    std::thread writer([&] {
        try {
            Writer w("-", FileKind::Paths, kInfo);
            w.writePaths(first);
            // The reader must get the first batch before finish(): chunks are not held back.
            streamed = firstSeen.get_future().wait_for(std::chrono::seconds(10)) == std::future_status::ready;
            w.writePaths(second);
            w.writeStats(stats);
            w.finish();
        } catch (...) {
            writerError = std::current_exception();
        }
    });
    std::vector<Chunk> chunks;
    std::string name;
    try {
        Reader r("-", FileKind::Paths);
        name = r.name();
        chunks.push_back(r.next());
        release();
        while (!std::holds_alternative<End>(chunks.emplace_back(r.next()))) {
        }
    } catch (...) {
        readerError = std::current_exception();
    }
    release();
    // Closing the pipe's read end first unblocks a writer still writing after a reader error.
    ::dup2(savedIn, STDIN_FILENO);
    writer.join();
    ::dup2(savedOut, STDOUT_FILENO);
    ::close(savedOut);
    ::close(savedIn);
    std::signal(SIGPIPE, oldSigpipe);
    if (writerError) std::rethrow_exception(writerError);
    if (readerError) std::rethrow_exception(readerError);

    CHECK(streamed);
    CHECK(name == "<stdin>");
    REQUIRE(chunks.size() == 4);
    CHECK(same(std::get<std::vector<PathRecord>>(chunks[0]), first));
    CHECK(same(std::get<std::vector<PathRecord>>(chunks[1]), second));
    CHECK(same(std::get<StatTable>(chunks[2]), stats));
}

TEST_CASE("a stream cut short (writer never finished) is reported as truncated", "[format]") {
    int fds[2];
    REQUIRE(::pipe(fds) == 0);
    std::fflush(stdout);
    const int savedOut = ::dup(STDOUT_FILENO);
    ::dup2(fds[1], STDOUT_FILENO);
    ::close(fds[1]);
    {
        Writer w("-", FileKind::Paths, kInfo);
        w.writePaths({});
    }
    ::dup2(savedOut, STDOUT_FILENO);   // closes the pipe's last write end: the reader sees its end
    ::close(savedOut);
    const std::string name = "/dev/fd/" + std::to_string(fds[0]);
    const std::string message = errorOf(name);
    ::close(fds[0]);
    CHECK(message.find(name + ": truncated at byte ") == 0);
    CHECK(message.find("after chunk 2 (PATH) (no END! marker: the file was cut short)") != std::string::npos);
}

TEST_CASE("checkSceneHash names both scenes and hashes", "[format]") {
    const nlohmann::json info = {{"scene", {{"path", "cbox/scene.xml"}, {"hash", hashHex(0xabcdef)}}}};
    CHECK(hashHex(0xabcdef) == "0000000000abcdef");
    CHECK_NOTHROW(checkSceneHash(info, 0xabcdef, "seeds.ltp"));
    CHECK_THROWS_WITH(checkSceneHash(info, 0x1234, "seeds.ltp", "veach/scene.xml"),
                      "seeds.ltp: made for scene cbox/scene.xml (hash 0000000000abcdef) but the scene given is "
                      "veach/scene.xml (hash 0000000000001234)");
    CHECK_THROWS_WITH(checkSceneHash(nlohmann::json::object(), 1, "x.ltp"),
                      "x.ltp: INFO has no scene hash, so it cannot be checked against the scene given");
}

TEST_CASE("the Python lister in SPEC.md reads what the Writer writes", "[format]") {
    if (!fs::exists("/usr/bin/python3")) return;   // the snippet documents the format; python is optional
    const std::string spec = slurp(std::string(LT_SOURCE_DIR) + "/formats/SPEC.md");
    const size_t begin = spec.find("```python\n", spec.find("## Listing a file in Python"));
    REQUIRE(begin != std::string::npos);
    const size_t end = spec.find("```", begin + 10);
    test::TempDir dir;
    const std::string script = dir.write("list.py", spec.substr(begin + 10, end - begin - 10));
    const std::string file = smallBufferFile(dir);
    FILE* pipe = ::popen(("/usr/bin/python3 " + script + " " + file + " 2>&1").c_str(), "r");
    REQUIRE(pipe);
    std::string output;
    char line[512];
    while (std::fgets(line, sizeof line, pipe)) output += line;
    CHECK(::pclose(pipe) == 0);
    const size_t snap = afterInfo(slurp(file));
    CHECK(output == file + ": version 1, buffer file\n"
                           "chunk 1 (INFO) at byte 12: " + std::to_string(snap - 28) + " bytes, crc ok\n"
                           "  {\"producer\": \"ltfile_test\", \"seed\": 7}\n"
                           "chunk 2 (SNAP) at byte " + std::to_string(snap) + ": 97 bytes, crc ok\n"
                           "chunk 3 (BUFR) at byte " + std::to_string(snap + 113) + ": 65 bytes, crc ok\n"
                           "chunk 4 (END!) at byte " + std::to_string(snap + 113 + 81) + ": 0 bytes, crc ok\n");
}

TEST_CASE("the Python reader of chain states in SPEC.md reads what the Writer writes", "[format]") {
    if (!fs::exists("/usr/bin/python3")) return;
    const std::string spec = slurp(std::string(LT_SOURCE_DIR) + "/formats/SPEC.md");
    const size_t begin = spec.find("```python\n", spec.find("## CHST"));
    REQUIRE(begin != std::string::npos);
    const size_t end = spec.find("```", begin + 10);
    test::TempDir dir;
    Random random;
    ChainRound round = random.round(30);
    round.mutations = 12345;
    for (auto& st : round.states)
        st.credit = 0.25;
    const std::string file = dir.file("s.ltp");
    {
        Writer w(file, FileKind::Paths, kInfo);
        w.writeChainRound(round);
        w.finish();
    }
    // Walks the chunks as the lister does and prints what chain_states finds.
    const std::string script = dir.write("states.py", spec.substr(begin + 10, end - begin - 10) + R"(
import sys
data = open(sys.argv[1], "rb").read()
at = 12
while at < len(data):
    tag, length = struct.unpack_from("<4sQ", data, at)
    if tag == b"CHST":
        mutations, b, states = chain_states(data[at + 12:at + 12 + length])
        print(mutations, len(states), round(4 * sum(s[1] for s in states)), [s[5] for s in states])
    at += 16 + length
)");
    FILE* pipe = ::popen(("/usr/bin/python3 " + script + " " + file + " 2>&1").c_str(), "r");
    REQUIRE(pipe);
    std::string output;
    char line[4096];
    while (std::fgets(line, sizeof line, pipe))
        output += line;
    CHECK(::pclose(pipe) == 0);
    std::string counts;
    for (const auto& st : round.states)
        counts += (counts.empty() ? "" : ", ") + std::to_string(st.vertices.size());
    std::ostringstream expected;
    // Four times the summed credit: each state's is 0.25.
    expected << "12345 " << round.states.size() << " " << round.states.size() << " [" << counts << "]\n";
    CHECK(output == expected.str());
}
