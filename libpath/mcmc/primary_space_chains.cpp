#include "mcmc/primary_space_chains.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <optional>

#include "math/distribution.h"
#include "util/error.h"
#include "mcmc/metropolis.h"
#include "mcmc/primary_space_target.h"

namespace lt {

namespace {

enum Row : size_t { LargeStep = 0, SmallStep = 1 };

// The share of each start-up round after the pilot that is spread evenly over the path lengths (the rest
// follows Neyman allocation; file comment of primary_space_chains.h).
constexpr double EvenShare = 0.25;

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
    // `lengths` (multiplexed only): q, the distribution of a large step's path length (index = edges - 1).
    PrimarySpaceChain(const PrimarySpaceTarget& target, const PrimarySpaceSettings& space, PrimarySampleVector start,
                      int edges, const DiscreteDistribution* lengths)
        : target_(target), largeStep_(space.largeStepProbability), u_(std::move(start)), edges_(edges),
          lengths_(lengths), mutationsPerLength_(lengths ? lengths->size() + 1 : 0, 0) {
        if (lengths_) normalization = NormalizationEstimate(lengths_->size() + 1);
    }

    uint64_t advance(uint64_t n, ChainImage& image, const std::function<bool()>& timeUp) override {
        if (!started_) {
            // The initial state: the start-up sample re-created from its own stream.
            started_ = true;
            position_.target = evaluate(edges_, position_.contributions);
            position_.stratum = stratum(edges_);
        }
        Pcg32& rng = u_.rng();
        // One clock reading per proposal: each is charged the time since the previous one ended (a
        // proposal costs about a microsecond, two readings of the clock were 3 % of it).
        auto t0 = std::chrono::steady_clock::now();
        uint64_t i = 0;
        for (; i < n; ++i) {
            // A time limit or Ctrl-C ends the round early, so a slow round cannot overshoot; only runs
            // of a fixed mutation count are bit-reproducible.
            if (i % 16 == 15 && timeUp()) break;
            const bool large = rng.nextDouble() < largeStep_;
            StrategyCounters& k = stats_[large ? LargeStep : SmallStep];
            const int edges = large && lengths_ ? int(lengths_->sample(rng.nextDouble())) + 1 : edges_;
            u_.startIteration(large);
            const uint64_t bad = health_.nonFinite;
            const double f = evaluate(edges, proposed_);
            ++k.proposed;
            // A large step's u' is uniform: f*(u') is an independent sample of b (of b_k' when multiplexed).
            if (large) normalization.add(stratum(edges), f);
            // Symmetric in u; a multiplexed large step's length is an independence proposal (file comment
            // of primary_space_chains.h).
            const double lengthRatio =
                edges == edges_ ? 1.0 : lengths_->pmf(size_t(edges_ - 1)) / lengths_->pmf(size_t(edges - 1));
            const double a = f > 0 ? std::min(1.0, f * lengthRatio / position_.target) : 0.0;
            if (!(f > 0))
                ++k.rejected[size_t(health_.nonFinite > bad ? RejectCause::NonFinite : RejectCause::ZeroContribution)];
            const bool move = f > 0 && rng.nextDouble() < a;
            k.acceptance += a;
            position_.step(proposed_, f, a, move, image, stratum(edges));
            if (move) {
                u_.accept();
                edges_ = edges;
                ++k.accepted;
            } else {
                u_.reject();
            }
            if (lengths_) ++mutationsPerLength_[size_t(edges_)];
            const auto t1 = std::chrono::steady_clock::now();
            k.seconds += std::chrono::duration<double>(t1 - t0).count();
            t0 = t1;
        }
        position_.flush(image);
        return i;
    }

    void collect(MutationStatistics& strategies, SampleHealth& health) const override {
        strategies.merge(stats_);
        health.nonFinite += health_.nonFinite;
    }
    void collectLengths(std::vector<uint64_t>& mutations) const {
        for (size_t k = 0; k < mutationsPerLength_.size(); ++k)
            mutations[k] += mutationsPerLength_[k];
    }

private:
    // The stratum of b, and of the image (chain_run.h), of a state of `edges` edges: its length when multiplexed.
    [[nodiscard]] size_t stratum(int edges) const { return lengths_ ? size_t(edges) : 0; }
    double evaluate(int edges, std::vector<ImageContribution>& out) {
        return lengths_ ? target_.evaluateMultiplexed(edges, u_, out, health_) : target_.evaluateAll(u_, out, health_);
    }

