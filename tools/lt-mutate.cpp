// lt-mutate: Markov-chain Monte Carlo rendering: path-space MLT (Veach and Guibas 1997) started from
// seed paths, Kelemen's primary-sample-space MLT and multiplexed MLT over lt's BDPT, with per-strategy
// statistics, snapshots and Ctrl-C.
#include "common/mutate_command.h"

int main(int argc, char** argv) {
    CLI::App app{"lt-mutate: render a Mitsuba scene with Markov chains. --space path (default) is Veach-Guibas "
                 "path-space MLT: chains of whole paths started from seed paths (a file from lt-seed --paths, or a "
                 "BDPT start-up of its own), mutated by --strategies. --space primary is Kelemen's primary-sample-"
                 "space MLT over BDPT (every (s,t) strategy of a sample accepted or rejected together); --space "
                 "multiplexed is Hachisuka's multiplexed MLT (one (s,t) strategy per sample, chosen by the chain; the "
                 "path length is part of the state, changed by large steps). Chains start from a start-up run that "
                 "first estimates the normalization b and picks their first states in proportion to the target "
                 "(start-up bias removal); b keeps being refined during the run (large steps, --refine-b) and the "
                 "image is scaled by it at every snapshot and at the end. Same seed and "
                 "mutation count give a bit-identical image whatever the thread count. Prints per-strategy "
                 "statistics and stores them in the output. Ctrl-C stops early and still writes a valid file.",
                 "lt-mutate"};
    lt::tool::MutateCommand mutate(app, lt::mutationKinds());
    return lt::tool::run(app, argc, argv, [&] { return mutate.run(argc, argv); });
}
