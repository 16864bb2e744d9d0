// lt-seed: render a scene with BDPT (or a path tracer) into a sample buffer, and optionally keep
// candidate seed paths and the normalization b for the Markov chains.
#include "common/render_command.h"

int main(int argc, char** argv) {
    CLI::App app{"lt-seed: render a Mitsuba scene with bidirectional path tracing (every (s,t) strategy, light "
                 "tracing included, MIS) or unidirectional path tracing with next-event estimation. Writes a "
                 "sample buffer (develop it with lt-image) and, with --paths, candidate seed paths and the "
                 "normalization b for lt-mutate. Same seed and sample count give a bit-identical file whatever the "
                 "thread count. Ctrl-C stops early and still writes a valid file.",
                 "lt-seed"};
    lt::tool::RenderCommand render(
        app, {{"bdpt", "pt"},
              "render for this many seconds (at least one pass over the image; the last pass may cover part of it, "
              "except with --paths, whose normalization needs whole passes)",
              "taken at the end of a pass over the image",
              true});
    return lt::tool::run(app, argc, argv, [&] { return render.run(argc, argv); });
}