    const PrimarySpaceTarget& target_;
    double largeStep_;
    PrimarySampleVector u_;
    int edges_;
    const DiscreteDistribution* lengths_;
    bool started_ = false;
    ChainPosition position_;
    std::vector<ImageContribution> proposed_;
    MutationStatistics stats_{{"large step", "small step"}};
    SampleHealth health_;
    std::vector<uint64_t> mutationsPerLength_;
};

// The start-up (file comment of primary_space_chains.h): independent primary samples of every path length (one
// length, 0, for Kelemen's), in rounds, until b is known to `startupError` or the budget is spent. Their values
// stay for the choice of the chains' first states.
class StartUp {
public:
    StartUp(const PrimarySpaceTarget& target, const PrimarySpaceSettings& space, uint64_t seed, ChainRunner& runner)
        : target_(target), space_(space), seed_(seed), runner_(runner),
          multiplexed_(space.space == PrimarySpace::Multiplexed),
          unbounded_(multiplexed_ && space.paths.maxDepth < 0), first_(multiplexed_ ? target.minEdges() : 1) {
        addLengths(multiplexed_ ? target.maxEdges() : 1);
    }

    // The path lengths of the chains: first() .. lengths() (multiplexed; 1 .. 1 for Kelemen's, whose one stratum
    // holds every length).
    [[nodiscard]] int first() const { return first_; }
    [[nodiscard]] int lengths() const { return lengths_; }
    [[nodiscard]] size_t stratum(int k) const { return multiplexed_ ? size_t(k) : 0; }
    [[nodiscard]] double workDone() const { return spent_ / budget_; }
    [[nodiscard]] uint64_t nonFinite() const { return nonFinite_; }
    // The values of length k's samples, in index order.
    [[nodiscard]] std::vector<double>& values(int k) { return values_[size_t(k)]; }

    // The pilot spends 1/8 of the budget spread as the budget (at least two samples a length, for a deviation);
    // each later round adds half the work done, a quarter spread so and the rest by Neyman allocation from the
    // deviations seen so far. With an unbounded depth, then, while the paths beyond the longest length carry more than
    // TailBound of b, the lengths double (file comment of primary_space_chains.h), each new one with its pilot, and the
    // rounds go on.
    void run(NormalizationEstimate& b) {
        b = NormalizationEstimate(multiplexed_ ? size_t(lengths_) + 1 : 1);
        pilot(first_, b);
        rounds(b);
        while (unbounded_ && !runner_.stopped()) {
            tail_ = tailEstimate(b);
            if (!(tail_.b > TailBound * (b.b() + tail_.b)) || lengths_ >= MaxUnboundedEdges) break;
            const int from = lengths_ + 1;
            addLengths(std::min(2 * lengths_, MaxUnboundedEdges));
            b.addStrata(size_t(lengths_) + 1);
            pilot(from, b);
            rounds(b);
        }
    }
    // b beyond the longest length, as the last estimate found it (0 with a bounded depth).
    struct Tail {
        double b = 0, error = 0;
    };
    [[nodiscard]] const Tail& tail() const { return tail_; }

private:
    [[nodiscard]] double cost(int k) const { return multiplexed_ ? double(k + 1) : 1.0; }

    // Lengths up to `lengths`, with their budget: `startupSamples` per path length on average, n_k = startupSamples x
    // (mean length) / k for length k, the same work (about k + 1 rays a sample) for every length; lengths added later
    // take their budget from the new mean.
    void addLengths(int lengths) {
        const int from = std::max(lengths_ + 1, first_);
        lengths_ = lengths;
        budgetCount_.resize(size_t(lengths_) + 1, 0.0);
        values_.resize(size_t(lengths_) + 1);
        for (int k = from; k <= lengths_; ++k) {
            budgetCount_[size_t(k)] =
                double(space_.startupSamples) * (multiplexed_ ? 0.5 * (lengths_ + first_) / k : 1.0);
            budget_ += budgetCount_[size_t(k)] * cost(k);
        }
    }

