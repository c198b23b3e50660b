// lieservo_demo — runs the paper's four tasks in simulation and prints one summary table
// beside the paper's numbers (docs/simulation.md).
//
//   lieservo_demo [--out DIR] [--seed N] [--trials N] [--rate HZ] [--quick] [--no-files]
//                 [--calibration card|paper] [--observations auto|real|gaussian] [--data DIR]
//                 [--model-card FILE] [--skin-friction MU] [--randomise] [--video] [--no-pictures]
//                 (--help: all of them)
//
// Exit status (lieservo_cli/program.hpp): 0 when every task met its success criteria, 1 when
// one missed them, 2 on bad usage or set-up (a malformed option, missing data, an unreadable
// image or model, an output folder that is not the demo's, out of memory), with a message
// naming the option or file.
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include <lieservo_cli/cli.hpp>

#include "lieservo_sim/tasks.hpp"
#include "programs/observation_setup.hpp"
#include "programs/results_page.hpp"
#include "programs/summary_rows.hpp"
#ifdef LIESERVO_DEMO_WITH_RENDER
#include "programs/picture_worker.hpp"
#endif

#ifdef LIESERVO_DEMO_WITH_REPLAY
// The real-data replay (examples/replay/demo_hook.cpp, linked in when examples/replay is built):
// true = the replay ran and passed. quick_images > 0: only the split's first quick_images images.
bool lieservoDemoReplay(const std::string& out_dir, int quick_images);
#endif

namespace {

using namespace lieservo::sim;
using namespace lieservo::sim::programs;
namespace cli = lieservo::cli;
using Clock = std::chrono::steady_clock;

double seconds(Clock::time_point a) { return std::chrono::duration<double>(Clock::now() - a).count(); }

struct DemoSettings {
  TaskOptions opt;
  ObservationChoice observations;
  int trials = 5;
  bool quick = false, no_files = false, no_pictures = false, video = false;
};

// Parses the options into `s`: -1 to go on, else the exit status.
int parseOptions(int argc, char** argv, DemoSettings& s) {
  TaskOptions& opt = s.opt;
  opt.out_dir = "results";
  CLI::App app("lieservo_demo: the paper's four tasks in simulation (MuJoCo) and the real-data replay, one\n"
               "summary table beside the paper's numbers. Exit status: 0 every task met its criteria, 1 a\n"
               "task missed them, 2 bad usage or set-up (the message names the option or file).",
               "lieservo_demo");
  app.add_option("--out", opt.out_dir, "results folder (made by the demo, or empty)")
      ->capture_default_str()
      ->check(cli::nonEmptyPath());
  app.add_option("--seed", opt.seed, "base seed")->capture_default_str()->check(
      cli::integerIn<std::uint64_t>(0, 1000000000000000));  // trial seeds are seed · 1000 + i + 1
  auto* trials_option = app.add_option("--trials", s.trials, "pushing trials per object and surface (the paper: 5)")
                            ->capture_default_str()
                            ->check(cli::integerIn(1, 100));
  app.add_option("--rate", opt.control_rate, "tactile control rate (Hz)")->capture_default_str()->check(cli::finiteIn(1, 1000));
  app.add_flag("--quick", s.quick, "shortened runs (duration scale 0.3; 2 trials unless --trials is given)");
  app.add_flag("--no-files", s.no_files, "do not write plots and logs");
  app.add_flag("--no-pictures", s.no_pictures,
               "no time-lapses or strips of frames (rendered offscreen; plots and logs still)");
  app.add_flag("--video", s.video, "also a video of each task's run (trial 1 of each pushing case); slow, off by default");
  addObservationOptions(app, s.observations, true);
  app.add_option("--skin-friction", opt.contact.skin_friction, "skin-object friction mu_c")
      ->capture_default_str()
      ->check(cli::finiteIn(0, 5));
  app.add_flag("--randomise", opt.randomise,
               "draw the assumed physical parameters (mu_s, mu_c, gel stiffness) per pushing trial from their "
               "ranges (docs/simulation.md, \"What is assumed\")");
  if (const int status = cli::parse(app, argc, argv); status >= 0) return status;
  if (s.quick) {
    opt.duration_scale = 0.3;
    if (trials_option->count() == 0) s.trials = 2;
  }
  if (s.no_files) opt.out_dir.clear();
  return -1;
}

// The tasks in turn, their rows and what they say; each task's pictures queued after it.
class TaskSequence {
 public:
  explicit TaskSequence(DemoSettings& s) : s_(s) {
    const bool pictures = !s.opt.out_dir.empty() && !s.no_pictures;
#ifdef LIESERVO_DEMO_WITH_RENDER
    if (pictures) worker_ = std::make_unique<PictureWorker>(s.opt.out_dir, s.video);
#else
    if (pictures)
      std::printf("no time-lapses: this build has no offscreen renderer (it needs OSMesa, apt install "
                  "libosmesa6-dev, and LIESERVO_BUILD_RENDER on); the page shows the plots alone\n");
    if (s.video) std::printf("--video: ignored, this build has no offscreen renderer\n");
#endif
  }

