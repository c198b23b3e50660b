// lieservo_demo — runs the paper's four tasks in simulation and prints one summary table
// beside the paper's numbers (docs/simulation.md).
//
//   lieservo_demo [--out DIR] [--seed N] [--trials N] [--rate HZ] [--quick] [--no-files]
//                 [--calibration card|paper] [--observations auto|real|gaussian] [--data DIR]
//                 [--model-card FILE] [--skin-friction MU] [--randomise] [--video] [--no-pictures]
//                 (--help: all of them)
//
// Exit status (lieservo_cli/cli.hpp): 0 when every task met its success criteria, 1 when one
// missed them, 2 on bad usage or set-up (a malformed option, missing data, an unreadable image
// or model, out of memory), with a message naming the option or file.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <cstdio>
#include <cstdlib>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <functional>
#include <limits>
#include <memory>
#include <mutex>
#include <new>
#include <string>
#include <thread>
#include <type_traits>
#include <vector>

#include <lieservo_cli/cli.hpp>

#include "lieservo_sim/csv_log.hpp"
#include "lieservo_sim/tasks.hpp"
#ifdef LIESERVO_DEMO_WITH_REAL_OBSERVATIONS
#include "lieservo_sim/real_observation.hpp"
#endif
#ifdef LIESERVO_DEMO_WITH_RENDER
#include "lieservo_sim/render.hpp"
#endif

#ifdef LIESERVO_DEMO_WITH_REPLAY
// The real-data replay (examples/replay/demo_hook.cpp, linked in when examples/replay is built):
// true = the replay ran and passed. quick_images > 0: only the split's first quick_images images.
bool lieservoDemoReplay(const std::string& out_dir, int quick_images);
#endif

namespace {

using namespace lieservo::sim;
using Clock = std::chrono::steady_clock;

double seconds(Clock::time_point a) { return std::chrono::duration<double>(Clock::now() - a).count(); }

std::string pm(double m, double s) {
  char b[64];
  if (std::isnan(m)) return "-";
  std::snprintf(b, sizeof b, "%.2f ± %.2f", m, s);
  return b;
}

#ifdef LIESERVO_DEMO_WITH_RENDER
// The pictures of the finished tasks (render.hpp), drawn on a thread of their own while the
// next task runs: the runs keep both cores busy and the drawing leaves one mostly idle (OSMesa),
// so drawing them in turn would add its whole time to the demo's. Each job draws from its own
// copy of a task's result, whose logged states are final, so a picture never touches a running
// task or changes a result. What the drawing reports is kept for the end (finish()).
class PictureWorker {
 public:
  PictureWorker(std::string out_dir, bool video) : out_dir_(std::move(out_dir)), video_(video) {
    thread_ = std::thread([this] { loop(); });
  }
  /// An early end: the pictures not yet started are dropped, the one being drawn is finished.
  ~PictureWorker() {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      jobs_.clear();
    }
    finish();
  }
  PictureWorker(const PictureWorker&) = delete;
  PictureWorker& operator=(const PictureWorker&) = delete;