    void pilot(int from, NormalizationEstimate& b) {
        std::vector<uint64_t> add(size_t(lengths_) + 1, 0);
        for (int k = from; k <= lengths_; ++k)
            add[size_t(k)] = std::max<uint64_t>(2, uint64_t(budgetCount_[size_t(k)] / 8));
        draw(add, b);
    }

    void rounds(NormalizationEstimate& b) {
        while (!runner_.stopped() && spent_ < budget_) {
            if (space_.startupError > 0 && b.b() > 0 && b.relativeStandardError() <= space_.startupError) break;
            const std::vector<uint64_t> add = nextRound(b);
            uint64_t added = 0;
            for (const uint64_t n : add)
                added += n;
            if (added == 0) break;
            draw(add, b);
        }
    }

    // Samples of the b of all lengths beyond the longest, L (file comment): a length L + j, j >= 1 drawn with
    // probability (1 - c) c^(j - 1) (Russian roulette beyond L), u uniform, and f*(L + j, u) over that probability.
    // c follows the decay of b over the last two lengths, within [0.5, 0.95]; lengths beyond MaxUnboundedEdges count
    // as 0. As many samples as the last length's budget, at least 4096, keyed by their index.
    [[nodiscard]] Tail tailEstimate(const NormalizationEstimate& b) {
        const double before = b.stratumB(size_t(lengths_) - 1);
        const double c = std::clamp(before > 0 ? b.stratumB(size_t(lengths_)) / before : 0.5, 0.5, 0.95);
        const uint64_t n = std::max<uint64_t>(4096, uint64_t(budgetCount_[size_t(lengths_)]));
        constexpr uint64_t Block = 256;
        std::vector<double> values(n);
        runner_.parallel().forEach(
            (n + Block - 1) / Block,
            [&](uint64_t block) {
                std::vector<ImageContribution> contributions;
                SampleHealth health;
                for (uint64_t i = block * Block; i < std::min(n, (block + 1) * Block); ++i) {
                    Pcg32 roulette = startupStream(seed_ ^ 0x7a11ULL, lengths_, i);
                    const int j = 1 + int(std::floor(std::log1p(-roulette.nextDouble()) / std::log(c)));
                    const double p = (1 - c) * std::pow(c, j - 1);
                    values[i] = 0;
                    if (lengths_ + j > MaxUnboundedEdges) continue;
                    PrimarySampleVector u(Pcg32(), startupStream(seed_ ^ 0x7a11ULL, -lengths_, i), space_.smallStep);
                    values[i] = target_.evaluateMultiplexed(lengths_ + j, u, contributions, health) / p;
                }
                nonFiniteBlocks_ += health.nonFinite;
            },
            [](uint64_t) {});
        nonFinite_ += nonFiniteBlocks_.exchange(0);
        spent_ += double(n) * cost(lengths_ + int(1 / (1 - c)));
        NormalizationEstimate tail;
        for (const double v : values)
            tail.add(0, v);
        return {tail.b(), tail.stratumStandardError(0)};
    }

    // The samples of the next round: half the work so far (the start-up ends within 1.5 times the work its error
    // needs). A quarter of it spread as the budget, the rest by Neyman allocation: a length whose samples so far
    // show no spread (a rare light the pilot missed) still gets its even share, so no length's count rests on the
    // values drawn alone. All of it spread so while no light is seen at all.
    [[nodiscard]] std::vector<uint64_t> nextRound(const NormalizationEstimate& b) const {
        const double work = std::min(spent_ / 2, budget_ - spent_);
        std::vector<double> deviation(size_t(lengths_) + 1, 0.0), costs(deviation.size(), 1.0);
        std::vector<uint64_t> have(deviation.size(), 0), even(deviation.size(), 0);
        for (int k = first_; k <= lengths_; ++k) {
            deviation[size_t(k)] = b.stratumDeviation(stratum(k));
            costs[size_t(k)] = cost(k);
            even[size_t(k)] = uint64_t(budgetCount_[size_t(k)] * EvenShare * work / budget_);
            have[size_t(k)] = values_[size_t(k)].size() + even[size_t(k)];
        }
        std::vector<uint64_t> add = neymanAllocation(deviation, costs, have, (1 - EvenShare) * work);
        uint64_t added = 0;
        for (size_t k = 0; k < add.size(); ++k)
            added += add[k];
        for (int k = first_; k <= lengths_; ++k)
            add[size_t(k)] += added > 0 ? even[size_t(k)] : uint64_t(budgetCount_[size_t(k)] * work / budget_);
        return add;
    }

