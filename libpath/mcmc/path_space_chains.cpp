#include "mcmc/path_space_chains.h"

#include <chrono>
#include <cmath>
#include <optional>
#include <utility>

#include "util/error.h"
#include "path/path_record.h"
#include "sampling/render.h"
#include "sampling/seed_file.h"

namespace lt {

namespace {

Pcg32 chainStream(uint64_t seed, uint64_t chain) { return Pcg32(mixBits(mixBits(seed ^ 0x9a7c4a1ULL) + chain), chain); }

class PathSpaceChain final : public MarkovChain {
public:
    // `refine`: the BDPT sampler and film of the run's samples of b, one every `refineEvery` mutations. `minEdges`:
    // shorter paths are outside the target (PathSettings::minDepth, the direct split).
    PathSpaceChain(const Scene& scene, const std::vector<WeightedMutation>& mutations, MarkovPath start, Pcg32 rng,
                   uint64_t index, uint64_t dumpEvery, bool stream, const Bdpt* refine, const SampleFilm& film,
                   uint64_t refineEvery, uint64_t refineSeed, const PathTarget& target, int minEdges)
        : scene_(scene), mutations_(mutations), x_(std::move(start)), minEdges_(minEdges), rng_(rng),
          stats_(statisticsOf(mutations)),
          index_(index), dumpEvery_(dumpEvery), stream_(stream), refine_(refine), film_(film),
          refineEvery_(refineEvery), refineSeed_(refineSeed), target_(target) {
        if (target_) x_.target = target_(x_.v, x_.raster, x_.f);
        position_.contributions = x_.contribution();
        position_.target = x_.target;
    }

    uint64_t advance(uint64_t n, ChainImage& image, const std::function<bool()>& timeUp) override {
        uint64_t i = 0;
        std::vector<ImageContribution> none;
        for (; i < n; ++i) {
            if (i % 16 == 15 && timeUp()) break;
            const auto t0 = std::chrono::steady_clock::now();
            // Selection in proportion to weight x suitability at the current state.
            const double totalX = selectionMass(x_);
            double u = rng_.nextDouble() * totalX;
            size_t m = 0;
            for (; m + 1 < mutations_.size(); ++m) {
                const double w = mutations_[m].mutation->suitable(x_) ? mutations_[m].weight : 0.0;
                if (u < w) break;
                u -= w;
            }
            StrategyCounters& k = stats_[m];
            ++k.proposed;
            proposal_.figures = stats_.figures(m);
            mutations_[m].mutation->propose(x_, rng_, proposal_);
            // A mutation that changes the length (bidirectional, lens subpath) may reach a path the target leaves out.
            if (!proposal_.failed && proposal_.y.edges() < minEdges_) proposal_.failed = RejectCause::ZeroContribution;
            if (target_ && !proposal_.failed) {
                // Q(x -> y) = T(x -> y) / f*(y) was divided by the f* evaluatePath set; Q(y -> x) already
                // holds the current state's target.
                const double t = target_(proposal_.y.v, proposal_.y.raster, proposal_.y.f);
                proposal_.forwardQ *= proposal_.y.target / t;
                proposal_.y.target = t;
            }
            double a = 0;
            if (proposal_.failed) {
                ++k.rejected[size_t(*proposal_.failed)];
                position_.step(none, 0, 0, false, image);
                held_ += 1;
            } else {
                // Q times the selection probability at each state (suitability can differ between x and y).
                const double w = mutations_[m].weight;
                const double totalY = selectionMass(proposal_.y);
                const double forward = proposal_.forwardQ * w / totalX;
                const double reverse =
                    mutations_[m].mutation->suitable(proposal_.y) && totalY > 0 ? proposal_.reverseQ * w / totalY : 0.0;
                a = acceptance(forward, reverse);
                const bool move = rng_.nextDouble() < a;
                auto c = proposal_.y.contribution();
                position_.step(c, proposal_.y.target, a, move, image);
                if (stream_) streamStep(a, move);
                if (move) {
                    std::swap(x_, proposal_.y);
                    ++k.accepted;
                }
            }
            k.acceptance += a;
            if (proposal_.figures) proposal_.figures->settle(a);
            k.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            const uint64_t count = done + i + 1;
            if (dumpEvery_ && count % dumpEvery_ == 0) dumped_.push_back(toPathRecord(scene_, x_, index_, count));
            if (refine_ && count % refineEvery_ == 0)
                normalization.add(0, bdptSampleOfB(*refine_, film_, refineSeed_, count / refineEvery_));
        }
        position_.flush(image);
        if (stream_ && held_ > 0) emit(x_, held_);
        held_ = 0;
        return i;
    }

    void collect(MutationStatistics& strategies, SampleHealth& health) const override {
        strategies.merge(stats_);
        for (size_t m = 0; m < mutations_.size(); ++m)
            health.nonFinite += stats_[m].rejected[size_t(RejectCause::NonFinite)];
    }