  /// Queues the pictures of one task's result (a tracking, following or pushing result).
  template <class Result>
  void add(const Result& result) {
    auto copy = std::make_shared<const Result>(result);
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      if (closing_) return;
      jobs_.emplace_back([this, copy](render::Renderer& r, render::Written& w) {
        if constexpr (std::is_same_v<Result, TrackingResult>)
          render::writeTrackingPictures(r, *copy, out_dir_, video_, w);
        else if constexpr (std::is_same_v<Result, FollowingResult>)
          render::writeFollowingPictures(r, *copy, out_dir_, video_, w);
        else
          render::writePushingPictures(r, *copy, out_dir_, video_, w);
      });
    }
    ready_.notify_one();
  }

  /// Waits until every queued picture is drawn; then the counts below are final.
  void finish() {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      closing_ = true;
    }
    ready_.notify_one();
    if (thread_.joinable()) thread_.join();
  }

  std::size_t images = 0, videos = 0;  ///< written (after finish())
  double seconds_drawing = 0;          ///< wall-clock time spent drawing (after finish())
  std::vector<std::string> messages;   ///< what could not be drawn (after finish())

 private:
  using Job = std::function<void(render::Renderer&, render::Written&)>;

  void loop() {
    std::unique_ptr<render::Renderer> renderer;  // made, used and freed on this thread only
    bool failed = false;
    for (;;) {
      Job job;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        ready_.wait(lock, [this] { return closing_ || !jobs_.empty(); });
        if (jobs_.empty()) return;
        job = std::move(jobs_.front());
        jobs_.pop_front();
      }
      if (failed) continue;
      const auto t = Clock::now();
      try {
        if (!renderer) renderer = std::make_unique<render::Renderer>(640, 480);
        render::Written w;
        job(*renderer, w);
        images += w.images.size();
        videos += w.videos.size();
        for (const auto& p : w.problems) messages.push_back("pictures: " + p);
      } catch (const std::exception& e) {  // RenderError, or what OpenCV or memory threw
        messages.push_back(std::string("no time-lapses: ") + e.what() + " (the page shows the plots alone)");
        failed = true;
      }
      seconds_drawing += seconds(t);
    }
  }

  const std::string out_dir_;
  const bool video_;
  std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<Job> jobs_;
  bool closing_ = false;
  std::thread thread_;
};
#endif

// "blue square, foam (mm) [reached 5/5, contact 5/5, ...]"
std::string caseLabel(const PushingCase& c) {
  const int n = int(c.trials.size());
  int leader = 0, upright = 0;
  for (const auto& t : c.trials) leader += t.contact_kept, upright += t.max_tilt <= Bounds::upright_tilt_max;
  char b[200];
  if (c.setup.dual_arm)
    std::snprintf(b, sizeof b, " [reached %d/%d, contact %d/%d, follower %d/%d, upright %d/%d, opposition >= %.0f deg]",
                  c.reached_trials, n, leader, n, c.follower_kept_trials, n, upright, n, c.min_opposition);
  else
    std::snprintf(b, sizeof b, " [reached %d/%d, contact %d/%d]", c.reached_trials, n, leader, n);
  return displayName(c.setup.object) + ", " + c.setup.surface.name + " (mm)" + b + (c.judged ? "" : " (reported)");
}

struct Row {
  std::string task, item, sim, paper;
  bool pass;
};

std::string html(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '&') out += "&amp;";
    else if (c == '<') out += "&lt;";
    else if (c == '>') out += "&gt;";
    else out += c;
  }
  return out;
}

