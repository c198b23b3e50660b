// examples/replay/demo_hook.cpp — the real-data replay as a step of the main job.
//
// lieservo_demo (examples/sim) calls lieservoDemoReplay() after the four simulated tasks
// when this file is linked in (see examples/sim/CMakeLists.txt). The network outputs are
// cached in the results folder, so a second run of the demo replays in about a second.
#include <cstdio>
#include <exception>
#include <string>
#include <sys/stat.h>

#include "replay.hpp"

bool lieservoDemoReplay(const std::string& out_dir) {
  namespace rp = lieservo::replay;
  rp::ReplayOptions opt;
  opt.data_dir = LIESERVO_DEFAULT_DATA_DIR;
  opt.models_dir = LIESERVO_DEFAULT_MODELS_DIR;
  struct stat st {};
  if (stat((opt.data_dir + "/" + opt.split + "/targets.csv").c_str(), &st) != 0) {
    std::printf("[replay] skipped: no real TacTip data at %s (configure with -DLIESERVO_DATA_DIR=...)\n",
                opt.data_dir.c_str());
    return true;  // the data set is optional; nothing failed
  }
  opt.cache_file = out_dir + "/replay_network_outputs.txt";
  opt.plot_dir = out_dir + "/replay";
  opt.verbose = false;
  try {
    const rp::ReplayResults r = rp::runReplay(opt);
    std::printf("%s", r.table().c_str());
    for (const rp::FilterRow& row : r.filter) {
      if (row.failures != 0) return false;
    }
    return r.have_gdn;
  } catch (const std::exception& e) {
    std::printf("[replay] failed: %s\n", e.what());
    return false;
  }
}
