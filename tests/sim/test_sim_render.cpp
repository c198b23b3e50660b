// The pictures of the runs (examples/sim/render.hpp): drawn offscreen from the logged states,
// they never change a run.
#include <catch2/catch.hpp>

#include <cstdio>
#include <filesystem>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "lieservo_sim/render.hpp"

using namespace lieservo::sim;

namespace {

PushingSetup shortPush() {
  PushingSetup su;
  su.object = shortObjects()[0];  // the blue square
  su.surface = SupportSpec::mdf();
  su.timeout = 4;                 // s: long enough to move it, short enough for a test
  return su;
}

// Everything a push logs, compared exactly.
void requireSameRun(const PushTrial& a, const PushTrial& b) {
  REQUIRE(a.sensor_path == b.sensor_path);
  REQUIRE(a.object_path == b.object_path);
  REQUIRE(a.bearing == b.bearing);
  REQUIRE(a.alignment_velocity == b.alignment_velocity);
  REQUIRE(a.leader_depth == b.leader_depth);
  REQUIRE(a.leader_tilt == b.leader_tilt);
  REQUIRE(a.object_tilt == b.object_tilt);
  REQUIRE(a.states.times == b.states.times);
  REQUIRE(a.states.qpos == b.states.qpos);
  REQUIRE(a.target_error == b.target_error);
}

}  // namespace

TEST_CASE("A run logs the same with pictures drawn before it and without", "[sim][render]") {
  TaskOptions opt;
  const PushTrial before = runPushTrial(shortPush(), opt, 7);
  REQUIRE(before.states.qpos.size() >= 10);  // every kStatePeriod over ~4 s, and the end

  // Draw in this thread (OSMesa and MuJoCo's renderer may change floating-point or global
  // state that the physics would then see), then run the same seeded trial again.
  render::Renderer renderer(320, 240);
  PushingResult pr;
  pr.cases.push_back(runPushingCase(shortPush(), opt, 1));
  pr.cases.back().figure_stem = "push";
  const std::string dir = (std::filesystem::temp_directory_path() / "lieservo_test_render").string();
  std::filesystem::remove_all(dir);
  render::Written written;
  render::writePushingPictures(renderer, pr, dir, true, written);
  REQUIRE(written.images.size() == 1);
  const PushTrial after = runPushTrial(shortPush(), opt, 7);
  requireSameRun(before, after);

  // The time-lapse: both views side by side under their captions, not one colour.
  const cv::Mat img = cv::imread(dir + "/" + written.images.front());
  REQUIRE(img.cols == 640);
  REQUIRE(img.rows == 240);
  cv::Scalar mean, sd;
  cv::meanStdDev(img, mean, sd);
  CHECK(sd[0] + sd[1] + sd[2] > 10);

  // The video plays back: as many frames as logged states, of the picture's size.
  REQUIRE(written.videos.size() == 1);
  cv::VideoCapture cap(dir + "/" + written.videos.front());
  REQUIRE(cap.isOpened());
  int frames = 0;
  cv::Mat f;
  while (cap.read(f)) {
    CHECK(f.cols == 320);
    CHECK(f.rows == 240);
    ++frames;
  }
  CHECK(frames == int(pr.cases.back().trials.front().states.qpos.size()));
  std::filesystem::remove_all(dir);
}

TEST_CASE("The renderer refuses what it cannot draw, and keeps working", "[sim][render]") {
  REQUIRE_THROWS_AS(render::Renderer(8, 8), render::RenderError);
  render::Renderer renderer(64, 48);
  mujoco::StateLog empty;
  REQUIRE_THROWS_AS(renderer.draw(empty, {0}, render::View{}), render::RenderError);
  mujoco::StateLog log;
  log.scene.objects = {shortObjects()[0]};
  {
    mujoco::World w(log.scene);
    log.add(0, w.positions());
  }
  REQUIRE_THROWS_AS(renderer.draw(log, {1}, render::View{}), render::RenderError);  // past the end
  mujoco::StateLog wrong = log;
  wrong.qpos[0].pop_back();
  REQUIRE_THROWS_AS(renderer.draw(wrong, {0}, render::View{}), render::RenderError);  // not this scene's size
  const cv::Mat ok = renderer.draw(log, {0}, render::View{});
  CHECK(ok.cols == 64);
  CHECK(ok.rows == 48);
  CHECK(render::evenMoments(11, 5) == std::vector<std::size_t>{0, 3, 5, 8, 10});  // halves round up
  CHECK(render::evenMoments(2, 5) == std::vector<std::size_t>{0, 1});
  CHECK(render::evenMoments(0, 5).empty());
}
