#include "mcmc/primary_space_chains.h"

#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

#include <chrono>
#include <ctime>
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

double cpuSeconds() { return double(std::clock()) / CLOCKS_PER_SEC; }

// The numbers of start-up sample `index` of path length `edges` (0 for Kelemen), and of chain `chain`:
// separate keyed streams, so nothing depends on the order in which threads run them.
Pcg32 startupStream(uint64_t seed, int edges, uint64_t index) {
    return Pcg32(mixBits(mixBits(seed ^ 0x5eed5eed5eedULL) + uint64_t(edges)) + index, index);
}
Pcg32 chainStream(uint64_t seed, uint64_t chain) {
    return Pcg32(mixBits(mixBits(seed ^ 0xc4a1c4a1ULL) + chain), chain);
}

struct Chain {
    Chain(PrimarySampleVector start, int length) : u(std::move(start)), edges(length) {}
    PrimarySampleVector u;
    ChainPosition position;
    int edges = 0;
    uint64_t quota = 0, done = 0;
    bool started = false;
    MutationStatistics stats{{"large step", "small step"}};
    SampleHealth health;
};

} // namespace

ChainRunStats runPrimarySpaceChains(const Scene& scene, const PrimarySpaceSettings& space, const ChainRunSettings& run,
                                    SampleFilm& film, const ChainProgressCallback& progress,
                                    const std::atomic<bool>* stop, const ChainSnapshotCallback& snapshot) {
    if (run.chains < 1) throw Error("the number of chains must be at least 1");
    if (run.mutations == 0 && !(run.timeLimit > 0)) throw Error("give a number of mutations or a time limit");
    if (!(space.largeStepProbability >= 0 && space.largeStepProbability <= 1))
        throw Error("the large-step probability must be in [0, 1]");
    const PrimarySpaceTarget target(scene, space.bdpt, space.unboundedEdges);
    const bool multiplexed = space.space == PrimarySpace::Multiplexed;
    const double pixels = double(film.width()) * double(film.height());

    const auto start = std::chrono::steady_clock::now();
    const double cpuStart = cpuSeconds();
    auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
    const uint64_t raysBefore = EmbreeAccel::rayCount();
    ChainRunStats stats;
    stats.strategies = MutationStatistics({"large step", "small step"});
    auto report = [&](const char* phase, double fraction, uint64_t mutations, uint64_t total) {
        if (!progress) return;
        ChainRunProgress p;
        p.phase = phase;
        p.fraction = fraction;
        p.mutations = mutations;
        p.totalMutations = total;
        p.wallSeconds = elapsed() - stats.snapshotSeconds;
        p.cpuSeconds = cpuSeconds() - cpuStart;
        p.snapshotSeconds = stats.snapshotSeconds;
        progress(p);
    };
    auto stopped = [&] { return stop && stop->load(); };

    const int threads = run.threads > 0 ? run.threads : tbb::this_task_arena::max_concurrency();
    tbb::task_arena arena(threads);

    // 1. Start-up: independent primary samples, per path length for multiplexed MLT.
    const int lengths = multiplexed ? target.maxEdges() : 1;
    const uint64_t perLength = std::max<uint64_t>(1, space.startupSamples / uint64_t(lengths));
    std::vector<std::vector<double>> weights(size_t(lengths) + 1);
    std::atomic<uint64_t> startupNonFinite{0};
    for (int k = 1; k <= lengths && !stopped(); ++k) {
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
        report("start-up", double(k) / lengths, 0, 0);
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
    stats.startupSeconds = elapsed();
    if (stopped()) {
        stats.interrupted = true;
        stats.wallSeconds = elapsed();
        stats.cpuSeconds = cpuSeconds() - cpuStart;
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
    std::vector<std::unique_ptr<Chain>> chains;
    for (int c = 0; c < run.chains; ++c) {
        Pcg32 rng = chainStream(run.seed, uint64_t(c));
        const int k = int(lengthShare.sample((c + offset) / run.chains)) + 1;
        const size_t index = startFrom[size_t(k)].sample(rng.nextDouble());
        auto chain = std::make_unique<Chain>(
            PrimarySampleVector(rng, startupStream(run.seed, multiplexed ? k : 0, index), space.smallStep), k);
        ++stats.chainsPerLength[size_t(k)];
        if (run.mutations > 0)
            chain->quota = run.mutations / uint64_t(run.chains) + (uint64_t(c) < run.mutations % uint64_t(run.chains));
        else
            chain->quota = ~uint64_t(0);
        chains.push_back(std::move(chain));
    }

    // 3. Rounds: every chain advances by up to mutationsPerRound, then the splats merge in chain order.
    const double scale = stats.b / pixels;
    SnapshotSchedule schedule = run.snapshots;
    const double pLarge = space.largeStepProbability;
    for (;;) {
        const double t = elapsed() - stats.snapshotSeconds;
        const bool timeUp = run.timeLimit > 0 && t >= run.timeLimit;
        bool remaining = false;
        for (const auto& c : chains)
            remaining |= c->done < c->quota;
        if (timeUp || !remaining) break;
        if (stopped()) {
            stats.interrupted = true;
            break;
        }
        std::vector<ChainImage> images(chains.size(), ChainImage(scale));
        std::vector<uint64_t> roundMutations(chains.size(), 0);
        arena.execute([&] {
            tbb::parallel_for(size_t(0), chains.size(), [&](size_t ci) {
                Chain& ch = *chains[ci];
                ChainImage& image = images[ci];
                std::vector<ImageContribution> proposed;
                if (!ch.started) {
                    // The initial state: the start-up sample re-created from its own stream.
                    ch.started = true;
                    ch.position.target =
                        multiplexed ? target.evaluateMultiplexed(ch.edges, ch.u, ch.position.contributions, ch.health)
                                    : target.evaluateAll(ch.u, ch.position.contributions, ch.health);
                }
                const uint64_t n = std::min<uint64_t>(uint64_t(run.mutationsPerRound), ch.quota - ch.done);
                Pcg32& rng = ch.u.rng();
                uint64_t i = 0;
                for (; i < n; ++i) {
                    // A time limit or Ctrl-C ends the round early (checked every 16 mutations, so a slow
                    // round cannot overshoot); only runs of a fixed mutation count are bit-reproducible.
                    if (i % 16 == 15 && ((run.timeLimit > 0 && elapsed() - stats.snapshotSeconds >= run.timeLimit) || stopped()))
                        break;
                    const bool large = rng.nextDouble() < pLarge;
                    StrategyCounters& k = ch.stats[large ? LargeStep : SmallStep];
                    const auto t0 = std::chrono::steady_clock::now();
                    ch.u.startIteration(large);
                    const uint64_t bad = ch.health.nonFinite;
                    const double f = multiplexed ? target.evaluateMultiplexed(ch.edges, ch.u, proposed, ch.health)
                                                 : target.evaluateAll(ch.u, proposed, ch.health);
                    ++k.proposed;
                    // Symmetric kernels: a = f*(u') / f*(u) (ALGORITHMS.md 8).
                    const double a = ch.position.target > 0 ? std::min(1.0, f / ch.position.target) : 1.0;
                    if (!(f > 0))
                        ++k.rejected[size_t(ch.health.nonFinite > bad ? RejectCause::NonFinite
                                                                      : RejectCause::ZeroContribution)];
                    const bool move = f > 0 && rng.nextDouble() < a;
                    k.acceptance += f > 0 ? a : 0.0;
                    ch.position.step(proposed, f, f > 0 ? a : 0.0, move, image);
                    if (move) {
                        ch.u.accept();
                        ++k.accepted;
                    } else {
                        ch.u.reject();
                    }
                    k.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
                }
                ch.position.flush(image);
                ch.done += i;
                roundMutations[ci] = i;
                EmbreeAccel::flushRayCount();
            });
        });
        for (size_t ci = 0; ci < chains.size(); ++ci) {
            TileResult r;
            r.splats = std::move(images[ci].splats());
            r.lightPaths = roundMutations[ci];
            film.merge(r);
            stats.mutations += roundMutations[ci];
        }
        const uint64_t total = run.mutations;
        const double wall = elapsed() - stats.snapshotSeconds;
        double fraction = total > 0 ? double(stats.mutations) / double(total) : -1;
        if (run.timeLimit > 0) fraction = std::max(fraction, std::min(1.0, wall / run.timeLimit));
        if (snapshot && schedule.due(wall, double(stats.mutations) / pixels)) {
            ChainRunProgress p;
            p.phase = "chains";
            p.mutations = stats.mutations;
            p.totalMutations = total;
            p.wallSeconds = wall;
            p.cpuSeconds = cpuSeconds() - cpuStart;
            p.snapshotSeconds = stats.snapshotSeconds;
            const double s0 = elapsed();
            snapshot(p, film);
            ++stats.snapshots;
            stats.snapshotSeconds += elapsed() - s0;
        }
        report("chains", fraction, stats.mutations, total);
    }
    for (const auto& c : chains) {
        stats.strategies.merge(c->stats);
        stats.health.nonFinite += c->health.nonFinite;
    }
    stats.wallSeconds = elapsed() - stats.snapshotSeconds;
    stats.cpuSeconds = cpuSeconds() - cpuStart;
    stats.rays = EmbreeAccel::rayCount() - raysBefore;
    return stats;
}

} // namespace lt