// One page of results: the summary table beside the paper's numbers, every figure in the
// results folder (SVG and PNG, its subfolders included) and links to the CSV logs. The
// pictures of a plot `X.svg` (its time-lapses, strips of frames and videos, in the folder `X/`)
// follow it, side by side.
bool writeIndex(const std::string& dir, const std::string& heading, const std::vector<Row>& rows,
                const std::vector<std::string>& failures) {
  namespace fs = std::filesystem;
  std::vector<std::string> figures, logs, videos;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(dir, ec); !ec && it != fs::recursive_directory_iterator();
       it.increment(ec)) {
    if (!it->is_regular_file(ec)) continue;
    const std::string ext = it->path().extension().string();
    const std::string rel = fs::relative(it->path(), dir, ec).generic_string();
    if (ext == ".svg" || ext == ".png") figures.push_back(rel);
    else if (ext == ".csv") logs.push_back(rel);
    else if (ext == ".mp4" || ext == ".webm") videos.push_back(rel);
  }
  std::sort(figures.begin(), figures.end());
  std::sort(logs.begin(), logs.end());
  std::sort(videos.begin(), videos.end());
  // The folder X/ of a plot X.svg: its pictures.
  auto folderOf = [](const std::string& rel) { return rel.substr(0, rel.find_last_of('/') + 1); };
  auto isPlot = [](const std::string& rel) {
    return rel.size() > 4 && rel.compare(rel.size() - 4, 4, ".svg") == 0 && rel.find('/') == std::string::npos;
  };
  std::vector<std::string> plot_folders;
  for (const auto& x : figures)
    if (isPlot(x)) plot_folders.push_back(x.substr(0, x.size() - 4) + "/");
  auto belongs = [&](const std::string& rel) {
    return std::find(plot_folders.begin(), plot_folders.end(), folderOf(rel)) != plot_folders.end();
  };
  std::ofstream f(dir + "/index.html");
  f << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>lieservo results</title>\n"
       "<style>body{font-family:sans-serif;margin:2em}table{border-collapse:collapse}"
       "td,th{border:1px solid #ccc;padding:2px 6px}.no{color:#b00;font-weight:bold}"
       "img{max-width:100%;border:1px solid #eee;margin:8px 0}.pictures{display:flex;flex-wrap:wrap;gap:8px}"
       ".pictures figure{margin:0;flex:1 1 45%;max-width:49%}figcaption{font-size:small;color:#555}"
       "</style></head><body>\n"
    << "<h1>lieservo: the paper's four tasks in simulation</h1>\n<pre>" << html(heading) << "</pre>\n"
    << "<h2>Summary beside the paper</h2>\n<table><tr><th>task</th><th>quantity</th><th>simulation</th>"
       "<th>paper</th><th>pass</th></tr>\n";
  for (const Row& r : rows)
    f << "<tr><td>" << html(r.task) << "</td><td>" << html(r.item) << "</td><td>" << html(r.sim) << "</td><td>"
      << html(r.paper) << "</td><td" << (r.pass ? ">yes" : " class=\"no\">NO") << "</td></tr>\n";
  f << "</table>\n";
  if (!failures.empty()) {
    f << "<h2>Failures</h2>\n<ul>\n";
    for (const auto& x : failures) f << "<li>" << html(x) << "</li>\n";
    f << "</ul>\n";
  }
  f << "<h2>Figures</h2>\n";
  for (const auto& x : figures) {
    if (belongs(x)) continue;  // shown under its plot
    f << "<h3>" << html(x) << "</h3>\n<img src=\"" << html(x) << "\" alt=\"" << html(x) << "\">\n";
    if (!isPlot(x)) continue;
    const std::string folder = x.substr(0, x.size() - 4) + "/";
    bool open = false;
    for (const auto& p : figures)
      if (folderOf(p) == folder) {
        if (!open) f << "<div class=\"pictures\">\n", open = true;
        f << "<figure><img class=\"picture\" src=\"" << html(p) << "\" alt=\"" << html(p) << "\"><figcaption>"
          << html(p) << "</figcaption></figure>\n";
      }
    if (open) f << "</div>\n";
    for (const auto& v : videos)
      if (folderOf(v) == folder) f << "<p>video: <a href=\"" << html(v) << "\">" << html(v) << "</a></p>\n";
  }
  f << "<h2>Logs</h2>\n<ul>\n";
  for (const auto& x : logs) f << "<li><a href=\"" << html(x) << "\">" << html(x) << "</a></li>\n";
  f << "</ul>\n</body></html>\n";
  return bool(f);
}

}  // namespace

