// A new mutation is its own code and one line of the registry: a toy mutation with two options of its own is
// added to lt's registry by one line below, and lt-mutate's own command (tools/common/mutate_command.h), run in
// this process, offers its options in --help, checks their values, records them in the output's parameters,
// hands them to the mutation, and reports the mutation's statistics, with nothing else of lt touched.
#include <catch2/catch.hpp>

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "common/mutate_command.h"
#include "formats/ltfile.h"
#include "mcmc/mutation_registry.h"
#include "test_util.h"

using namespace lt;

namespace {

// The toy: with probability `miss` (option --toy-miss) it fails ("missed"), otherwise it proposes the state it was
// given (Q = 1 / f* both ways, so every such proposal is accepted). Detailed balance holds for any miss rate, so
// the chains stay correct; what the option does shows in the statistics. --toy-suitable on|off says whether the
// mutation is suitable for any path.
class ToyMutation final : public Mutation {
public:
    ToyMutation(double miss, bool suitable) : miss_(miss), suitable_(suitable) {}
    [[nodiscard]] std::string name() const override { return "toy"; }
    [[nodiscard]] bool suitable(const MarkovPath&) const override { return suitable_; }
    void propose(const MarkovPath& x, Pcg32& rng, Proposal& out) const override {
        out.reset();
        if (rng.nextDouble() < miss_) {
            out.failed = RejectCause::Missed;
            return;
        }
        out.y = x;
        setTransitionDensities(out, x, 1, 1, 1);
    }

private:
    double miss_;
    bool suitable_;
};

const MutationKind ToyKind{
    "toy",
    "mutation",
    "proposes the state itself, or misses",
    {{"--toy-miss", "toy_miss", "toy: probability of a miss (default 0.5)", "FLOAT", "0.5",
      option::number([](double v) { return v >= 0 && v < 1; }, "must lie in [0, 1)")},
     {"--toy-suitable", "toy_suitable", "toy: suitable for every path (default on)", "on|off", "on", option::onOff}},
    [](const MutationContext&, const OptionValues& v) -> std::unique_ptr<Mutation> {
        return std::make_unique<ToyMutation>(v.number("toy_miss"), v.at("toy_suitable").get<bool>());
    },
    [](const SceneFeatures&) { return std::string("a toy: ask for it"); },
    {},
    {}};

// lt's registry and the toy's line.
std::vector<const MutationKind*> withToy() {
    std::vector<const MutationKind*> kinds(mutationKinds().begin(), mutationKinds().end());
    kinds.push_back(&ToyKind);
    return kinds;
}

// lt-mutate with the registry `kinds`, run in this process on `args`: its exit code and what it printed.
struct Run {
    int code = 0;
    std::string err, out;
};
Run runMutate(const std::vector<const MutationKind*>& kinds, std::vector<std::string> args) {
    args.insert(args.begin(), "lt-mutate");
    std::vector<char*> argv;
    for (auto& a : args)
        argv.push_back(a.data());
    std::ostringstream err, out;
    auto* oldErr = std::cerr.rdbuf(err.rdbuf());
    auto* oldOut = std::cout.rdbuf(out.rdbuf());
    CLI::App app{"lt-mutate", "lt-mutate"};
    tool::MutateCommand mutate(app, kinds);
    const int code =
        tool::run(app, int(argv.size()), argv.data(), [&] { return mutate.run(int(argv.size()), argv.data()); });
    std::cerr.rdbuf(oldErr);
    std::cout.rdbuf(oldOut);
    return {code, err.str(), out.str()};
}

} // namespace

