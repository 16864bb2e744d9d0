#include "mcmc/primary_space_chains.h"

#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

#include <chrono>
#include <memory>
#include <numeric>

#include "math/distribution.h"
#include "math/error.h"
#include "mcmc/metropolis.h"
#include "mcmc/primary_space_target.h"
#include "scene/accel.h"

namespace lt {

namespace {

enum Row : size_t { LargeStep = 0, SmallStep = 1 };

// The numbers of start-up sample `index` of path length `edges` (0 for Kelemen), and of chain `chain`:
// separate keyed streams, so nothing depends on the order in which threads run them.
Pcg32 startupStream(uint64_t seed, int edges, uint64_t index) {
    return Pcg32(mixBits(mixBits(seed ^ 0x5eed5eed5eedULL) + uint64_t(edges)) + index, index);
}
Pcg32 chainStream(uint64_t seed, uint64_t chain) {
    return Pcg32(mixBits(mixBits(seed ^ 0xc4a1c4a1ULL) + chain), chain);
}

class PrimarySpaceChain final : public MarkovChain {
public:
    PrimarySpaceChain(const PrimarySpaceTarget& target, const PrimarySpaceSettings& space, PrimarySampleVector start,
                      int edges)
        : target_(target), multiplexed_(space.space == PrimarySpace::Multiplexed),
          largeStep_(space.largeStepProbability), u_(std::move(start)), edges_(edges) {}

    uint64_t advance(uint64_t n, ChainImage& image, const std::function<bool()>& timeUp) override {
        if (!started_) {
            // The initial state: the start-up sample re-created from its own stream.
            started_ = true;
            position_.target = evaluate(position_.contributions);
        }
        Pcg32& rng = u_.rng();
        uint64_t i = 0;
        for (; i < n; ++i) {
            // A time limit or Ctrl-C ends the round early, so a slow round cannot overshoot; only runs
            // of a fixed mutation count are bit-reproducible.
            if (i % 16 == 15 && timeUp()) break;
            const bool large = rng.nextDouble() < largeStep_;
            StrategyCounters& k = stats_[large ? LargeStep : SmallStep];
            const auto t0 = std::chrono::steady_clock::now();
            u_.startIteration(large);
            const uint64_t bad = health_.nonFinite;
            const double f = evaluate(proposed_);
            ++k.proposed;
            // Symmetric kernels: a = f*(u') / f*(u) (ALGORITHMS.md 8).
            const double a = f > 0 ? std::min(1.0, f / position_.target) : 0.0;
            if (!(f > 0))
                ++k.rejected[size_t(health_.nonFinite > bad ? RejectCause::NonFinite : RejectCause::ZeroContribution)];
            const bool move = f > 0 && rng.nextDouble() < a;
            k.acceptance += a;
            position_.step(proposed_, f, a, move, image);
            if (move) {
                u_.accept();
                ++k.accepted;
            } else {
                u_.reject();
            }
            k.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        }
        position_.flush(image);
        return i;
    }

    void collect(MutationStatistics& strategies, SampleHealth& health) const override {
        strategies.merge(stats_);
        health.nonFinite += health_.nonFinite;
    }

private:
    double evaluate(std::vector<ImageContribution>& out) {
        return multiplexed_ ? target_.evaluateMultiplexed(edges_, u_, out, health_)
                            : target_.evaluateAll(u_, out, health_);
    }