    // `add[k]` more samples of each length k, keyed by their index within the length; their values join b in index
    // order, so b is the same for any thread count. In chunks of an eighth of the length's share of the budget (at
    // least 4096), so that Ctrl-C ends even a round that gives one length half the budget soon.
    void draw(const std::vector<uint64_t>& add, NormalizationEstimate& b) {
        constexpr uint64_t Block = 256; // samples a work item
        for (int k = first_; k <= lengths_; ++k) {
            std::vector<double>& v = values_[size_t(k)];
            const uint64_t chunk = std::max<uint64_t>(4096, uint64_t(budgetCount_[size_t(k)] / 8));
            for (uint64_t done = 0; done < add[size_t(k)] && !runner_.stopped();) {
                const uint64_t count = std::min(chunk, add[size_t(k)] - done);
                const size_t begin = v.size();
                v.resize(begin + count);
                runner_.parallel().forEach(
                    (count + Block - 1) / Block,
                    [&](uint64_t block) {
                        std::vector<ImageContribution> c;
                        SampleHealth health;
                        for (uint64_t i = block * Block; i < std::min(count, (block + 1) * Block); ++i) {
                            PrimarySampleVector u(Pcg32(), startupStream(seed_, multiplexed_ ? k : 0, begin + i),
                                                  space_.smallStep);
                            v[begin + i] = multiplexed_ ? target_.evaluateMultiplexed(k, u, c, health)
                                                        : target_.evaluateAll(u, c, health);
                        }
                        nonFiniteBlocks_ += health.nonFinite;
                    },
                    [&](uint64_t block) {
                        for (uint64_t i = block * Block; i < std::min(count, (block + 1) * Block); ++i)
                            b.add(stratum(k), v[begin + i]);
                    });
                nonFinite_ += nonFiniteBlocks_.exchange(0);
                spent_ += double(count) * cost(k);
                done += count;
                runner_.report("start-up", std::min(1.0, spent_ / budget_), 0);
            }
        }
    }

    const PrimarySpaceTarget& target_;
    const PrimarySpaceSettings& space_;
    uint64_t seed_;
    ChainRunner& runner_;
    bool multiplexed_, unbounded_;
    int first_, lengths_ = 0;
    Tail tail_;
    std::vector<double> budgetCount_;
    double budget_ = 0, spent_ = 0;
    std::vector<std::vector<double>> values_; // f* of the start-up samples of each length
    std::atomic<uint64_t> nonFiniteBlocks_{0};
    uint64_t nonFinite_ = 0;
};

// q, the distribution of a multiplexed large step's path length (file comment of primary_space_chains.h): the
// start-up's estimate of b_k / b mixed with a floor spread in proportion to 1 / k.
DiscreteDistribution lengthProposal(const NormalizationEstimate& normalization, int first, int lengths) {
    const double b = normalization.b();
    double harmonic = 0;
    for (int k = first; k <= lengths; ++k)
        harmonic += 1.0 / k;
    std::vector<double> q(static_cast<size_t>(lengths), 0.0);
    for (int k = first; k <= lengths; ++k)
        q[size_t(k - 1)] = (1 - LengthFloor) * normalization.stratumB(size_t(k)) / b + LengthFloor / (k * harmonic);
    return DiscreteDistribution(q);
}

} // namespace

