// examples/replay/demo_hook.cpp — the real-data replay as a step of the main job.
//
// lieservo_demo (examples/sim) calls lieservoDemoReplay() after the four simulated tasks
// when this file is linked in (see examples/sim/CMakeLists.txt). The network outputs are
// cached in the results folder, so a second run of the demo replays in about a second; with
// --no-files (no results folder) nothing is written.
#include <cstdio>
#include <exception>
#include <string>
#include <sys/stat.h>

#include "lieservo_adapters/tactile_frame.hpp"
#include "replay.hpp"

namespace {

// What one tactile frame costs on one thread (the report's line; the stage-by-stage benchmark
// is benchmarks/frame_report.py). A failure here is reported, not a failed task.
void reportFrameRate(const std::string& data_dir, const std::string& models_dir) {
  namespace ad = lieservo::adapters;
  try {
    ad::TactileFrame frame = ad::TactileFrame::load(data_dir + "/val/processed_images/image_1.png",
                                                    models_dir + "/train_val/model_card.json");
    const ad::FrameTiming t = ad::timeFrames(frame, 21);
    std::printf("[frame] one tactile frame on one thread (median of %d; %s): %.1f ms = preprocessing %.1f ms + "
                "GDN %.1f ms + observation, filter, controller and pipeline cycle %.1f us: the loop sustains %.0f Hz "
                "(the paper: 20 Hz)\n",
                t.frames, frame.image_source.c_str(), t.whole_us * 1e-3, t.preprocess_us * 1e-3, t.gdn_us * 1e-3,
                t.estimation_control_us, 1e6 / t.whole_us);
  } catch (const std::exception& e) {
    std::printf("[frame] not measured: %s\n", e.what());
  }
}

}  // namespace

bool lieservoDemoReplay(const std::string& out_dir, int quick_images) {
  namespace rp = lieservo::replay;
  rp::ReplayOptions opt;
  opt.quick = quick_images;
  opt.data_dir = LIESERVO_DEFAULT_DATA_DIR;
  opt.models_dir = LIESERVO_DEFAULT_MODELS_DIR;
  struct stat st {};
  if (stat((opt.data_dir + "/" + opt.split + "/targets.csv").c_str(), &st) != 0) {
    std::printf("[replay] skipped: no real TacTip data at %s (configure with -DLIESERVO_DATA_DIR=...)\n",
                opt.data_dir.c_str());
    reportFrameRate(opt.data_dir, opt.models_dir);
    return true;  // the data set is optional; nothing failed
  }
  rp::setDemoOutputs(opt, out_dir);
  opt.verbose = false;
  try {
    const rp::ReplayResults r = rp::runReplay(opt);
    std::printf("%s", r.table().c_str());
    reportFrameRate(opt.data_dir, opt.models_dir);
    for (const rp::FilterRow& row : r.filter) {
      if (row.failures != 0) return false;
    }
    return r.have_gdn;
  } catch (const std::exception& e) {
    std::printf("[replay] failed: %s\n", e.what());
    return false;
  }
}
