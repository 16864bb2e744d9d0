#include "run/mlt_job.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

#include "gdmlt/chain_gradient.h"
#include "run/run_summary.h"
#include "util/error.h"

namespace lt {

namespace {

// Tells the caller what the run does now (RunProgress::phase points into `what` for the call).
void tellPhase(const RunControl& control, const std::string& what) {
    RunProgress p;
    p.phase = what.c_str();
    if (control.progress) control.progress(p);
}

} // namespace

ChainSpace chainSpace(const std::string& name) {
    if (name == "path") return ChainSpace::Path;
    if (name == "primary") return ChainSpace::Primary;
    if (name == "multiplexed") return ChainSpace::Multiplexed;
    throw Error("no chain space named '" + name + "' (path, primary or multiplexed)");
}

MltJob::MltJob(const Scene& scene, MltSettings settings, std::optional<PathSpaceSeeds> seeds, MutationKinds kinds)
    : scene_(scene), settings_(std::move(settings)), seeds_(std::move(seeds)), kinds_(kinds) {
    if (seeds_) seedFileB_ = seeds_->b.b();
    MltSettings& s = settings_;
    s.direct.check();
    chainPaths_ = s.direct.chainPaths(s.paths);
    if (s.direct.samples > 0 && !split())
        notes_.push_back("the max depth " + std::to_string(s.paths.maxDepth) +
                         " leaves no path beyond the direct part's two edges: the chains render every path (no direct "
                         "split)");
    if (split() && s.space == ChainSpace::Multiplexed && s.paths.maxDepth < 0 && s.unboundedEdges <= DirectSplit::Edges)
        throw Error("--max-length-unbounded " + std::to_string(s.unboundedEdges) +
                    " leaves the chains no path longer than the direct part's two edges (--direct-samples -1 gives "
                    "them every path)");
    if (!pathSpace() && (s.dumpEvery > 0 || s.stream || s.target != ChainTarget::Luminance))
        throw Error("the chain-state stream, path dumps and other targets than luminance need --space path");
    if (s.stream && scene.camera.hasAperture())
        throw Error(scene.filename + ": --stream writes no lens points yet, and this scene's thinlens camera needs "
                                     "them (the gradient stage works with pinhole cameras)");
    if (s.startupSamples == 0) s.startupSamples = s.space == ChainSpace::Multiplexed ? 20000 : 100000;
    if (seeds_ && !pathSpace()) {
        std::ostringstream note;
        note << "--space " << (s.space == ChainSpace::Primary ? "primary" : "multiplexed")
             << " starts its chains from its own start-up samples; the " << seeds_->paths.size()
             << " seed paths are for --space path (their b = " << seeds_->b.b() << ")";
        notes_.push_back(note.str());
    }
    if (pathSpace()) {
        features_ = analyzeScene(scene);
        choice_ = chooseMutations(s.strategies, features_, kinds_);
        for (const auto& w : choice_.warnings)
            notes_.push_back("warning: " + w);
        for (const auto& why : choice_.leftOut)
            notes_.push_back("left out: " + why);
    }
}

int MltJob::maxEdges() const {
    // Unbounded: the path-space mutations build paths of any length (the bidirectional mutation changes a length by at
    // most MaxLengthChange, so its proposal needs no bound); multiplexed chains start from unboundedEdges lengths
    // and add more while the paths beyond carry light (primary_space_chains.h).
    if (settings_.paths.maxDepth > 0) return settings_.paths.maxDepth;
    return pathSpace() ? std::numeric_limits<int>::max() : settings_.unboundedEdges;
}

nlohmann::json MltJob::parameters() const {
    const MltSettings& s = settings_;
    const char* spaces[] = {"path", "primary", "multiplexed"};
    nlohmann::json p = {{"space", spaces[int(s.space)]},
                        {"mutations", s.run.mutations},
                        {"chains", s.run.chains},
                        {"round", s.run.mutationsPerRound},
                        {"estimator", "expected-value splatting; image = b / N sum f / f* at each state"},
                        {"target", s.target == ChainTarget::Gradient ? "gradient" : "luminance"},
                        {"direct_samples", split() ? s.direct.samples : -1}};
    if (s.target == ChainTarget::Gradient) {
        p["gradient_alpha"] = s.gradientAlpha;
        p["shift_threshold"] = s.shiftThreshold;
    }
    if (pathSpace()) {
        p["refine_b"] = s.refineB;
        if (!seeded()) p["startup_samples"] = s.startupSamples;
        p.update(mutationParameters(choice_, s.mutationValues));
        p["max_length"] = s.paths.maxDepth; // -1: unbounded
        return p;
    }
    const SmallStepKernel smallStep;
    p["large_step"] = s.largeStep;
    p["small_step"] = {{"s1", smallStep.s1()}, {"s2", smallStep.s2()}};
    p["startup_samples"] = s.startupSamples;
    p["startup_error"] = s.startupError;
    if (s.space == ChainSpace::Multiplexed) {
        p["max_length"] = s.paths.maxDepth; // -1: unbounded, the lengths grown as primary_space_chains.h says
        if (s.paths.maxDepth < 0) p["first_lengths"] = s.unboundedEdges;
    }
    return p;
}

void MltJob::runPathSpace(const RunControl& control, const PathDump& dump, SampleFilm& film, MltOutcome& out,
                          std::vector<file::StatTable>& prepared) {
    const MltSettings& s = settings_;
    const PathTarget target =
        s.target == ChainTarget::Gradient ? gradientTarget(scene_, s.gradientAlpha, s.shiftThreshold) : PathTarget{};
    const auto note = [&](const std::string& line) {
        if (control.note) control.note(line);
    };
    if (!seeded()) {
        // No seed paths: a BDPT start-up of its own, as lt-seed --paths would make it.
        tellPhase(control, "seeding with BDPT");
        RunControl seeding(control.threads);
        seeding.stop = control.stop;
        seeds_ = seedWithBdpt(scene_, chainPaths_, s.startupSamples, std::max<size_t>(4 * size_t(s.run.chains), 1024),
                              s.run.seed ^ 0x5eedULL, seeding, target);
        std::ostringstream line;
        line << "seeded with BDPT (" << s.startupSamples << " samples): b = " << seeds_->b.b();
        note(line.str());
    }
    OptionValues values = s.mutationValues;
    for (const auto& e : choice_.chosen) {
        if (!e.kind->prepare) continue;
        values.setDefaults(e.kind->options);
        tellPhase(control, "preparing the " + e.kind->name + " " + e.kind->noun);
        if (const auto found = e.kind->prepare({scene_, features_, seeds_->paths, s.run.seed, control.stop}, values)) {
            prepared.push_back(found->table);
            note(found->message);
        }
    }
    std::vector<std::unique_ptr<Mutation>> owned;
    std::vector<WeightedMutation> mix;
    makeMutations(choice_, {scene_, maxEdges(), chainPaths_.minDepth}, values, owned, mix);
    out.stats = runPathSpaceChains(scene_, *seeds_, mix, s.run, chainPaths_, s.refineB, film, control, dump, target);
    out.streamEnd = file::valueTable("normalization", {{"b", out.stats.normalization.b()},
                                                       {"b_samples", double(out.stats.normalization.samples())},
                                                       {"mutations", double(out.stats.mutations)}});
}

MltOutcome MltJob::run(const RunControl& control, const PathDump& dump) {
    const MltSettings& s = settings_;
    SampleFilm film(scene_.camera);
    const double pixels = double(film.width()) * double(film.height());
    MltOutcome out;
    std::vector<file::StatTable> prepared;
    // The direct part first, into the film's camera samples: every snapshot of the chains is then a whole image.
    RenderStats direct;
    if (split()) {
        tellPhase(control, "direct part");
        direct = renderDirectPart(scene_, s.paths, s.direct, s.run.seed, film, control);
    }
    if (pathSpace()) {
        runPathSpace(control, dump, film, out, prepared);
    } else {
        PrimarySpaceSettings ps;
        ps.space = s.space == ChainSpace::Primary ? PrimarySpace::Kelemen : PrimarySpace::Multiplexed;
        ps.paths = chainPaths_;
        ps.unboundedEdges = s.unboundedEdges;
        ps.largeStepProbability = s.largeStep;
        ps.startupSamples = s.startupSamples;
        ps.startupError = s.startupError;
        out.stats = runPrimarySpaceChains(scene_, ps, s.run, film, control);
    }
    const ChainRunStats& st = out.stats;
    if (s.run.timeLimit > 0 && st.startupSeconds > s.run.timeLimit)
        out.notes.push_back("warning: the start-up took " + formatSeconds(st.startupSeconds) +
                            ", longer than --time; the chains ran one round (lower --startup-samples)");
    for (std::string& w : untrustedB(st))
        out.notes.push_back(std::move(w));
    if (st.lengths >= MaxUnboundedEdges && st.tailB > TailBound * (st.normalization.b() + st.tailB))
        out.notes.push_back("warning: paths of over " + std::to_string(MaxUnboundedEdges) +
                            " edges carry an estimated " + std::to_string(100 * st.tailB / (st.normalization.b() + st.tailB)) +
                            "% of the light, which the chains leave out (give a --max-depth, or use --space primary)");
    out.image = film.toBuffer(st.b);
    std::optional<DirectSplitRecord> directRecord;
    if (split()) {
        directRecord = directSplitRecord(film, out.image, s.direct, direct);
        for (size_t c = 0; c < 3; ++c) {
            out.image.channels.push_back(std::string("direct.") + "RGB"[c]);
            out.image.planes.push_back(std::move(directRecord->planes[c]));
        }
    }
    out.tables.push_back(runTable(st,
                                  {{"mutations", double(st.mutations)},
                                   {"mutations_per_pixel", double(st.mutations) / pixels},
                                   {"chains", double(s.run.chains)}},
                                  {{"startup_seconds", st.startupSeconds}}));
    const NormalizationEstimate& b = st.normalization;
    std::vector<std::pair<std::string, double>> norm = {{"b", b.b()},
                                                        {"b_relative_standard_error", b.relativeStandardError()},
                                                        {"b_samples", double(b.samples())},
                                                        {"startup_samples", double(st.startupSamples)}};
    if (pathSpace()) {
        norm.emplace_back("unusable_seeds", double(st.unusableSeeds));
    } else {
        norm.emplace_back("startup_work", st.startupWork);
        norm.emplace_back("startup_relative_standard_error", st.startupError);
    }
    if (s.target != ChainTarget::Luminance) norm.emplace_back("film_b", st.b);
    if (seedFileB_) norm.emplace_back("b_seed_file", *seedFileB_);
    if (st.lengths > 0) {
        norm.emplace_back("lengths", double(st.lengths));
        norm.emplace_back("tail_b", st.tailB);
        norm.emplace_back("tail_b_standard_error", st.tailError);
    }
    out.tables.push_back(file::valueTable("normalization", norm));
    if (directRecord) out.tables.push_back(directRecord->table);
    out.tables.push_back(st.strategies.table());
    for (auto& t : st.strategies.figureTables())
        out.tables.push_back(std::move(t));
    for (auto& t : prepared)
        out.tables.push_back(std::move(t));
    if (s.space == ChainSpace::Multiplexed) {
        file::StatTable lengths{"path_lengths",
                                {"b", "b_standard_error", "b_samples", "chains_started", "mutations", "image_weight"},
                                {},
                                {}};
        for (size_t k = size_t(chainPaths_.minDepth); k < b.strata(); ++k) {
            lengths.rows.push_back(std::to_string(k) + " edges");
            lengths.values.push_back({b.stratumB(k), b.stratumStandardError(k), double(b.stratumSamples(k)),
                                      double(st.chainsPerLength[k]), double(st.mutationsPerLength[k]),
                                      k < st.stratumWeights.size() ? st.stratumWeights[k] : 0.0});
        }
        out.tables.push_back(lengths);
    }
    out.summary = summary(out, directRecord, direct);
    out.rates = rates(st, pixels);
    return out;
}

std::string MltJob::summary(const MltOutcome& out, const std::optional<DirectSplitRecord>& direct,
                            const RenderStats& directStats) const {
    const ChainRunStats& st = out.stats;
    const NormalizationEstimate& b = st.normalization;
    std::ostringstream o;
    if (direct)
        o << "direct part (paths of 1 and 2 edges): " << settings_.direct.samples
          << " Sobol samples/pixel of path tracing in " << formatSeconds(directStats.wallSeconds) << ", "
          << std::setprecision(3) << 100 * direct->share << "% of the image; the chains render the rest\n"
          << std::setprecision(6);
    // A seed file's b comes without its spread: with --refine-b 0 nothing measures it.
    const double se = b.relativeStandardError();
    o << "b = " << b.b();
    if (std::isfinite(se))
        o << " +- " << std::setprecision(2) << 100 * se << "%";
    else
        o << " (standard error unknown)";
    o << " from " << b.samples() << " samples (" << st.startupSamples
      << (pathSpace() ? " of the seed run" : " of the start-up") << ", " << b.samples() - st.startupSamples
      << " during the run)";
    if (!pathSpace())
        o << "; the start-up ended at b +- " << std::setprecision(2) << 100 * st.startupError << "% after "
          << std::lround(100 * st.startupWork) << "% of its budget";
    o << std::setprecision(6);
    if (pathSpace())
        o << "; chains started from " << seeds_->paths.size() << " seed paths (" << st.unusableSeeds
          << " unusable draws skipped)";
    o << '\n' << st.strategies.text();
    if (st.lengths > 0)
        o << "multiplexed chains cover paths of " << chainPaths_.minDepth << " to " << st.lengths
          << " edges (from " << settings_.unboundedEdges << ", grown while the paths beyond carried over "
          << 100 * TailBound << "% of b); the paths beyond: an estimated " << std::setprecision(2)
          << 100 * st.tailB / (b.b() + st.tailB) << "% +- " << 100 * st.tailError / (b.b() + st.tailB)
          << "% of b, left out\n"
          << std::setprecision(6);
    if (settings_.space == ChainSpace::Multiplexed) {
        o << "path lengths (edges: share of b +- standard error, share of the mutations, chains started there):\n";
        // Lengths with under 0.01 % of b and of the mutations are summed in one line.
        double restB = 0, restMutations = 0;
        size_t rest = 0;
        for (size_t k = size_t(chainPaths_.minDepth); k < b.strata(); ++k) {
            const double shareB = b.stratumB(k) / b.b();
            const double shareM = double(st.mutationsPerLength[k]) / double(std::max<uint64_t>(1, st.mutations));
            if (shareB < 1e-4 && shareM < 1e-4) {
                restB += shareB;
                restMutations += shareM;
                ++rest;
                continue;
            }
            o << "  " << std::setw(2) << k << ": " << std::setprecision(3) << std::setw(6) << 100 * shareB << "% +- "
              << std::setw(6) << 100 * b.stratumStandardError(k) / b.b() << "%, " << std::setw(6) << 100 * shareM
              << "%, " << st.chainsPerLength[k] << '\n';
        }
        if (rest)
            o << "  " << rest << " other lengths, each under 0.01 %: " << std::setprecision(2) << 100 * restB
              << "% of b, " << 100 * restMutations << "% of the mutations together\n";
    }
    return o.str();
}

std::vector<std::string> MltJob::untrustedB(const ChainRunStats& st) const {
    // The chains' part of the image is (b / N) sum f / f*: its scale is b, and b's relative error is the error of
    // every pixel's mean, which no number of mutations lowers. Above UntrustedB a 2.5-sigma error of b already moves
    // the image by more than 5 % (the bound lt's tests hold every method's regions to).
    constexpr double UntrustedB = 0.02;
    const NormalizationEstimate& b = st.normalization;
    const std::string remedy =
        (pathSpace() ? "draw more seed samples (lt-seed --spp, or --startup-samples without a seed file), raise "
                       "--refine-b or run longer"
                     : "lower --startup-error or raise --startup-samples; longer runs refine b with their large steps") +
        std::string(split() ? "" : ", or render the direct light apart (--direct-samples)");
    std::vector<std::string> warnings;
    const double se = b.relativeStandardError();
    if (se > UntrustedB) { // not NaN (a seed file's b alone: unknown, said in the summary)
        std::ostringstream o;
        o << "warning: b, the scale of the chains' image, is known only to +- " << std::setprecision(2) << 100 * se
          << "% (over " << 100 * UntrustedB << "%): every pixel may be off by that much; " << remedy;
        warnings.push_back(o.str());
    }
    // MMLT scales each length's image by its own b_k (chain_run.h), so a region lit by paths of one length alone
    // carries b_k's relative error, however well b as a whole is known (a lamp seen directly, length 1, was 95 % of
    // b +- 95 % on a public scene). A length holds a region alone only where it is a large part of the light: the
    // long tail of bounces spreads over the whole image under the short lengths (on cornell-box, 24 x 24, default
    // start-up, length 7 holds 3 % of b +- 2.8 % of itself and lights no region on its own), so lengths under
    // LengthShare of b are left out; b's own warning covers their sum.
    constexpr double LengthShare = 0.1;
    if (settings_.space == ChainSpace::Multiplexed && b.b() > 0) {
        std::ostringstream lengths;
        int count = 0;
        for (size_t k = size_t(chainPaths_.minDepth); k < b.strata(); ++k) {
            const double bk = b.stratumB(k), rk = bk > 0 ? b.stratumStandardError(k) / bk : 0.0;
            if (bk < LengthShare * b.b() || !(rk > UntrustedB)) continue;
            lengths << (count++ ? ", " : "") << k << (k == 1 ? " edge" : " edges") << " +- " << std::fixed
                    << std::setprecision(1) << 100 * rk << "% (" << 100 * bk / b.b() << "% of b)";
        }
        if (count)
            warnings.push_back("warning: MMLT scales each path length by its own b_k, known only to " + lengths.str() +
                               ", over " + std::to_string(int(100 * UntrustedB)) +
                               "%: where paths of such a length light the image alone it may be off by that much; " +
                               remedy);
    }
    return warnings;
}

std::string MltJob::rates(const ChainRunStats& st, double pixels) {
    std::ostringstream o;
    o << (st.interrupted ? "interrupted after " : "") << std::setprecision(4) << double(st.mutations) / pixels
      << " mutations/pixel in " << formatSeconds(st.wallSeconds) << " (" << std::setprecision(3)
      << double(st.mutations) / st.wallSeconds / 1e3 << "k mutations/s, " << double(st.rays) / st.wallSeconds / 1e6
      << "M rays/s)" << nonFiniteNote(st.health, "samples");
    return o.str();
}

} // namespace lt
