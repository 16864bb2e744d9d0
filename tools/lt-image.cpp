// lt-image: develop the final buffer of a render (or several, merged by their stored weights) into a
// linear EXR and an sRGB PNG preview.
#include <algorithm>
#include <iostream>
#include <vector>

#include "common/info.h"
#include "common/tool.h"
#include "image/buffer_merge.h"
#include "image/buffer_source.h"
#include "image/image_io.h"

int main(int argc, char** argv) {
    CLI::App app{"lt-image: develop a sample buffer into a linear EXR (every plane as a channel, the file's INFO "
                 "as metadata) and an sRGB PNG preview. Several inputs (e.g. runs with different seeds, chains, "
                 "machines) are merged by their stored weights; EXR inputs count with weight 1.",
                 "lt-image"};
    std::vector<std::string> inputs;
    std::string exrOut, pngOut;
    double exposure = 0;
    app.add_option("IN", inputs, "buffer files (.lts, - for stdin) or EXR images")->required();
    app.add_option("-o,--output", exrOut, "linear float EXR to write");
    app.add_option("--png", pngOut, "8-bit sRGB preview to write");
    app.add_option("--exposure", exposure, "scale the PNG preview by 2^EV (default 0; the EXR is never scaled)");
    return lt::tool::run(app, argc, argv, [&] {
        if (exrOut.empty() && pngOut.empty()) throw lt::Error("nothing to write: give -o OUT.exr and/or --png OUT.png");
        std::vector<lt::file::Buffer> buffers;
        std::vector<std::string> names;
        nlohmann::json sources = nlohmann::json::array();
        nlohmann::json info;
        for (const auto& in : inputs) {
            lt::BufferSource s = lt::loadBuffer(in);
            sources.push_back({{"file", s.name}, {"origin", s.origin}, {"weight", s.buffer.weight}, {"info", s.info}});
            info = s.info;
            buffers.push_back(std::move(s.buffer));
            names.push_back(std::move(s.name));
        }
        const lt::file::Buffer merged = lt::mergeBuffers(buffers, names);
        // One input: its INFO goes into the EXR as is (the renderer's metadata carried over). Several: a
        // new INFO saying what was merged, keeping every input's INFO.
        if (inputs.size() > 1) {
            info = lt::tool::makeInfo("lt-image", argc, argv, {{"exposure", exposure}}, nullptr);
            info["sources"] = sources;
            info["weight"] = merged.weight;
            if (std::all_of(sources.begin(), sources.end(), [&](const auto& s) {
                    return s["info"].contains("scene") && s["info"]["scene"] == sources[0]["info"]["scene"];
                }))
                info["scene"] = sources[0]["info"]["scene"];
        }
        if (!info.is_object()) info = nlohmann::json::object(); // an EXR input has no INFO
        if (!exrOut.empty()) lt::writeExr(exrOut, merged, info);
        if (!pngOut.empty()) lt::writePng(pngOut, merged, exposure);

        std::string wrote = exrOut.empty() ? pngOut : exrOut + (pngOut.empty() ? "" : " and " + pngOut);
        std::cerr << "lt-image: wrote " << wrote << ": " << merged.width << "x" << merged.height << ", "
                  << merged.channels.size() << " channels";
        if (inputs.size() > 1) std::cerr << ", merged " << inputs.size() << " files (" << merged.combine << ")";
        std::cerr << ", weight " << merged.weight << '\n';
        return 0;
    });
}