    const PrimarySpaceTarget& target_;
    bool multiplexed_;
    double largeStep_;
    PrimarySampleVector u_;
    int edges_;
    bool started_ = false;
    ChainPosition position_;
    std::vector<ImageContribution> proposed_;
    MutationStatistics stats_{{"large step", "small step"}};
    SampleHealth health_;
};

} // namespace

ChainRunStats runPrimarySpaceChains(const Scene& scene, const PrimarySpaceSettings& space, const ChainRunSettings& run,
                                    SampleFilm& film, const ChainProgressCallback& progress,
                                    const std::atomic<bool>* stop, const ChainSnapshotCallback& snapshot) {
    if (run.chains < 1) throw Error("the number of chains must be at least 1");
    if (run.mutations == 0 && !(run.timeLimit > 0)) throw Error("give a number of mutations or a time limit");
    if (!(space.largeStepProbability >= 0 && space.largeStepProbability <= 1))
        throw Error("the large-step probability must be in [0, 1]");
    ChainRunner runner(run, film, progress, stop, snapshot);
    const PrimarySpaceTarget target(scene, space.bdpt, space.unboundedEdges);
    const bool multiplexed = space.space == PrimarySpace::Multiplexed;
    const double pixels = double(film.width()) * double(film.height());
    ChainRunStats stats;
    stats.strategies = MutationStatistics({"large step", "small step"});
    const int threads = run.threads > 0 ? run.threads : tbb::this_task_arena::max_concurrency();
    tbb::task_arena arena(threads);

    // 1. Start-up: independent primary samples, per path length for multiplexed MLT.
    const int lengths = multiplexed ? target.maxEdges() : 1;
    const uint64_t perLength = std::max<uint64_t>(1, space.startupSamples / uint64_t(lengths));
    std::vector<std::vector<double>> weights(size_t(lengths) + 1);
    std::atomic<uint64_t> startupNonFinite{0};
    for (int k = 1; k <= lengths && !runner.stopped(); ++k) {
        auto& w = weights[size_t(k)];
        w.assign(perLength, 0.0);
        arena.execute([&] {
            tbb::parallel_for(tbb::blocked_range<uint64_t>(0, perLength, 256),
                              [&](const tbb::blocked_range<uint64_t>& r) {
                                  std::vector<ImageContribution> c;
                                  SampleHealth health;
                                  for (uint64_t i = r.begin(); i != r.end(); ++i) {
                                      PrimarySampleVector u(Pcg32(), startupStream(run.seed, multiplexed ? k : 0, i),
                                                            space.smallStep);
                                      w[i] = multiplexed ? target.evaluateMultiplexed(k, u, c, health)
                                                         : target.evaluateAll(u, c, health);
                                  }
                                  EmbreeAccel::flushRayCount();
                                  startupNonFinite += health.nonFinite;
                              });
        });
        runner.report("start-up", double(k) / lengths, 0);
    }
    stats.startupSamples = perLength * uint64_t(lengths);
    stats.health.nonFinite = startupNonFinite.load();
    stats.bPerLength.assign(size_t(lengths) + 1, 0.0);
    for (int k = 1; k <= lengths; ++k) {
        // Summed in index order: the same b for any thread count.
        const auto& w = weights[size_t(k)];
        stats.bPerLength[size_t(k)] = std::accumulate(w.begin(), w.end(), 0.0) / double(perLength);
    }
    stats.b = std::accumulate(stats.bPerLength.begin(), stats.bPerLength.end(), 0.0);
    stats.startupSeconds = runner.elapsed();
    if (runner.stopped()) {
        stats.interrupted = true;
        runner.finish(stats);
        return stats;
    }
    if (!(stats.b > 0))
        throw Error("the start-up found no light reaching the camera in " + std::to_string(stats.startupSamples) +
                    " samples: nothing for the chains to start from (raise --startup-samples, or check the scene)");

    // 2. The chains: a path length for each (multiplexed), a start-up sample drawn in proportion to f*.
    std::vector<DiscreteDistribution> startFrom(size_t(lengths) + 1);
    for (int k = 1; k <= lengths; ++k)
        if (stats.bPerLength[size_t(k)] > 0) startFrom[size_t(k)] = DiscreteDistribution(weights[size_t(k)]);
    std::vector<double> lengthWeights(stats.bPerLength.begin() + 1, stats.bPerLength.end());
    const DiscreteDistribution lengthShare(lengthWeights);
    Pcg32 allocation = chainStream(run.seed, ~uint64_t(0));
    const double offset = allocation.nextDouble();
    stats.chainsPerLength.assign(size_t(lengths) + 1, 0);
    std::vector<std::unique_ptr<MarkovChain>> chains;
    for (int c = 0; c < run.chains; ++c) {
        Pcg32 rng = chainStream(run.seed, uint64_t(c));
        const int k = int(lengthShare.sample((c + offset) / run.chains)) + 1;
        const size_t index = startFrom[size_t(k)].sample(rng.nextDouble());
        chains.push_back(std::make_unique<PrimarySpaceChain>(
            target, space,
            PrimarySampleVector(rng, startupStream(run.seed, multiplexed ? k : 0, index), space.smallStep), k));
        ++stats.chainsPerLength[size_t(k)];
    }
    runner.assignQuotas(chains);

    // 3. Rounds of mutations.
    runner.run(chains, stats.b / pixels, stats);
    return stats;
}

} // namespace lt