ChainRunStats runPrimarySpaceChains(const Scene& scene, const PrimarySpaceSettings& space, const ChainRunSettings& run,
                                    SampleFilm& film, const RunControl& control) {
    if (run.chains < 1) throw Error("the number of chains must be at least 1");
    if (space.startupSamples == 0) throw Error("the start-up needs a budget of at least one sample");
    if (run.mutations == 0 && !(run.timeLimit > 0)) throw Error("give a number of mutations or a time limit");
    if (!(space.largeStepProbability >= 0 && space.largeStepProbability <= 1))
        throw Error("the large-step probability must be in [0, 1]");
    ChainRunner runner(run, film, control);
    const PrimarySpaceTarget target(scene, space.paths, space.unboundedEdges);
    const bool multiplexed = space.space == PrimarySpace::Multiplexed;
    ChainRunStats stats;
    stats.strategies = MutationStatistics({"large step", "small step"});

    // 1. Start-up: independent primary samples, in rounds (file comment of primary_space_chains.h).
    StartUp startUp(target, space, run.seed, runner);
    startUp.run(stats.normalization);
    const int lengths = startUp.lengths();
    if (multiplexed && space.paths.maxDepth < 0) {
        stats.lengths = lengths;
        stats.tailB = startUp.tail().b;
        stats.tailError = startUp.tail().error;
    }
    std::vector<uint64_t> first(size_t(lengths) + 2, 0); // samples of length k: [first[k], first[k + 1])
    for (int k = 1; k <= lengths; ++k)
        first[size_t(k) + 1] = first[size_t(k)] + startUp.values(k).size();
    stats.startupSamples = first[size_t(lengths) + 1];
    stats.health.nonFinite = startUp.nonFinite();
    stats.startupSeconds = runner.elapsed();
    stats.startupWork = startUp.workDone();
    stats.startupError = stats.normalization.relativeStandardError();
    if (runner.stopped()) {
        stats.interrupted = true;
        runner.finish(stats);
        return stats;
    }
    if (!(stats.normalization.b() > 0))
        throw Error("the start-up found no light reaching the camera" +
                    (space.paths.minDepth > 1
                         ? " along paths of " + std::to_string(space.paths.minDepth) +
                               " or more edges (the direct part renders the shorter ones)"
                         : std::string()) +
                    " in " + std::to_string(stats.startupSamples) +
                    " samples: nothing for the chains to start from (raise --startup-samples, or check the scene)");

    // 2. q, the large steps' path lengths (multiplexed), and the chains' first states: start-up samples in
    // proportion to the target over all lengths. A sample of length k stands for 1 / n_k of that length's
    // integral, so its resampling weight is f* / n_k (start-up bias removal over the strata); systematic
    // over the chain index.
    std::optional<DiscreteDistribution> lengthsQ;
    if (multiplexed) lengthsQ.emplace(lengthProposal(stats.normalization, startUp.first(), lengths));
    std::vector<double> weights;
    weights.reserve(stats.startupSamples);
    for (int k = 1; k <= lengths; ++k) {
        for (const double f : startUp.values(k))
            weights.push_back(f / double(startUp.values(k).size()));
        startUp.values(k) = std::vector<double>();
    }
    Pcg32 allocation = chainStream(run.seed, ~uint64_t(0));
    const std::vector<size_t> starts = systematicResample(weights, size_t(run.chains), allocation.nextDouble());
    weights = std::vector<double>(); // millions of samples with long paths (multiplexed): freed for the run
    stats.chainsPerLength.assign(multiplexed ? size_t(lengths) + 1 : 0, 0);
    stats.mutationsPerLength.assign(stats.chainsPerLength.size(), 0);
    std::vector<std::unique_ptr<MarkovChain>> chains;
    for (int c = 0; c < run.chains; ++c) {
        Pcg32 rng = chainStream(run.seed, uint64_t(c));
        const size_t index = starts[size_t(c)];
        const int k = int(std::upper_bound(first.begin() + 1, first.end(), uint64_t(index)) - first.begin()) - 1;
        chains.push_back(std::make_unique<PrimarySpaceChain>(
            target, space,
            PrimarySampleVector(rng, startupStream(run.seed, multiplexed ? k : 0, index - first[size_t(k)]),
                                space.smallStep),
            k, lengthsQ ? &*lengthsQ : nullptr));
        if (multiplexed) ++stats.chainsPerLength[size_t(k)];
    }
    runner.assignQuotas(chains);

    // 3. Rounds of mutations.
    runner.run(chains, stats);
    for (const auto& c : chains)
        static_cast<const PrimarySpaceChain&>(*c).collectLengths(stats.mutationsPerLength);
    return stats;
}

} // namespace lt
