// lieservo_collect — collect (or resume) a pose-and-shear training set (paper Algorithm 1 (alg:data_collection)).
//
//   lieservo_collect --out DIR [--samples N] [--seed S] [--stop-after K] [--sort-by-depth]
//                    [--r-max MM] [--z-min MM] [--z-max MM] [--phi-max DEG]
//                    [--gamma-min DEG] [--gamma-max DEG] [--start-height MM]
//                    [--image-size W H] [--source synthetic] [--quiet]   (--help: all of them)
//
// Running the same command again after an interruption (Ctrl-C, crash, --stop-after) resumes
// at the next sample. This build drives the kinematic stand-in arm and the synthetic image
// source; the real set-up swaps in the Franka adapter (examples/franka) and a camera
// ImageSource (examples/adapters) at the two marked places below. --out is a folder this
// program made (or a new or empty one): a user's folder is refused with exit 2, untouched.
#include "collector.hpp"
#include "kinematic_arm.hpp"

#include <lieservo_cli/cli.hpp>

#include <csignal>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace {

volatile std::sig_atomic_t g_stop = 0;
extern "C" void onSignal(int) { g_stop = 1; }

namespace cli = lieservo::cli;

// The command line: the plan's options, the synthetic source's and the test hooks.
struct Options {
  lieservo::collection::CollectionConfig cfg;
  std::vector<int> image_size{128, 128};
  std::string source = "synthetic";
  bool quiet = false;
};

void addOptions(CLI::App& app, Options& o) {
  app.add_option("--out", o.cfg.out_dir, "the data set's folder (new, empty, or one it made)")->required()->check(cli::nonEmptyPath());
  app.add_option("--samples", o.cfg.n_samples, "number of samples in the plan")
      ->capture_default_str()
      ->check(cli::integerIn<std::size_t>(1, 100000000));
  app.add_option("--seed", o.cfg.seed, "seed of the sampling plan")
      ->capture_default_str()
      ->check(cli::integerIn<std::uint64_t>(0, std::numeric_limits<std::uint64_t>::max()));
  app.add_option("--stop-after", o.cfg.stop_after, "stop after K new samples in this run (resume later)")
      ->check(cli::integerIn<std::size_t>(0, std::numeric_limits<std::size_t>::max()));
  app.add_flag("--sort-by-depth", o.cfg.sort_by_depth, "order the plan by increasing depth z");
  const double big = 1e6;
  app.add_option("--r-max", o.cfg.ranges.r_max_mm, "shear disk radius (mm)")->capture_default_str()->check(cli::finiteIn(0, big));
  app.add_option("--z-min", o.cfg.ranges.z_min_mm, "least depth (mm)")->capture_default_str()->check(cli::finiteIn(-big, big));
  app.add_option("--z-max", o.cfg.ranges.z_max_mm, "greatest depth (mm)")->capture_default_str()->check(cli::finiteIn(-big, big));
  app.add_option("--phi-max", o.cfg.ranges.phi_max_deg, "contact-angle cap half-angle (deg)")
      ->capture_default_str()
      ->check(cli::finiteIn(0, 90));
  app.add_option("--gamma-min", o.cfg.ranges.gamma_min_deg, "least rotational shear (deg)")
      ->capture_default_str()
      ->check(cli::finiteIn(-big, big));
  app.add_option("--gamma-max", o.cfg.ranges.gamma_max_deg, "greatest rotational shear (deg)")
      ->capture_default_str()
      ->check(cli::finiteIn(-big, big));
  app.add_option("--start-height", o.cfg.start_height_mm, "start point above the surface (mm)")
      ->capture_default_str()
      ->check(cli::finiteIn(-big, big));
  app.add_option("--image-size", o.image_size, "synthetic image size W H")
      ->expected(2)
      ->capture_default_str()
      ->check(cli::integerIn(1, 4096));
  app.add_option("--source", o.source, "image source")->capture_default_str()->check(CLI::IsMember({"synthetic"}));
  app.add_flag("--quiet", o.quiet, "no progress lines");
  // Test hooks (tests/collection): terminate while writing sample N, at point P.
  app.add_option("--crash-at", o.cfg.crash_at)->group("")->check(cli::integerIn<std::size_t>(0, 100000000));
  app.add_option("--crash-point", o.cfg.crash_point)->group("")->check(cli::integerIn(0, 1));
}

}  // namespace

static int run(int argc, char** argv) {
  using namespace lieservo::collection;
  Options o;
  CollectionConfig& cfg = o.cfg;
  CLI::App app("lieservo_collect: collect (or resume) a pose-and-shear training set (the paper's Algorithm 1).\n"
               "Running the same command again after an interruption resumes at the next sample. Exit status:\n"
               "0 done; 2 bad usage or set-up: a malformed or out-of-range option, an output folder that cannot be\n"
               "written, or a data set that does not match this command (other parameters, a missing image).",
               "lieservo_collect");
  addOptions(app, o);
  if (const int status = cli::parse(app, argc, argv); status >= 0) return status;
  if (cfg.ranges.z_min_mm > cfg.ranges.z_max_mm || cfg.ranges.gamma_min_deg > cfg.ranges.gamma_max_deg) {
    std::cerr << "lieservo_collect: " << (cfg.ranges.z_min_mm > cfg.ranges.z_max_mm ? "--z-min exceeds --z-max"
                                                                                   : "--gamma-min exceeds --gamma-max")
              << "\n(lieservo_collect --help lists the options)\n";
    return cli::kUsageOrSetup;
  }
  if (o.quiet) cfg.progress = false;
  const int width = o.image_size[0], height = o.image_size[1];

  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);
  cfg.stop_requested = &g_stop;

  // A data set's folder: one this program made (its collect_params.json, or the marker of a
  // lieservo program), a new or an empty one. Anything else is a user's folder: refused.
  if (std::string why; !cli::claimOutputFolder("--out", cfg.out_dir, "lieservo_collect", why, "collect_params.json")) {
    std::cerr << "lieservo_collect: " << why << "\n";
    return cli::kUsageOrSetup;
  }
  try {
    // (1) The robot: the kinematic stand-in. A real run constructs the Franka adapter here.
    const auto X_wf = lieservo::SE3<double>::fromEulerXYZ6Degrees(cfg.work_frame);
    KinematicArm arm(X_wf);
    // (2) The image source. A camera ImageSource (examples/adapters) plugs in here.
    std::unique_ptr<ImageSource> camera;
    camera = std::make_unique<SyntheticTactileSource>(arm, X_wf, width, height);  // --source synthetic
    const CollectionResult r = runCollection(cfg, arm, *camera);
    std::cerr << "[lieservo_collect] " << cfg.out_dir << ": " << r.rows_after << "/" << cfg.n_samples << " samples ("
              << r.written << " written now, " << r.rows_before << " found)"
              << (r.complete ? ", complete" : ", incomplete: run the same command again to resume") << "\n";
    return cli::kOk;
  } catch (const std::exception& e) {
    std::cerr << "lieservo_collect: " << e.what() << "\n";
    return cli::kUsageOrSetup;
  }
}

int main(int argc, char** argv) {
  return lieservo::cli::runProgram("lieservo_collect", [&] { return run(argc, argv); });
}