static int run(int argc, char** argv) {
  namespace cli = lieservo::cli;
  TaskOptions opt;
  opt.out_dir = "results";
  std::string calibration = "card";
  std::string observations = "auto";
  std::string data_dir = LIESERVO_DEFAULT_DATA_DIR;
  std::string model_card = LIESERVO_SIM_MODEL_CARD;
  int trials = 5;
  bool quick = false, no_files = false, no_pictures = false, video = false;
  CLI::App app("lieservo_demo: the paper's four tasks in simulation (MuJoCo) and the real-data replay, one\n"
               "summary table beside the paper's numbers. Exit status: 0 every task met its criteria, 1 a\n"
               "task missed them, 2 bad usage or set-up (the message names the option or file).",
               "lieservo_demo");
  app.add_option("--out", opt.out_dir, "results folder")->capture_default_str();
  app.add_option("--seed", opt.seed, "base seed")->capture_default_str()->check(
      cli::integerIn<std::uint64_t>(0, 1000000000000000));  // trial seeds are seed · 1000 + i + 1
  auto* trials_option = app.add_option("--trials", trials, "pushing trials per object and surface (the paper: 5)")
      ->capture_default_str()
      ->check(cli::integerIn(1, 100));
  app.add_option("--rate", opt.control_rate, "tactile control rate (Hz)")->capture_default_str()->check(cli::finiteIn(1, 1000));
  app.add_flag("--quick", quick, "shortened runs (duration scale 0.3; 2 trials unless --trials is given)");
  app.add_flag("--no-files", no_files, "do not write plots and logs");
  app.add_flag("--no-pictures", no_pictures, "no time-lapses or strips of frames (rendered offscreen; plots and logs still)");
  app.add_flag("--video", video, "also a video of each task's run (trial 1 of each pushing case); slow, off by default");
  app.add_option("--observations", observations,
                 "'real': the card's GDN on the nearest labelled TacTip image it did not train on; 'gaussian': "
                 "the calibrated Gaussian model; 'auto': real when the data set is there")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "real", "gaussian"}));
  app.add_option("--data", data_dir, "the TacTip data set for 'real'")->capture_default_str();
  app.add_option("--calibration", calibration,
                 "the Gaussian model's error calibration: the model card's measured MAE (falls back to the "
                 "paper's) or the paper's Table 1")
      ->capture_default_str()
      ->check(CLI::IsMember({"card", "paper"}));
  auto* card_option = app.add_option("--model-card", model_card,
                                     "the GDN's model card (the paper's reproduction model: "
                                     "examples/gdn/models/model_card.json)")
                          ->capture_default_str();
  app.add_option("--skin-friction", opt.contact.skin_friction, "skin-object friction mu_c")
      ->capture_default_str()
      ->check(cli::finiteIn(0, 5));
  app.add_flag("--randomise", opt.randomise,
               "draw the assumed physical parameters (mu_s, mu_c, gel stiffness) per pushing trial from their "
               "ranges (docs/simulation.md, \"What is assumed\")");
  if (const int status = cli::parse(app, argc, argv); status >= 0) return status;
  if (quick) {
    opt.duration_scale = 0.3;
    if (trials_option->count() == 0) trials = 2;
  }
  if (no_files) opt.out_dir.clear();
  const bool model_card_given = card_option->count() > 0;
  if (calibration == "card") {
    if (!GdnCalibration::fromModelCard(model_card, opt.calibration)) {
      if (model_card_given) {
        std::fprintf(stderr, "--model-card %s: cannot read models.gdn's measured MAE from it\n", model_card.c_str());
        return 2;
      }
      std::printf("note: no readable GDN model card at %s, using the paper's Table 1\n", model_card.c_str());
    }
  }
  std::string observation_note;
#ifdef LIESERVO_DEMO_WITH_REAL_OBSERVATIONS
  // 'auto' falls back to the Gaussian model only when the data set is absent; with the data set
  // there, anything that stops the real mode (a corrupted model or params file) is a set-up error.
  RealObservationOptions ro;
  ro.data_dir = data_dir;
  ro.model_card = model_card;
  if (observations == "real" || (observations == "auto" && ro.dataSetPresent())) {
    try {
      opt.observations = std::make_shared<RealGdnObservations>(ro);
    } catch (const SceneError& e) {
      std::fprintf(stderr, "set-up error: %s\n", e.what());
      return lieservo::cli::kUsageOrSetup;
    }
  } else if (observations == "auto") {
    observation_note = "(no TacTip data set at " + data_dir + ": the `real` mode needs it)";
  }
