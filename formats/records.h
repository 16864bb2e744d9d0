// The in-memory form of what lt's files hold (formats/SPEC.md gives the byte layout; formats/ltfile.h
// reads and writes it). Plain data, no behaviour: libpath fills and consumes these.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace lt::file {

enum class FileKind : uint32_t { Paths = 1, Buffer = 2 };

// One vertex of a stored light path: enough to re-create the vertex
// exactly in the same scene (shape + primitive + barycentrics; differential geometry is recomputed)
// and to look at it.
enum class VertexKind : uint8_t { Camera = 0, Light = 1, Surface = 2, PortalCrossing = 3 };
struct VertexRecord {
    VertexKind kind = VertexKind::Surface;
    uint8_t lobe = 0;                 // bsdf/bsdf.h Lobe bits of the scattering at this vertex
    uint8_t flags = 0;                // bit 0: degenerate position (pinhole, point light); bit 1: degenerate direction
    uint8_t reserved = 0;
    int32_t shape = -1;               // index into the scene's shapes (-1: none, e.g. camera, point light)
    uint32_t prim = 0;                // triangle index
    std::array<double, 2> coords{};   // barycentrics (b1, b2) or analytic uv
    std::array<double, 3> p{};        // position (double: manifold walks need it)
    std::array<float, 3> ng{};        // geometric normal
    std::array<float, 3> ns{};        // shading normal
    int32_t bsdf = -1;                // index into the scene's BSDFs
    int32_t light = -1;               // index into the scene's emitters
    float roughness = 0;              // Beckmann-equivalent alpha of the BSDF here
    double pdfFwd = 0;                // area density of sampling this vertex from its predecessor
    double pdfRev = 0;                // area density of sampling it from its successor
};

struct PathRecord {
    std::vector<VertexRecord> vertices;   // light-to-eye order: vertices[0] on a light, back() on the camera
    std::array<float, 2> raster{};        // continuous raster position (pixels of the full film)
    uint16_t s = 0, t = 0;                // BDPT technique: s light-subpath vertices, t camera-subpath vertices
    std::array<float, 3> contribution{};  // unweighted f / p (RGB)
    double pdf = 0;                       // sampling density of the technique (product-area measure)
    double misWeight = 0;                 // MIS weight of the technique
    double weight = 0;                    // resampling weight (luminance of the MIS-weighted contribution)
    uint64_t rngStream = 0;               // RNG stream and offset it came from (primary-sample-space replay)
    uint64_t rngOffset = 0;
};

// One state of a path-space Markov chain with the credit the chain's image gave it (lt-mutate --stream,
// SPEC.md "CHST"): an estimator downstream re-weighs the chain's samples from these alone. The image of
// the run is (b / N) x sum of credit x f / f* splatted at the raster positions (N: the mutations).
struct ChainState {
    uint32_t chain = 0;
    double credit = 0;             // expected-value credit: a for a proposal, the sum of 1 - a for a state held
    std::array<float, 2> raster{}; // continuous raster position (pixels of the full film)
    std::array<float, 3> f{};      // the contribution f (image units, RGB)
    float target = 0;              // f*, the value of the chain's target function
    // Light to eye, as a chain state's path record holds them; stored are only what re-creates them: kind,
    // lobe, shape, prim and coords, and at the light vertex light, p and ng.
    std::vector<VertexRecord> vertices;
};

// What one round of all chains credited, in chain order, with the run's figures after it.
struct ChainRound {
    uint64_t mutations = 0; // all chains' mutations so far (N)
    double b = 0;           // the normalization as it stands after the round
    uint64_t bSamples = 0;  // the independent samples b rests on
    double wallSeconds = 0; // of the run so far
    double cpuSeconds = 0;
    std::vector<ChainState> states;
};

// A set of named float planes of one size, e.g. "primal.R", "dx.G", "var.B"; plus per-pixel sample
// counts and how this buffer combines with another's.
struct Buffer {
    uint32_t width = 0, height = 0;
    std::vector<std::string> channels;            // channel names, one plane each
    std::vector<std::vector<float>> planes;       // planes[c][y * width + x], rows top to bottom
    std::vector<uint32_t> sampleCounts;           // per pixel (may be empty)
    double weight = 1;                            // merge weight (e.g. total samples or mutations)
    std::string combine = "weighted-mean";        // how buffers combine: "weighted-mean" or "sum"
};

struct Snapshot {
    double wallSeconds = 0;
    double cpuSeconds = 0;
    uint64_t samples = 0;          // samples (or mutations) so far
    double overheadSeconds = 0;    // time spent writing snapshots so far (reported, not hidden)
    Buffer buffer;
};

// Per-strategy counters of a Markov chain run (or any table of named counts).
struct StatTable {
    std::string name;                              // e.g. "strategies"
    std::vector<std::string> columns;              // e.g. proposed, accepted, occluded, ...
    std::vector<std::string> rows;                 // e.g. bidirectional, lens, ...
    std::vector<std::vector<double>> values;       // values[row][column]
};

} // namespace lt::file
