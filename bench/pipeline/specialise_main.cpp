// Stand-alone entry point for the specialisation benchmark; `tessera-bench specialise`
// runs the same code.
#include <CLI/CLI.hpp>

#include "specialise.hpp"

int main(int argc, char** argv) {
  CLI::App app{"Specialised pipeline vs all-features pipeline vs virtual dispatch"};
  tessera::bench::SpecialiseOptions options;
  app.add_option("--width", options.width, "image width")->check(CLI::Range(8u, 4096u));
  app.add_option("--height", options.height, "image height")->check(CLI::Range(8u, 4096u));
  app.add_option("--spp", options.spp, "samples per pixel")->check(CLI::Range(1u, 4096u));
  app.add_option("--repeats", options.repeats, "timed runs per renderer; the best counts")
      ->check(CLI::Range(1, 100));
  app.add_option("--only", options.only_renderer,
                 "render once with just this renderer (for profilers)")
      ->check(CLI::IsMember({"specialised", "all", "virtual"}));
  app.add_option("--scene", options.only_scene,
                 "with --only: the scene (triangles, analytic, mixed, triangles_sky)");
  app.add_option("--sampler", options.sampler, "render.sampler of every scene")
      ->check(CLI::IsMember({"sobol", "independent"}));
  app.add_flag("!--no-light-tree", options.light_tree,
               "pick lights by power alone instead of by the light tree");
  CLI11_PARSE(app, argc, argv);
  return tessera::bench::run_specialise(options);
}