  std::vector<Row> rows;
  std::vector<std::string> failures, reported;
  double sim_seconds = 0;
  bool ok = true;
  std::size_t picture_count = 0, video_count = 0;
  double picture_seconds = 0;

  /// Runs all tasks: -1 when they ran (ok says whether they passed), else the exit status.
  int run() {
    const TaskOptions& opt = s_.opt;
    const int n = s_.trials;
    std::printf("[1/4] object tracking (single-axis moves + periodic trajectory) ... ");
    const TrackingResult tr = timed([&] { return runObjectTracking(opt); });
    addTrackingRows(tr, rows);
    if (!finished(tr)) return cli::kUsageOrSetup;
    std::printf("[2/4] surface following (curved ramp, 8 dome paths) ... ");
    const FollowingResult fr = timed([&] { return runSurfaceFollowing(opt); });
    addFollowingRows(fr, rows);
    if (!finished(fr)) return cli::kUsageOrSetup;
    std::printf("[3/4] single-arm pushing on MuJoCo (4 prisms x foam/MDF x %d trials) ... ", n);
    const PushingResult sp = timed([&] { return runSingleArmPushing(opt, n); });
    addPushingRows(sp, "single-arm push", rows);
    if (!finished(sp)) return cli::kUsageOrSetup;
    // Dual-arm pushing: the paper's decentralised follower (its round objects reported), then
    // the centralised follower; the tall objects pushed by one arm on foam (reported: how many
    // topple); the toppling thresholds by statics and by the engine.
    std::printf("[4/4] dual-arm pushing on MuJoCo (short on foam/MDF, tall and everyday on MDF, x %d trials)\n"
                "      the paper's follower (Table 9) ... ",
                n);
    const PushingResult dp = timed([&] { return runDualArmPushing(opt, n, false); });
    addPushingRows(dp, "dual-arm push", rows);
    if (!finished(dp)) return cli::kUsageOrSetup;
    std::printf("      the centralised follower (Section 3.3.4's alternative, not the paper's controller) ... ");
    const PushingResult cp = timed([&] { return runDualArmPushing(opt, n, true); });
    addPushingRows(cp, "dual, centralised", rows);
    if (!finished(cp)) return cli::kUsageOrSetup;
    if (!opt.out_dir.empty()) {
      writeOppositionPlot(dp, cp, opt.out_dir + "/pushing_dual_opposition.svg");
      writePushingSummaryFigure(opt.out_dir + "/" + kSummaryFigure, {&sp, &dp, &cp},
                                {"single-arm", "dual-arm", "dual, centralised"});
    }
    std::printf("      tall objects pushed by one arm on the compliant foam (reported: how many topple) ... ");
    const PushingResult tp = timed([&] { return runTallSingleArmPushing(opt, n); }, "done");
    addTallPushRows(tp, rows);
    if (!finished(tp, false)) return cli::kUsageOrSetup;
    std::printf("      toppling thresholds on a rigid support (mu_s 0.35) by statics and by the engine ... ");
    std::fflush(stdout);
    const auto t0 = Clock::now();
    addToppleRows(toppleTable(tallAndEverydayObjects()), rows);
    std::printf("done (%.1f s)\n", seconds(t0));
    return -1;
  }

  /// Waits for the last picture (they are on the page) and prints what the drawing reported.
  void finishPictures() {
#ifdef LIESERVO_DEMO_WITH_RENDER
    if (!worker_) return;
    worker_->finish();
    for (const auto& m : worker_->messages) std::printf("      %s\n", m.c_str());
    picture_count = worker_->images;
    video_count = worker_->videos;
    picture_seconds = worker_->seconds_drawing;
#endif
  }

 private:
  // Runs one task and prints its verdict and times: "ok (12 s simulated, 3.4 s)".
  template <class Task>
  auto timed(Task task, const char* done = nullptr) -> decltype(task()) {
    std::fflush(stdout);
    const auto t0 = Clock::now();
    auto r = task();
    std::printf("%s (%.0f s simulated, %.1f s)\n", done ? done : r.success ? "ok" : "FAILED", r.sim_time, seconds(t0));
    return r;
  }

  // Takes in a task's result; false when its real-mode observations failed (set-up error).
  template <class Result>
  bool finished(const Result& r, bool judged = true) {
    if (judged) {
      failures.insert(failures.end(), r.failures.begin(), r.failures.end());
      ok = ok && r.success;
    }
    if constexpr (std::is_same_v<Result, PushingResult>)
      if (judged) reported.insert(reported.end(), r.reported.begin(), r.reported.end());
    sim_seconds += r.sim_time;
    if (observationsFailed(s_.opt)) return false;
#ifdef LIESERVO_DEMO_WITH_RENDER
    if (worker_) worker_->add(r);
#endif
    return true;
  }