    std::vector<file::PathRecord>& dumped() { return dumped_; }
    file::EncodedChainStates& streamed() { return streamed_; }

    // Empty statistics of the mix: a row per mutation, with its own figures.
    static MutationStatistics statisticsOf(const std::vector<WeightedMutation>& mutations) {
        std::vector<std::string> names;
        std::vector<std::unique_ptr<MutationFigures>> figures;
        for (const auto& m : mutations) {
            names.push_back(m.mutation->name());
            figures.push_back(m.mutation->makeFigures());
        }
        return MutationStatistics(std::move(names), std::move(figures));
    }

private:
    // The stream's records of one Metropolis step, as ChainPosition credits the image (path_space_chains.h
    // PathDump): called before the chain moves to the proposal.
    void streamStep(double a, bool move) {
        held_ += 1 - a;
        if (!move) {
            if (a > 0 && proposal_.y.target > 0) emit(proposal_.y, a);
            return;
        }
        if (held_ > 0) emit(x_, held_);
        held_ = a;
    }
    void emit(const MarkovPath& p, double credit) {
        toChainState(p, uint32_t(index_), credit, scratch_);
        streamed_.add(scratch_);
    }

    double selectionMass(const MarkovPath& p) const {
        double sum = 0;
        for (const auto& m : mutations_)
            if (m.mutation->suitable(p)) sum += m.weight;
        return sum;
    }