TEST_CASE("a mutation with two options is its own code and one registry line", "[mcmc][registry]") {
    test::TempDir dir;
    const auto kinds = withToy();
    const std::string scene = test::shippedScene("cornell-box"), out = (dir.path / "toy.lts").string();
    const std::vector<std::string> common = {scene, "--resolution",      "8x8",  "--mutations", "40000", "--chains",
                                             "8",   "--startup-samples", "2000", "--threads",   "2",     "-o",
                                             out};

    SECTION("its options are in --help, with their help") {
        const Run r = runMutate(kinds, {"--help"});
        CHECK(r.code == 0);
        CHECK(r.out.find("--toy-miss") != std::string::npos);
        CHECK(r.out.find("toy: probability of a miss") != std::string::npos);
        CHECK(r.out.find("--toy-suitable") != std::string::npos);
        CHECK(r.out.find("toy: proposes the state itself") != std::string::npos); // --strategies lists it
    }
    SECTION("a bad value is refused in one line naming the option, before any work") {
        auto args = common;
        args.insert(args.end(), {"--strategies", "bidirectional,toy", "--toy-miss", "1.5"});
        const Run r = runMutate(kinds, args);
        CHECK(r.code != 0);
        CHECK(r.err.find("--toy-miss") != std::string::npos);
        CHECK(r.err.find("must lie in [0, 1)") != std::string::npos);
        CHECK(!std::filesystem::exists(out));
    }
    SECTION("its options reach the mutation and the output's parameters, its row the statistics") {
        // Broken on purpose: with the option not handed to the mutation (make() reading the default 0.5), the
        // miss fraction came out 0.50 and the check below (0.2 within its binomial bound) failed.
        auto args = common;
        args.insert(args.end(), {"--strategies", "bidirectional,toy:3", "--toy-miss", "0.2", "--quiet"});
        const Run r = runMutate(kinds, args);
        REQUIRE(r.code == 0);
        file::Content content = file::readAll(out, file::FileKind::Buffer);
        const auto& params = content.info["parameters"];
        CHECK(params["toy_miss"] == 0.2);
        CHECK(params["toy_suitable"] == true);
        CHECK(params["strategies"][1]["name"] == "toy");
        CHECK(params["strategies"][1]["weight"] == 3.0);
        const file::StatTable* strategies = nullptr;
        for (const auto& t : content.stats)
            if (t.name == "strategies") strategies = &t;
        REQUIRE(strategies);
        REQUIRE(strategies->rows.size() == 2);
        CHECK(strategies->rows[1] == "toy");
        const auto column = [&](const std::string& name) {
            return size_t(std::find(strategies->columns.begin(), strategies->columns.end(), name) -
                          strategies->columns.begin());
        };
        const double proposed = strategies->values[1][column("proposed")];
        const double missed = strategies->values[1][column("missed")];
        // Three quarters of the 40000 proposals (weight 3 : 1), each missed with probability 0.2: the fraction's
        // standard deviation is sqrt(0.2 0.8 / 30000) = 0.0023; 5 of them bound it.
        CHECK(proposed > 25000);
        CHECK(std::abs(missed / proposed - 0.2) < 5 * std::sqrt(0.2 * 0.8 / proposed));
        // Everything that did not miss was the state itself: accepted.
        CHECK(strategies->values[1][column("accepted")] == proposed - missed);
    }
    SECTION("its other option reaches it too: a toy suitable for no path is never chosen") {
        auto args = common;
        args.insert(args.end(), {"--strategies", "bidirectional,toy", "--toy-suitable", "off", "--quiet"});
        REQUIRE(runMutate(kinds, args).code == 0);
        file::Content content = file::readAll(out, file::FileKind::Buffer);
        CHECK(content.info["parameters"]["toy_suitable"] == false);
        for (const auto& t : content.stats)
            if (t.name == "strategies") CHECK(t.values[1][0] == 0); // proposed
    }
    SECTION("lt's own registry does not know it") {
        auto args = common;
        args.insert(args.end(), {"--strategies", "bidirectional,toy"});
        const Run r = runMutate({mutationKinds().begin(), mutationKinds().end()}, args);
        CHECK(r.code != 0);
        CHECK(r.err.find("unknown mutation 'toy'") != std::string::npos);
    }
}