  DemoSettings& s_;
#ifdef LIESERVO_DEMO_WITH_RENDER
  std::unique_ptr<PictureWorker> worker_;
#endif
};

// What follows the table: the page, the pictures, the reported and failed items, the times.
void printEnd(const DemoSettings& s, const TaskSequence& seq, const std::string& observation_mode,
              const std::string& note, double wall) {
  const TaskOptions& opt = s.opt;
  std::printf("pushing: final target error = perpendicular distance from the target to the sensor-object contact\n"
              "normal at termination, mean ± sd over %d seeded trials (paper: 5 real trials, Tables 3-5).\n",
              s.trials);
  if (!opt.out_dir.empty()) {
    char heading[400];
    std::snprintf(heading, sizeof heading, "control %.0f Hz, seed %llu, %d pushing trials per case\nobservations: %s",
                  opt.control_rate, static_cast<unsigned long long>(opt.seed), s.trials, observation_mode.c_str());
    if (writeIndex(opt.out_dir, heading, seq.rows, seq.failures))
      std::printf("plots (SVG) and logs (CSV) in %s/, all on one page: %s/index.html\n", opt.out_dir.c_str(),
                  opt.out_dir.c_str());
    else
      std::printf("plots (SVG) and logs (CSV) in %s/ (index.html could not be written)\n", opt.out_dir.c_str());
  }
  if (seq.picture_count + seq.video_count > 0)
    std::printf("pictures: %zu time-lapses and strips of frames%s, drawn offscreen in %.1f s beside the runs\n",
                seq.picture_count, s.video ? (", " + std::to_string(seq.video_count) + " videos").c_str() : "",
                seq.picture_seconds);
  for (const auto& f : seq.reported) std::printf("reported (does not decide): %s\n", f.c_str());
  for (const auto& f : seq.failures) std::printf("FAILED: %s\n", f.c_str());
  std::printf("simulated %.0f s in %.1f s wall-clock: real-time factor %.1f\n", seq.sim_seconds, wall,
              wall > 0 ? seq.sim_seconds / wall : 0.0);
  std::printf("observations: %s\n", observationsRan(opt, note).c_str());
  std::printf("total %.1f s: %s\n", wall, seq.ok ? "all tasks passed" : "SOME TASKS FAILED");
}

int run(int argc, char** argv) {
  DemoSettings s;
  if (const int status = parseOptions(argc, argv, s); status >= 0) return status;
  TaskOptions& opt = s.opt;
  std::string note;
  if (const int status = setUpObservations(s.observations, opt, note); status >= 0) return status;
  try {
    opt.validate();
  } catch (const SceneError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return cli::kUsageOrSetup;
  }
  if (std::string why; !opt.out_dir.empty() && !cli::claimOutputFolder("--out", opt.out_dir, "lieservo_demo", why, "index.html")) {
    std::fprintf(stderr, "%s\n", why.c_str());
    return cli::kUsageOrSetup;
  }
  const std::string observation_mode =
      opt.observations ? opt.observations->describe() : GdnObservationModel(opt.calibration).describe();
  std::printf("lieservo simulation demo: all four tasks on MuJoCo (2.5 ms steps), control %.0f Hz, seed %llu,\n"
              "skin friction %.2f\nobservations (%s mode): %s\n",
              opt.control_rate, static_cast<unsigned long long>(opt.seed), opt.contact.skin_friction,
              opt.observations ? "real" : "gaussian", observation_mode.c_str());
  if (!note.empty()) std::printf("%s\n", note.c_str());
  const auto t_all = Clock::now();
  TaskSequence seq(s);
  try {
    if (const int status = seq.run(); status >= 0) return status;
  } catch (const SceneError& e) {
    std::fprintf(stderr, "set-up error: %s\n", e.what());
    return cli::kUsageOrSetup;
  }
#ifdef LIESERVO_DEMO_WITH_REPLAY
  std::printf("[replay] real-data replay ... \n");
  // --quick replays a fifth of the 2000 images (Tables 1-2 then say n = 400).
  const bool replay_ok = lieservoDemoReplay(opt.out_dir, s.quick ? 400 : 0);
  seq.rows.push_back({"replay", "real TacTip data replay", replay_ok ? "ok" : "FAILED", "-", replay_ok});
  seq.ok = seq.ok && replay_ok;
#endif
  seq.finishPictures();
  printSummaryTable(seq.rows);
  printEnd(s, seq, observation_mode, note, seconds(t_all));
  return seq.ok ? cli::kOk : cli::kCriteriaMissed;
}

}  // namespace

int main(int argc, char** argv) {
  return lieservo::cli::runProgram("lieservo_demo", [&] { return run(argc, argv); });
}
