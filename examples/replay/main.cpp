// lieservo_replay — reproduce the paper's Tables 1 and 2 on a split of the real TacTip data
// (default: val/).
//
//   lieservo_replay [--data DIR] [--models DIR] [--quick N] [--plots DIR] [--results-md FILE]
//                   [--cache FILE] [--sigmas 10,1,0.1,0.01] [--seed S] [--no-cnn]
//                   [--skip-missing] [--check] [--quiet]
//
// Exit codes (lieservo_cli/program.hpp): 0 ok; 1 --check failed; 2 bad usage or set-up (a
// malformed option, missing or unreadable data or model, a filter that fails at every step, an
// output that is not the replay's: --cache, --results-md or --plots naming a user's file or
// folder); 77 data/model missing with --skip-missing (CTest SKIP_RETURN_CODE).
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
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

namespace {

namespace cli = lieservo::cli;
namespace replay = lieservo::replay;

struct Settings {
  replay::ReplayOptions opt;
  std::string results_md, command;
  bool skip_missing = false, check = false;
};

// Parses the options: -1 to go on, else the exit status.
int parseOptions(int argc, char** argv, Settings& s) {
  replay::ReplayOptions& opt = s.opt;
  opt.data_dir = LIESERVO_DEFAULT_DATA_DIR;
  opt.models_dir = LIESERVO_DEFAULT_MODELS_DIR;
  // The report names paths relative to the repository root (no machine paths in the docs).
  opt.display_root = LIESERVO_SOURCE_ROOT;
  std::ostringstream command;
  command << replay::displayPath(argv[0], opt.display_root, true);
  for (int i = 1; i < argc; ++i) command << ' ' << argv[i];
  s.command = command.str();
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
  app.add_option("--plots", opt.plot_dir, "write predicted-vs-actual scatter plots (SVG) in this folder (new, empty, "
                                          "or one a lieservo program made)")
      ->check(cli::nonEmptyPath());
  app.add_option("--results-md", s.results_md,
                 "write the Markdown report (docs/results.md; an existing file only if it is such a report)")
      ->check(cli::nonEmptyPath());
  app.add_option("--cache", opt.cache_file,
                 "cache the network outputs (keyed by the model files' SHA-256; an existing file only if it is "
                 "such a cache)")
      ->check(cli::nonEmptyPath());
  app.add_option("--sigmas", opt.sigma_psi, "Table 2's process noise levels sigma_psi (mm and deg), comma-separated")
      ->delimiter(',')
      ->capture_default_str()
      ->check(cli::finiteIn(1e-6, 100));
  app.add_option("--seed", opt.seed, "seed of the process noise")->capture_default_str()->check(
      cli::integerIn<std::uint64_t>(0, std::numeric_limits<std::uint64_t>::max()));
  bool no_cnn = false, quiet = false;
  app.add_flag("--no-cnn", no_cnn, "do not run the CNN baseline");
  app.add_flag("--skip-missing", s.skip_missing, "exit 77 (skip) when the data or the GDN model is absent");
  app.add_flag("--check", s.check, "exit 1 unless results are finite and the filter (smallest sigma) reduces every MAE");
  app.add_flag("--quiet", quiet, "no progress output");
  if (const int status = cli::parse(app, argc, argv); status >= 0) return status;
  if (no_cnn) opt.run_cnn = false;
  if (quiet) opt.verbose = false;
  return -1;
}

// Before any work: the outputs named are the replay's to write (-1), else the exit status.
int checkOutputs(const Settings& s) {
  std::string why;
  if (!s.results_md.empty() && !cli::mayOverwrite("--results-md", s.results_md, replay::kResultsHeading, why)) {
    std::cerr << "lieservo_replay: " << why << "\n";
    return cli::kUsageOrSetup;
  }
  if (!s.opt.plot_dir.empty() && !cli::claimOutputFolder("--plots", s.opt.plot_dir, "lieservo_replay", why, "table1_gdn.svg")) {
    std::cerr << "lieservo_replay: " << why << "\n";
    return cli::kUsageOrSetup;
  }
  return -1;
}

// --check: the results are finite, no filter step failed, and the smallest σψ lowers every MAE.
bool passesCheck(const replay::ReplayResults& r) {
  bool ok = r.have_gdn && !r.filter.empty();
  for (std::size_t j = 0; j < 6 && ok; ++j) {
    ok = std::isfinite(r.gdn_mae[j]) && r.gdn_mae[j] > 0.0;
    for (const auto& row : r.filter) ok = ok && std::isfinite(row.mae[j]) && row.failures == 0;
    const replay::FilterRow* best = &r.filter.front();
    for (const auto& row : r.filter)
      if (row.sigma_psi < best->sigma_psi) best = &row;
    ok = ok && best->mae[j] < r.gdn_mae[j];
  }
  return ok;
}

int run(int argc, char** argv) {
  Settings s;
  if (const int status = parseOptions(argc, argv, s); status >= 0) return status;
  if (s.skip_missing) {
    const std::string targets = s.opt.data_dir + "/" + s.opt.split + "/targets.csv";
    for (const std::string& p : {targets, s.opt.models_dir + "/model_card.json", s.opt.models_dir + "/gdn.onnx"})
      if (!std::filesystem::exists(p)) {
        std::cout << "lieservo_replay: SKIPPED: " << p << " not found (data or GDN model not available yet)\n";
        return cli::kSkipped;
      }
  }
  if (const int status = checkOutputs(s); status >= 0) return status;
  const replay::ReplayResults r = replay::runReplay(s.opt);
  std::cout << r.table();
  if (!s.results_md.empty()) {
    const std::filesystem::path p(s.results_md);
    if (p.has_parent_path()) std::filesystem::create_directories(p.parent_path());
    if (std::string why; !cli::writeFileAtomically(s.results_md, r.markdown(s.opt, s.command), why))
      throw std::runtime_error(why);
    std::cout << "wrote " << s.results_md << "\n";
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
  if (s.check) {
    if (!passesCheck(r)) {
      std::cerr << "lieservo_replay: --check FAILED\n";
      return cli::kCriteriaMissed;
    }
    std::cout << "lieservo_replay: --check passed\n";
  }
  return cli::kOk;
}

}  // namespace

int main(int argc, char** argv) {
  return cli::runProgram("lieservo_replay", [&] { return run(argc, argv); });
}
