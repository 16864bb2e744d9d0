// lt-gradient: gradient-domain rendering of a scene: the primal image and its forward-difference gradients
// from shifted paths (G-PT, or gradient-domain path reusing), for lt-reconstruct to turn into the image; with
// --from-paths, the gradient stage of gradient-domain MLT.
#include "common/render_command.h"
#include "common/stream_gradient_command.h"

int main(int argc, char** argv) {
    CLI::App app{"lt-gradient: render a Mitsuba scene in the gradient domain. Base paths are traced as by a path "
                 "tracer with next-event estimation and shifted to other pixels (reconnection at the first pair of "
                 "rough vertices, half-vector copy through smooth ones). --method gpt shifts every path to its four "
                 "neighbours (gradient-domain path tracing); --method gdpr reuses every path in all pixels of its "
                 "tile (gradient-domain path reusing). Writes the planes primal, dx, dy and direct as lt-reconstruct "
                 "reads them, and per pixel the variance of one pass's value of each (NAME.var, luminance): "
                 "lt-gradient S -o - | "
                 "lt-reconstruct - -o image.exr. With --from-paths it is the gradient stage of gradient-domain MLT "
                 "instead: the states of lt-mutate's chains (lt-mutate S --stream -) are shifted to their four "
                 "neighbours and weighed as draws of the chains' density. Same seed and sample count give a "
                 "bit-identical file whatever the thread count; Ctrl-C stops after the current tiles (or round) and "
                 "still writes a valid file.",
                 "lt-gradient"};
    lt::tool::RenderCommand render(
        app, {{"gdpr", "gpt"},
              "render for this many seconds (at least one pass over the image; gpt ends at the end of a pass, gdpr "
              "after the tile under way)",
              "each holds primal, dx, dy and direct, which lt-reconstruct reconstructs and lt-error then measures"});
    lt::tool::StreamGradientCommand fromPaths(app);
    return lt::tool::run(app, argc, argv, [&] {
        return fromPaths.given() ? fromPaths.run(render.options(), render.estimatorValues(), argc, argv)
                                 : render.run(argc, argv);
    });
}
