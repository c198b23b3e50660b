// lieservo_replay — reproduce the paper's Tables 1 and 2 on a split of the real TacTip data
// (default: val/).
//
//   lieservo_replay [--data DIR] [--models DIR] [--quick N] [--plots DIR] [--results-md FILE]
//                   [--cache FILE] [--sigmas 10,1,0.1,0.01] [--seed S] [--no-cnn]
//                   [--skip-missing] [--check] [--quiet]
//
// Exit codes: 0 ok; 1 --check failed; 2 bad usage or set-up (a malformed option, missing or
// unreadable data or model, a filter that fails at every step); 77 data/model missing with
// --skip-missing (CTest SKIP_RETURN_CODE).
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <new>
#include <sstream>
#include <string>

#include <opencv2/core.hpp>

#include <lieservo_cli/cli.hpp>

#include "replay.hpp"

#ifndef LIESERVO_DEFAULT_DATA_DIR
#define LIESERVO_DEFAULT_DATA_DIR "../shared/data/tactip"
#endif
#ifndef LIESERVO_DEFAULT_MODELS_DIR
#define LIESERVO_DEFAULT_MODELS_DIR "examples/gdn/models"
#endif

int main(int argc, char** argv) {
  lieservo::replay::ReplayOptions opt;
  opt.data_dir = LIESERVO_DEFAULT_DATA_DIR;
  opt.models_dir = LIESERVO_DEFAULT_MODELS_DIR;
  std::string results_md;
  bool skip_missing = false, check = false;
  // The report names paths relative to the repository root (no machine paths in the docs).
  opt.display_root = LIESERVO_SOURCE_ROOT;
  std::ostringstream command;
  command << lieservo::replay::displayPath(argv[0], opt.display_root, true);
  for (int i = 1; i < argc; ++i) command << ' ' << argv[i];

  namespace cli = lieservo::cli;
  CLI::App app("lieservo_replay: the paper's Tables 1 and 2 on a split of the real TacTip data. Exit status: 0 ok,\n"
               "1 --check failed, 2 bad usage or set-up, 77 data or model missing with --skip-missing.",
               "lieservo_replay");
  app.add_option("--data", opt.data_dir, "TacTip data (one folder per split)")->capture_default_str();
  app.add_option("--split", opt.split, "the split to replay: DATA/SPLIT/targets.csv and processed_images/")
      ->capture_default_str();
  app.add_option("--models", opt.models_dir, "model_card.json, gdn.onnx, cnn.onnx")->capture_default_str();
  app.add_option("--quick", opt.quick, "only the split's first N images")->check(cli::integerIn(1, 1000000));
  app.add_flag("--unseen-only", opt.unseen_only,
               "only the images the card's network did not train on (data.trained_on and its held-out list: "
               "e.g. --models examples/gdn/models/train_val)");
  app.add_option("--plots", opt.plot_dir, "write predicted-vs-actual scatter plots (SVG) here");
  app.add_option("--results-md", results_md, "write the Markdown report (docs/results.md)");
  app.add_option("--cache", opt.cache_file, "cache the network outputs (keyed by model file hashes)");
  app.add_option("--sigmas", opt.sigma_psi, "Table 2's process noise levels sigma_psi (mm and deg), comma-separated")
      ->delimiter(',')
      ->capture_default_str()
      ->check(cli::finiteIn(1e-6, 100));
  app.add_option("--seed", opt.seed, "seed of the process noise")->capture_default_str()->check(
      cli::integerIn<std::uint64_t>(0, std::numeric_limits<std::uint64_t>::max()));
  bool no_cnn = false, quiet = false;
  app.add_flag("--no-cnn", no_cnn, "do not run the CNN baseline");
  app.add_flag("--skip-missing", skip_missing, "exit 77 (skip) when the data or the GDN model is absent");
  app.add_flag("--check", check, "exit 1 unless results are finite and the filter (smallest sigma) reduces every MAE");
  app.add_flag("--quiet", quiet, "no progress output");
  if (const int status = cli::parse(app, argc, argv); status >= 0) return status;
  if (no_cnn) opt.run_cnn = false;
  if (quiet) opt.verbose = false;

  namespace fs = std::filesystem;
  if (skip_missing) {
    const std::string targets = opt.data_dir + "/" + opt.split + "/targets.csv";
    const std::string card = opt.models_dir + "/model_card.json", gdn = opt.models_dir + "/gdn.onnx";
    for (const std::string& p : {targets, card, gdn}) {
      if (!fs::exists(p)) {
        std::cout << "lieservo_replay: SKIPPED: " << p << " not found (data or GDN model not available yet)\n";
        return 77;
      }
    }
  }

  try {
    const lieservo::replay::ReplayResults r = lieservo::replay::runReplay(opt);
    std::cout << r.table();
    if (!results_md.empty()) {
      const fs::path p(results_md);
      if (p.has_parent_path()) fs::create_directories(p.parent_path());
      std::ofstream out(results_md);
      out << r.markdown(opt, command.str());
      if (!out) throw std::runtime_error(results_md + ": cannot write");
      std::cout << "wrote " << results_md << "\n";
    }
    for (const auto& p : r.plots) std::cout << "wrote " << p << "\n";
    // A noise level at which the filter failed at every step has no Table 2 row to show.
    for (const auto& row : r.filter) {
      if (row.failures >= r.n && r.n > 0) {
        std::cerr << "lieservo_replay: the filter failed at every step with sigma_psi = " << row.sigma_psi << "\n";
        return cli::kUsageOrSetup;
      }
      if (row.failures > 0)
        std::cerr << "lieservo_replay: warning: the filter failed at " << row.failures << " of " << r.n
                  << " steps with sigma_psi = " << row.sigma_psi << " (re-initialised each time)\n";
    }
    if (check) {
      bool ok = r.have_gdn && !r.filter.empty();
      for (std::size_t j = 0; j < 6 && ok; ++j) {
        ok = std::isfinite(r.gdn_mae[j]) && r.gdn_mae[j] > 0.0;
        for (const auto& row : r.filter) ok = ok && std::isfinite(row.mae[j]) && row.failures == 0;
        // The smallest σψ must reduce the error of every component.
        double smallest = r.filter.front().sigma_psi;
        const lieservo::replay::FilterRow* best = &r.filter.front();
        for (const auto& row : r.filter)
          if (row.sigma_psi < smallest) {
            smallest = row.sigma_psi;
            best = &row;
          }
        ok = ok && best->mae[j] < r.gdn_mae[j];
      }
      if (!ok) {
        std::cerr << "lieservo_replay: --check FAILED\n";
        return cli::kCriteriaMissed;
      }
      std::cout << "lieservo_replay: --check passed\n";
    }
  } catch (const std::bad_alloc&) {
    std::cerr << "lieservo_replay: out of memory\n";
    return cli::kUsageOrSetup;
  } catch (const std::exception& e) {
    std::cerr << "lieservo_replay: error: " << e.what() << "\n";
    return cli::kUsageOrSetup;
  }
  return cli::kOk;
}