#else
  if (observations == "real") {
    std::fprintf(stderr, "--observations real: this build has no `real` mode (it needs OpenCV and nanoflann)\n");
    return 2;
  }
  if (observations == "auto") observation_note = "(this build has no `real` mode: it needs OpenCV and nanoflann)";
#endif
  try {
    opt.validate();
  } catch (const SceneError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
  if (!opt.out_dir.empty() && !makeDirectories(opt.out_dir)) {
    std::fprintf(stderr, "cannot create output folder '%s'\n", opt.out_dir.c_str());
    return 2;
  }

  const std::string observation_mode =
      opt.observations ? opt.observations->describe() : GdnObservationModel(opt.calibration).describe();
  std::printf("lieservo simulation demo: all four tasks on MuJoCo (2.5 ms steps), control %.0f Hz, seed %llu,\n"
              "skin friction %.2f\nobservations (%s mode): %s\n",
              opt.control_rate, static_cast<unsigned long long>(opt.seed), opt.contact.skin_friction,
              opt.observations ? "real" : "gaussian", observation_mode.c_str());
  if (!observation_note.empty()) std::printf("%s\n", observation_note.c_str());
  // A real-mode observation that could not be made (an unreadable or truncated image, a
  // network that fails) is a set-up error, not a missed criterion: exit 2 naming the file.
  auto observationsFailed = [&]() {
#ifdef LIESERVO_DEMO_WITH_REAL_OBSERVATIONS
    if (const auto* real = dynamic_cast<const RealGdnObservations*>(opt.observations.get());
        real && !real->lastError().empty()) {
      std::fprintf(stderr, "\nset-up error: real observations: %s\n", real->lastError().c_str());
      return true;
    }
#endif
    return false;
  };
  // The pictures of the runs, drawn from their logged states after each task (render.hpp) on a
  // thread of their own (PictureWorker): never part of a result. Without a renderer the page
  // shows the plots alone.
  const bool pictures = !opt.out_dir.empty() && !no_pictures;
  double picture_seconds = 0;
  std::size_t picture_count = 0, video_count = 0;
#ifdef LIESERVO_DEMO_WITH_RENDER
  std::unique_ptr<PictureWorker> picture_worker;
  if (pictures) picture_worker = std::make_unique<PictureWorker>(opt.out_dir, video);
#else
  if (pictures)
    std::printf("no time-lapses: this build has no offscreen renderer (it needs OSMesa, apt install "
                "libosmesa6-dev, and LIESERVO_BUILD_RENDER on); the page shows the plots alone\n");
  if (video) std::printf("--video: ignored, this build has no offscreen renderer\n");
#endif
  auto drawPictures = [&](const auto& result) {
#ifdef LIESERVO_DEMO_WITH_RENDER
    if (picture_worker) picture_worker->add(result);
#else
    (void)result;
#endif
  };
  const auto t_all = Clock::now();
  std::vector<Row> rows;
  std::vector<std::string> failures, reported;
  double sim_seconds = 0;
  bool ok = true;
  char buf[160];
  try {
    // (a) object tracking
    auto t0 = Clock::now();
    std::printf("[1/4] object tracking (single-axis moves + periodic trajectory) ... ");
    std::fflush(stdout);
    const TrackingResult tr = runObjectTracking(opt);
    std::printf("%s (%.0f s simulated, %.1f s)\n", tr.success ? "ok" : "FAILED", tr.sim_time, seconds(t0));
    for (const TrackingSegment* s : {&tr.single_axis, &tr.periodic}) {
      std::snprintf(buf, sizeof buf, "%.2f / %.2f", s->depth_error.mean, s->depth_error.max);
      rows.push_back({"tracking", s->name + ": depth err mean/max (mm)", buf, "qualitative (6 mm ref)", tr.success});
      std::snprintf(buf, sizeof buf, "%.2f / %.2f", s->tilt.mean, s->tilt.max);
      rows.push_back({"tracking", s->name + ": angle from normal mean/max (deg)", buf, "qualitative", tr.success});
      std::snprintf(buf, sizeof buf, "%.2f / %.2f", s->twist.mean, s->twist.max);
      rows.push_back({"tracking", s->name + ": gamma twist mean/max (deg)", buf, "-", true});
      rows.push_back({"tracking", s->name + ": contact kept", s->contact_kept ? "yes" : "NO", "yes", s->contact_kept});
    }
    failures.insert(failures.end(), tr.failures.begin(), tr.failures.end());
    sim_seconds += tr.sim_time;
    ok = ok && tr.success;
    if (observationsFailed()) return lieservo::cli::kUsageOrSetup;
    drawPictures(tr);

    // (b) surface following
    t0 = Clock::now();
    std::printf("[2/4] surface following (curved ramp, 8 dome paths) ... ");
    std::fflush(stdout);
    const FollowingResult fr = runSurfaceFollowing(opt);
    std::printf("%s (%.0f s simulated, %.1f s)\n", fr.success ? "ok" : "FAILED", fr.sim_time, seconds(t0));
    for (const FollowingPath* p : {&fr.ramp, &fr.dome_pooled}) {
      std::snprintf(buf, sizeof buf, "%.2f / %.2f", p->depth_error.mean, p->depth_error.max);
      rows.push_back({"following", p->name + ": depth err mean/max (mm)", buf, "qualitative (3 mm ref)", fr.success});
      std::snprintf(buf, sizeof buf, "%.2f / %.2f", p->tilt.mean, p->tilt.max);
      rows.push_back({"following", p->name + ": angle from normal mean/max (deg)", buf, "qualitative", fr.success});
      std::snprintf(buf, sizeof buf, "%.0f mm, %s", p->distance, p->contact_kept ? "contact kept" : "CONTACT LOST");
      rows.push_back({"following", p->name + ": path length", buf, "-", p->contact_kept && p->reached_end});
    }
    failures.insert(failures.end(), fr.failures.begin(), fr.failures.end());
    sim_seconds += fr.sim_time;
    ok = ok && fr.success;
    if (observationsFailed()) return lieservo::cli::kUsageOrSetup;
    drawPictures(fr);

    // (c) single-arm pushing
    t0 = Clock::now();
    std::printf("[3/4] single-arm pushing on MuJoCo (4 prisms x foam/MDF x %d trials) ... ", trials);
    std::fflush(stdout);
    const PushingResult sp = runSingleArmPushing(opt, trials);
    std::printf("%s (%.0f s simulated, %.1f s)\n", sp.success ? "ok" : "FAILED", sp.sim_time, seconds(t0));
    for (const auto& c : sp.cases) {
      const PaperValue pv = paperSingleArm(c.setup.object.name, c.setup.surface.name);
      rows.push_back({"single-arm push", caseLabel(c), pm(c.mean_error, c.sd_error), pm(pv.mean, pv.sd), c.success});
    }
    failures.insert(failures.end(), sp.failures.begin(), sp.failures.end());
    ok = ok && sp.success;
    sim_seconds += sp.sim_time;
    if (observationsFailed()) return lieservo::cli::kUsageOrSetup;
    drawPictures(sp);

    // (d) dual-arm pushing: the paper's decentralised follower (its round objects reported),
    // then the centralised follower; the tall objects pushed by one arm on foam (reported: how
    // many topple); the toppling thresholds by statics and by the engine.
    t0 = Clock::now();
    std::printf("[4/4] dual-arm pushing on MuJoCo (short on foam/MDF, tall and everyday on MDF, x %d trials)\n"
                "      the paper's follower (Table 9) ... ",
                trials);
    std::fflush(stdout);
    const PushingResult dp = runDualArmPushing(opt, trials, false);
    std::printf("%s (%.0f s simulated, %.1f s)\n", dp.success ? "ok" : "FAILED", dp.sim_time, seconds(t0));
    auto dualRows = [&](const PushingResult& r, const char* task) {
      for (const auto& c : r.cases) {
        const PaperValue pv = paperDualArm(c.setup.object.name, c.setup.surface.name, c.setup.tall);
        rows.push_back({task, caseLabel(c), pm(c.mean_error, c.sd_error), pm(pv.mean, pv.sd), c.success || !c.judged});
      }
      failures.insert(failures.end(), r.failures.begin(), r.failures.end());
      reported.insert(reported.end(), r.reported.begin(), r.reported.end());
      ok = ok && r.success;
      sim_seconds += r.sim_time;
    };
    dualRows(dp, "dual-arm push");
    if (observationsFailed()) return lieservo::cli::kUsageOrSetup;
    drawPictures(dp);
    t0 = Clock::now();
    std::printf("      the centralised follower (Section 3.3.4's alternative, not the paper's controller) ... ");
    std::fflush(stdout);
    const PushingResult cp = runDualArmPushing(opt, trials, true);
    std::printf("%s (%.0f s simulated, %.1f s)\n", cp.success ? "ok" : "FAILED", cp.sim_time, seconds(t0));
    dualRows(cp, "dual, centralised");
    if (observationsFailed()) return lieservo::cli::kUsageOrSetup;
    drawPictures(cp);
    if (!opt.out_dir.empty()) writeOppositionPlot(dp, cp, opt.out_dir + "/pushing_dual_opposition.svg");
    t0 = Clock::now();
    std::printf("      tall objects pushed by one arm on the compliant foam (reported: how many topple) ... ");
    std::fflush(stdout);
    const PushingResult tp = runTallSingleArmPushing(opt, trials);
    std::printf("done (%.0f s simulated, %.1f s)\n", tp.sim_time, seconds(t0));
    for (const auto& c : tp.cases) {
      std::snprintf(buf, sizeof buf, "%d of %d toppled", c.toppled_trials, int(c.trials.size()));
      rows.push_back({"1-arm tall push", displayName(c.setup.object) + ", foam (reported)", buf, "topples", true});
    }
    sim_seconds += tp.sim_time;
    if (observationsFailed()) return lieservo::cli::kUsageOrSetup;
    drawPictures(tp);
    t0 = Clock::now();
    std::printf("      toppling thresholds on a rigid support (mu_s 0.35) by statics and by the engine ... ");
    std::fflush(stdout);
    const std::vector<ToppleRow> topple = toppleTable(tallAndEverydayObjects());
    std::printf("done (%.1f s)\n", seconds(t0));
    for (const ToppleRow& r : topple) {
      const bool above = std::isinf(r.statics_height) && std::isinf(r.engine_height);
      const bool agree = (above || std::abs(r.engine_height / r.statics_height - 1) <= 0.1) &&
                         std::abs(r.engine_friction / r.statics_friction - 1) <= 0.1;
      auto height = [](double h) {
        char b[32];
        if (std::isinf(h)) return std::string("above the top");
        std::snprintf(b, sizeof b, "%.0f mm", h);
        return std::string(b);
      };
      std::snprintf(buf, sizeof buf, "%s / %.2f", height(r.engine_height).c_str(), r.engine_friction);
      char statics[64];
      std::snprintf(statics, sizeof statics, "statics %s / %.2f", height(r.statics_height).c_str(), r.statics_friction);
      rows.push_back({"toppling", displayName(r.object) + ": h* at mu_s 0.35 / mu_s* at h 45 mm, engine", buf,
                      statics, agree});
    }
  } catch (const SceneError& e) {
    std::fprintf(stderr, "set-up error: %s\n", e.what());
    return lieservo::cli::kUsageOrSetup;
  }

#ifdef LIESERVO_DEMO_WITH_REPLAY
  {
    std::printf("[replay] real-data replay ... \n");
    // --quick replays a fifth of the 2000 images (Tables 1-2 then say n = 400).
    const bool replay_ok = lieservoDemoReplay(opt.out_dir, quick ? 400 : 0);
    rows.push_back({"replay", "real TacTip data replay", replay_ok ? "ok" : "FAILED", "-", replay_ok});
    ok = ok && replay_ok;
  }
#endif

#ifdef LIESERVO_DEMO_WITH_RENDER
  // The pictures are on the page: wait for the last of them before writing it.
  if (picture_worker) {
    picture_worker->finish();
    for (const auto& m : picture_worker->messages) std::printf("      %s\n", m.c_str());
    picture_count = picture_worker->images;
    video_count = picture_worker->videos;
    picture_seconds = picture_worker->seconds_drawing;
  }
#endif

  // ---- one summary table ----
  std::printf("\n%-16s %-88s %-24s %-24s %s\n", "task", "quantity", "simulation", "paper", "pass");
  std::printf("%s\n", std::string(162, '-').c_str());
  for (const Row& r : rows)
    std::printf("%-16s %-88s %-24s %-24s %s\n", r.task.c_str(), r.item.c_str(), r.sim.c_str(), r.paper.c_str(),
                r.pass ? "yes" : "NO");
  std::printf("%s\n", std::string(162, '-').c_str());
  std::printf("pushing: final target error = perpendicular distance from the target to the sensor-object contact\n"
              "normal at termination, mean ± sd over %d seeded trials (paper: 5 real trials, Tables 3-5).\n",
              trials);
  if (!opt.out_dir.empty()) {
    char heading[400];
    std::snprintf(heading, sizeof heading, "control %.0f Hz, seed %llu, %d pushing trials per case\nobservations: %s",
                  opt.control_rate, static_cast<unsigned long long>(opt.seed), trials, observation_mode.c_str());
    if (writeIndex(opt.out_dir, heading, rows, failures))
      std::printf("plots (SVG) and logs (CSV) in %s/, all on one page: %s/index.html\n", opt.out_dir.c_str(),
                  opt.out_dir.c_str());
    else
      std::printf("plots (SVG) and logs (CSV) in %s/ (index.html could not be written)\n", opt.out_dir.c_str());
  }
  if (picture_count + video_count > 0)
    std::printf("pictures: %zu time-lapses and strips of frames%s, drawn offscreen in %.1f s beside the runs\n",
                picture_count,
                video ? (", " + std::to_string(video_count) + " videos").c_str() : "", picture_seconds);
  for (const auto& f : reported) std::printf("reported (does not decide): %s\n", f.c_str());
  for (const auto& f : failures) std::printf("FAILED: %s\n", f.c_str());
  const double wall = seconds(t_all);
  std::printf("simulated %.0f s in %.1f s wall-clock: real-time factor %.1f\n", sim_seconds, wall,
              wall > 0 ? sim_seconds / wall : 0.0);
#ifdef LIESERVO_DEMO_WITH_REAL_OBSERVATIONS
  if (const auto* real = dynamic_cast<const RealGdnObservations*>(opt.observations.get()))
    std::printf("observations: real mode, %zu distinct TacTip images run through the GDN\n", real->evaluatedImages());
  else
#endif
    std::printf("observations: gaussian mode%s\n", observation_note.empty() ? "" : (" " + observation_note).c_str());
  std::printf("total %.1f s: %s\n", wall, ok ? "all tasks passed" : "SOME TASKS FAILED");
  return ok ? lieservo::cli::kOk : lieservo::cli::kCriteriaMissed;
}

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "lieservo_demo: out of memory\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "lieservo_demo: %s\n", e.what());
  }
  return lieservo::cli::kUsageOrSetup;
}
