// lt-mutate --stream: the chain-state stream written while the chains go on. Each round's states are handed
// to a writer thread (at most one round in flight, so memory stays at two rounds' states), so the chains do
// not wait for the encoding's CRC and the write; an error of a write is thrown at the next round or at finish().
#pragma once

#include <future>
#include <optional>
#include <vector>

#include "formats/ltfile.h"

namespace lt::tool {

class ChainStreamWriter {
public:
    ChainStreamWriter(const std::string& path, const nlohmann::json& info)
        : writer_(path, file::FileKind::Paths, info) {}

    void writeRound(const file::ChainRound& figures, std::vector<file::EncodedChainStates>&& states) {
        wait();
        pending_ = std::async(std::launch::async, [this, figures, states = std::move(states)] {
            std::vector<const file::EncodedChainStates*> parts;
            for (const auto& s : states)
                parts.push_back(&s);
            writer_.writeChainRound(figures, parts);
        });
    }

    // The last round written, `stats` after it, END!.
    void finish(const file::StatTable& stats) {
        wait();
        writer_.writeStats(stats);
        writer_.finish();
    }

private:
    void wait() {
        if (pending_.valid()) pending_.get();
    }

    file::Writer writer_;
    std::future<void> pending_;
};

} // namespace lt::tool
