// lieservo_collect — collect (or resume) a pose-and-shear training set (paper Algorithm 1 (alg:data_collection)).
//
//   lieservo_collect --out DIR [--samples N] [--seed S] [--stop-after K] [--sort-by-depth]
//                    [--r-max MM] [--z-min MM] [--z-max MM] [--phi-max DEG]
//                    [--gamma-min DEG] [--gamma-max DEG] [--start-height MM]
//                    [--image-size W H] [--source synthetic] [--quiet]
//
// Running the same command again after an interruption (Ctrl-C, crash, --stop-after) resumes
// at the next sample. This build drives the kinematic stand-in arm and the synthetic image
// source; the real set-up swaps in the Franka adapter (examples/franka) and a camera
// ImageSource (examples/adapters) at the two marked places below.
#include "collector.hpp"
#include "kinematic_arm.hpp"

#include <csignal>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <memory>
#include <string>

namespace {

volatile std::sig_atomic_t g_stop = 0;
extern "C" void onSignal(int) { g_stop = 1; }

void usage(std::ostream& os) {
  os << "usage: lieservo_collect --out DIR [options]\n"
        "  --samples N          number of samples in the plan (default 20)\n"
        "  --seed S             seed of the sampling plan (default 1)\n"
        "  --stop-after K       stop after K new samples in this run (resume later)\n"
        "  --sort-by-depth      order the plan by increasing depth z\n"
        "  --r-max MM           shear disk radius (default 5)\n"
        "  --z-min MM --z-max MM  depth range (default 0.5 6)\n"
        "  --phi-max DEG        contact-angle cap half-angle (default 25)\n"
        "  --gamma-min DEG --gamma-max DEG  rotational shear range (default -5 5)\n"
        "  --start-height MM    start point above the surface (default 10)\n"
        "  --image-size W H     synthetic image size (default 128 128)\n"
        "  --source NAME        image source: synthetic (default)\n"
        "  --quiet              no progress lines\n";
}

}  // namespace

int main(int argc, char** argv) {
  using namespace lieservo::collection;
  CollectionConfig cfg;
  int width = 128, height = 128;
  std::string source = "synthetic";
  try {
    for (int a = 1; a < argc; ++a) {
      const std::string k = argv[a];
      auto next = [&]() -> std::string {
        if (a + 1 >= argc) throw DatasetError("missing value after " + k);
        return argv[++a];
      };
      auto num = [&]() -> double {
        const std::string v = next();
        char* end = nullptr;
        const double x = std::strtod(v.c_str(), &end);
        if (end == v.c_str() || *end != '\0' || !std::isfinite(x)) throw DatasetError("bad number '" + v + "' after " + k);
        return x;
      };
      auto count = [&]() -> unsigned long long {
        const std::string v = next();
        char* end = nullptr;
        const unsigned long long x = std::strtoull(v.c_str(), &end, 10);
        if (end == v.c_str() || *end != '\0' || v[0] == '-') throw DatasetError("bad count '" + v + "' after " + k);
        return x;
      };
      if (k == "--out") cfg.out_dir = next();
      else if (k == "--samples") cfg.n_samples = count();
      else if (k == "--seed") cfg.seed = count();
      else if (k == "--stop-after") cfg.stop_after = count();
      else if (k == "--sort-by-depth") cfg.sort_by_depth = true;
      else if (k == "--r-max") cfg.ranges.r_max_mm = num();
      else if (k == "--z-min") cfg.ranges.z_min_mm = num();
      else if (k == "--z-max") cfg.ranges.z_max_mm = num();
      else if (k == "--phi-max") cfg.ranges.phi_max_deg = num();
      else if (k == "--gamma-min") cfg.ranges.gamma_min_deg = num();
      else if (k == "--gamma-max") cfg.ranges.gamma_max_deg = num();
      else if (k == "--start-height") cfg.start_height_mm = num();
      else if (k == "--image-size") {
        width = static_cast<int>(count());
        height = static_cast<int>(count());
      } else if (k == "--source") source = next();
      else if (k == "--quiet") cfg.progress = false;
      else if (k == "--crash-at") cfg.crash_at = count();            // test hook (hidden)
      else if (k == "--crash-point") cfg.crash_point = static_cast<int>(count());
      else if (k == "--help" || k == "-h") {
        usage(std::cout);
        return 0;
      } else {
        throw DatasetError("unknown option '" + k + "'");
      }
    }
    if (cfg.out_dir.empty()) throw DatasetError("--out DIR is required");
    if (width <= 0 || height <= 0 || width > 4096 || height > 4096) throw DatasetError("--image-size must be in 1..4096");
  } catch (const DatasetError& e) {
    std::cerr << "lieservo_collect: " << e.what() << "\n";
    usage(std::cerr);
    return 2;
  }

  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);
  cfg.stop_requested = &g_stop;

  try {
    // (1) The robot: the kinematic stand-in. A real run constructs the Franka adapter here.
    const auto X_wf = lieservo::SE3<double>::fromEulerXYZ6Degrees(cfg.work_frame);
    KinematicArm arm(X_wf);
    // (2) The image source. A camera ImageSource (examples/adapters) plugs in here.
    std::unique_ptr<ImageSource> camera;
    if (source == "synthetic") {
      camera = std::make_unique<SyntheticTactileSource>(arm, X_wf, width, height);
    } else {
      std::cerr << "lieservo_collect: unknown --source '" << source << "' (this build has: synthetic)\n";
      return 2;
    }
    const CollectionResult r = runCollection(cfg, arm, *camera);
    std::cerr << "[lieservo_collect] " << cfg.out_dir << ": " << r.rows_after << "/" << cfg.n_samples << " samples ("
              << r.written << " written now, " << r.rows_before << " found)"
              << (r.complete ? ", complete" : ", incomplete: run the same command again to resume") << "\n";
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "lieservo_collect: " << e.what() << "\n";
    return 1;
  }
}
