// lieservo_replay — reproduce the paper's Tables 1 and 2 on a split of the real TacTip data
// (default: val/).
//
//   lieservo_replay [--data DIR] [--models DIR] [--quick N] [--plots DIR] [--results-md FILE]
//                   [--cache FILE] [--sigmas 10,1,0.1,0.01] [--seed S] [--no-cnn]
//                   [--skip-missing] [--check] [--quiet]
//
// Exit codes: 0 ok; 1 error (or --check failed); 2 bad usage; 77 data/model missing with
// --skip-missing (CTest SKIP_RETURN_CODE).
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

#include <opencv2/core.hpp>

#include "replay.hpp"

#ifndef LIESERVO_DEFAULT_DATA_DIR
#define LIESERVO_DEFAULT_DATA_DIR "../shared/data/tactip"
#endif
#ifndef LIESERVO_DEFAULT_MODELS_DIR
#define LIESERVO_DEFAULT_MODELS_DIR "examples/gdn/models"
#endif

namespace {

void usage(std::ostream& os) {
  os << "usage: lieservo_replay [--data DIR] [--split NAME] [--models DIR] [--quick N] [--plots DIR]\n"
        "                       [--results-md FILE]\n"
        "                       [--cache FILE] [--sigmas 10,1,0.1,0.01] [--seed S] [--no-cnn]\n"
        "                       [--unseen-only] [--skip-missing] [--check] [--quiet]\n"
        "  --data DIR        TacTip data (with one folder per split); default " LIESERVO_DEFAULT_DATA_DIR "\n"
        "  --split NAME      the split to replay: DIR/NAME/targets.csv and processed_images/; default val\n"
        "  --models DIR      model_card.json, gdn.onnx, cnn.onnx; default " LIESERVO_DEFAULT_MODELS_DIR "\n"
        "  --quick N         only the split's first N images\n"
        "  --unseen-only     only the images the card's network did not train on (data.trained_on and\n"
        "                    its held-out list: e.g. --models examples/gdn/models/train_val)\n"
        "  --plots DIR       write predicted-vs-actual scatter plots (SVG) here\n"
        "  --results-md FILE write the Markdown report (docs/results.md)\n"
        "  --cache FILE      cache the network outputs (keyed by model file hashes)\n"
        "  --skip-missing    exit 77 (skip) when the data or the GDN model is absent\n"
        "  --check           exit 1 unless results are finite and the filter (smallest sigma) reduces every MAE\n";
}

}  // namespace

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

  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&](const char* name) -> std::string {
      if (i + 1 >= argc) {
        std::cerr << "lieservo_replay: " << name << " needs a value\n";
        usage(std::cerr);
        std::exit(2);
      }
      return argv[++i];
    };
    try {
      if (a == "--data") opt.data_dir = value("--data");
      else if (a == "--split") opt.split = value("--split");
      else if (a == "--models") opt.models_dir = value("--models");
      else if (a == "--quick") opt.quick = std::stoi(value("--quick"));
      else if (a == "--plots") opt.plot_dir = value("--plots");
      else if (a == "--results-md") results_md = value("--results-md");
      else if (a == "--cache") opt.cache_file = value("--cache");
      else if (a == "--seed") opt.seed = std::stoull(value("--seed"));
      else if (a == "--no-cnn") opt.run_cnn = false;
      else if (a == "--unseen-only") opt.unseen_only = true;
      else if (a == "--skip-missing") skip_missing = true;
      else if (a == "--check") check = true;
      else if (a == "--quiet") opt.verbose = false;
      else if (a == "--sigmas") {
        opt.sigma_psi.clear();
        std::stringstream ss(value("--sigmas"));
        std::string tok;
        while (std::getline(ss, tok, ',')) opt.sigma_psi.push_back(std::stod(tok));
      } else if (a == "-h" || a == "--help") {
        usage(std::cout);
        return 0;
      } else {
        std::cerr << "lieservo_replay: unknown argument " << a << "\n";
        usage(std::cerr);
        return 2;
      }
    } catch (const std::exception&) {
      std::cerr << "lieservo_replay: bad value for " << a << "\n";
      return 2;
    }
  }

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
        return 1;
      }
      std::cout << "lieservo_replay: --check passed\n";
    }
  } catch (const std::exception& e) {
    std::cerr << "lieservo_replay: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
