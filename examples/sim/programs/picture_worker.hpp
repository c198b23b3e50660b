// picture_worker.hpp — the demo's pictures of the finished tasks (render.hpp), drawn on a
// thread of their own while the next task runs.
#pragma once

#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <type_traits>
#include <vector>

#include "lieservo_sim/render.hpp"
#include "lieservo_sim/tasks.hpp"

namespace lieservo::sim::programs {

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
  using Clock = std::chrono::steady_clock;
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
      seconds_drawing += std::chrono::duration<double>(Clock::now() - t).count();
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

}  // namespace lieservo::sim::programs