    const Scene& scene_;
    const std::vector<WeightedMutation>& mutations_;
    MarkovPath x_;
    int minEdges_;
    Pcg32 rng_;
    Proposal proposal_;
    ChainPosition position_;
    MutationStatistics stats_;
    uint64_t index_, dumpEvery_;
    std::vector<file::PathRecord> dumped_;
    bool stream_;
    double held_ = 0; // the stream's credit of the current state so far
    file::ChainState scratch_;
    file::EncodedChainStates streamed_;
    const Bdpt* refine_;
    const SampleFilm& film_;
    uint64_t refineEvery_, refineSeed_;
    const PathTarget& target_;
};

} // namespace

PathSpaceSeeds seedsFromFile(file::Content&& content, int minEdges) {
    SeedFile file = readSeedFile(std::move(content), minEdges);
    PathSpaceSeeds seeds;
    seeds.paths = std::move(file.paths);
    seeds.b.addMean(0, file.b, file.samples);
    return seeds;
}

namespace {

// A strategy path's resampling weight under a chain `target`: its MIS weight times the target of its vertices with
// f / p in place of f (every target is proportional to f's scale), as seedWeight weighs luminance.
double targetSeedWeight(const SampleFilm& film, const StrategyPath& path, const PathTarget& target) {
    if (!(path.misWeight > 0) || path.unweighted.isBlack()) return 0;
    const double w = path.misWeight * target(joinedVertices(path), path.raster, path.unweighted);
    return w > 0 && std::isfinite(w) ? seedWeight(film, path, w) : 0.0;
}

} // namespace

double bdptSampleOfB(const Bdpt& bdpt, const SampleFilm& film, uint64_t seed, uint64_t index,
                     const StrategyCallback* onPath) {
    thread_local std::vector<Splat> splats;
    SampleHealth health;
    IndependentSampler u(mixBits(mixBits(seed ^ 0x5eedULL) + index), index);
    const PixelRect window = film.window();
    const int x = window.x0 + std::min(int(u.next1D() * window.width()), window.width() - 1);
    const int y = window.y0 + std::min(int(u.next1D() * window.height()), window.height() - 1);
    double sum = 0;
    const StrategyCallback collect = [&](const StrategyPath& sp) {
        sum += seedWeight(film, sp);
        if (onPath) (*onPath)(sp);
    };
    splats.clear();
    (void)bdpt.sample(film.sampleRaster(x, y, u.next2D()), u, splats, health, &collect);
    return sum * double(window.area());
}

PathSpaceSeeds seedWithBdpt(const Scene& scene, const PathSettings& bdpt, uint64_t samples, size_t keep, uint64_t seed,
                            const RunControl& control, const PathTarget& target) {
    // `samples` BDPT samples at uniformly chosen pixels (not whole passes: on a large image a pass alone
    // would outlast a short run), each with its own keyed stream; candidates and samples of b reach the
    // reservoir and the estimate in sample order, block by block, so nothing depends on the thread count.
    const SampleFilm film(scene.camera);
    const Bdpt sampler(scene, bdpt);
    SeedReservoir reservoir(keep, seed ^ 0x9e3779b97f4a7c15ULL);
    PathSpaceSeeds out;
    constexpr uint64_t Block = 1024; // samples a work item
    struct SampleBlock {
        uint64_t index = 0;
        std::vector<file::PathRecord> candidates;
        std::vector<double> values;
    };
    ParallelRun run(control);
    uint64_t next = 0;
    run.ordered<SampleBlock>(
        [&](SampleBlock& block) {
            if (run.stopped() || next * Block >= samples) return false;
            block.index = next++;
            block.candidates.clear();
            block.values.clear();
            return true;
        },
        [&](SampleBlock& block) {
            for (uint64_t i = block.index * Block; i < std::min(samples, (block.index + 1) * Block); ++i) {
                const StrategyCallback collect = [&](const StrategyPath& sp) {
                    block.candidates.push_back(seedCandidate(scene, film, sp, i, 0));
                    if (target) block.candidates.back().weight = targetSeedWeight(film, sp, target);
                };
                block.values.push_back(bdptSampleOfB(sampler, film, seed, i, &collect));
            }
        },
        [&](SampleBlock& block) {
            for (const auto& c : block.candidates)
                reservoir.add(c);
            for (double v : block.values)
                out.b.add(0, v);
        });
    out.paths = reservoir.draws();
    return out;
}

ChainRunStats runPathSpaceChains(const Scene& scene, const PathSpaceSeeds& seeds,
                                 const std::vector<WeightedMutation>& mutations, const ChainRunSettings& run,
                                 const PathSettings& bdpt, double refineB, SampleFilm& film, const RunControl& control,
                                 const PathDump& dump, const PathTarget& target) {
    if (run.chains < 1) throw Error("the number of chains must be at least 1");
    if (run.mutations == 0 && !(run.timeLimit > 0)) throw Error("give a number of mutations or a time limit");
    if (mutations.empty()) throw Error("no mutation to run");
    if (seeds.paths.empty() || !(seeds.b.b() > 0)) throw Error("no seed paths with light to start the chains from");
    if (!(refineB >= 0 && refineB <= 1)) throw Error("the samples of b per mutation must be in [0, 1]");
    ChainRunSettings settings = run;
    settings.luminanceNormalized = bool(target);
    ChainRunner runner(settings, film, control);
    ChainRunStats stats;
    stats.strategies = PathSpaceChain::statisticsOf(mutations);
    stats.normalization = seeds.b;
    stats.startupSamples = seeds.b.samples();
    // The run's own samples of b: BDPT with the scene's settings, one every `refineEvery` mutations of a chain.
    std::optional<Bdpt> refine;
    const uint64_t refineEvery = refineB > 0 ? std::max<uint64_t>(1, uint64_t(std::llround(1 / refineB))) : 0;
    if (refineEvery) refine.emplace(scene, bdpt);

    // Each chain starts from a seed draw picked uniformly (the draws are already in proportion to
    // weight). A draw that does not re-create in this scene is replaced by another and counted.
    std::vector<std::unique_ptr<MarkovChain>> chains;
    uint64_t unusable = 0;
    for (int c = 0; c < run.chains; ++c) {
        Pcg32 rng = chainStream(run.seed, uint64_t(c));
        for (int attempt = 0;; ++attempt) {
            const size_t i = std::min(size_t(rng.nextDouble() * double(seeds.paths.size())), seeds.paths.size() - 1);
            try {
                MarkovPath start = pathFromRecord(scene, seeds.paths[i], i);
                if (start.edges() < bdpt.minDepth)
                    throw Error("seed path " + std::to_string(i) + " has " + std::to_string(start.edges()) +
                                " edges, fewer than the chains render");
                chains.push_back(std::make_unique<PathSpaceChain>(
                    scene, mutations, std::move(start), rng, uint64_t(c), dump.every, bool(dump.writeRound),
                    refine ? &*refine : nullptr, film, refineEvery,
                    mixBits(mixBits(run.seed ^ 0xb5a3b5a3ULL) + uint64_t(c)), target, bdpt.minDepth));
                break;
            } catch (const Error& e) {
                ++unusable;
                if (attempt >= 1000)
                    throw Error(std::string("no usable seed path after 1000 attempts; the last: ") + e.what());
            }
        }
    }
    stats.unusableSeeds = unusable;
    stats.startupSeconds = runner.elapsed();
    runner.assignQuotas(chains);
    std::function<void(std::vector<std::unique_ptr<MarkovChain>>&, const RoundEnd&)> afterRound;
    if ((dump.every && dump.write) || dump.writeRound)
        afterRound = [&](std::vector<std::unique_ptr<MarkovChain>>& all, const RoundEnd& end) {
            std::vector<file::EncodedChainStates> states;
            for (auto& c : all) {
                auto& chain = static_cast<PathSpaceChain&>(*c);
                if (dump.every && dump.write && !chain.dumped().empty()) dump.write(chain.dumped());
                chain.dumped().clear();
                states.push_back(std::exchange(chain.streamed(), {}));
            }
            if (dump.writeRound)
                dump.writeRound({end.mutations, end.b, end.bSamples, end.wallSeconds, end.cpuSeconds, {}},
                                std::move(states));
        };
    runner.run(chains, stats, afterRound);
    return stats;
}

} // namespace lt
