// The figures the tasks write show their data: every panel of every SVG holds at least one
// polyline of two or more points inside the panel's axes, spanning at least a tenth of the
// panel; the dome's top view shows eight distinct radial paths (one per 45° heading) beside
// the dome's outline. Bounds written before the runs.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "lieservo_sim/tasks.hpp"
#include "svg_test_util.hpp"

using namespace lieservo::sim;

namespace {

using svg_test::Panel;
using svg_test::panels;
using svg_test::Polyline;
using svg_test::slurp;

void checkFigure(const std::string& path, std::size_t expected_panels) {
  INFO(path);
  REQUIRE(std::filesystem::exists(path));
  const std::vector<Panel> ps = panels(slurp(path));
  CHECK(ps.size() == expected_panels);
  for (std::size_t k = 0; k < ps.size(); ++k) {
    const Panel& p = ps[k];
    INFO("panel " << k);
    bool has_data = false;
    for (const Polyline& l : p.lines) {
      if (l.pts.size() < 2) continue;
      double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
      for (const auto& pt : l.pts) {
        const Vec2 q(pt.first, pt.second);
        CHECK(q.x() >= p.x - 1);
        CHECK(q.x() <= p.x + p.size + 1);
        CHECK(q.y() >= p.y - 1);
        CHECK(q.y() <= p.y + p.size + 1);
        x0 = std::min(x0, q.x()), x1 = std::max(x1, q.x()), y0 = std::min(y0, q.y()), y1 = std::max(y1, q.y());
      }
      has_data = has_data || std::max(x1 - x0, y1 - y0) >= 0.1 * p.size;
    }
    CHECK(has_data);
  }
}

std::string freshDir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("lieservo_figures_" + name);
  std::filesystem::remove_all(dir);
  return dir.string();
}

}  // namespace

TEST_CASE("figures: tracking and following plots show their data; the dome has eight paths", "[sim][figures]") {
  TaskOptions o;
  o.seed = 2;
  o.duration_scale = 0.1;
  o.out_dir = freshDir("tracking");
  runObjectTracking(o);
  checkFigure(o.out_dir + "/tracking_single_axis.svg", 3);
  checkFigure(o.out_dir + "/tracking_periodic.svg", 3);
  checkFigure(o.out_dir + "/tracking_errors.svg", 2);
  o.duration_scale = 0.3;
  o.out_dir = freshDir("following");
  runSurfaceFollowing(o);
  checkFigure(o.out_dir + "/following_ramp.svg", 3);
  checkFigure(o.out_dir + "/following_dome.svg", 3);
  // Top view: the dome's outline (grey) and eight paths from the pole, heading 0°, 45°, … in the
  // plot (SVG y points down): pairwise at least 30° apart, each at least 5 % of the panel long.
  const std::vector<Panel> dome = panels(slurp(o.out_dir + "/following_dome.svg"));
  REQUIRE(dome.size() == 3);
  std::vector<double> headings;
  for (const Polyline& l : dome[0].lines) {
    if (l.colour == "#888") continue;
    REQUIRE(l.pts.size() >= 2);
    const Vec2 d(l.pts.back().first - l.pts.front().first, l.pts.back().second - l.pts.front().second);
    CHECK(d.norm() >= 0.05 * dome[0].size);
    headings.push_back(std::atan2(-d.y(), d.x()));
  }
  REQUIRE(headings.size() == 8);
  for (std::size_t i = 0; i < 8; ++i)
    for (std::size_t j = i + 1; j < 8; ++j) {
      INFO("paths " << i << " and " << j);
      CHECK(std::abs(std::remainder(headings[i] - headings[j], 2 * kPi)) >= deg2rad(30));
    }
}

TEST_CASE("figures: the pushing plot shows the object, both sensors and the target", "[sim][figures]") {
  TaskOptions o;
  o.seed = 4;
  PushingSetup s;
  s.object = shortObjects()[2];
  s.surface = SupportSpec::mdf();
  s.dual_arm = true;
  s.target = Vec2(-100, 180);  // a short push
  s.timeout = 10;
  const PushingCase c = runPushingCase(s, o, 1);
  const std::string dir = freshDir("pushing");
  std::filesystem::create_directories(dir);
  writePushingPlot({&c, &c}, dir + "/pushing.svg", "two panels");
  checkFigure(dir + "/pushing.svg", 2);
  const std::vector<Panel> ps = panels(slurp(dir + "/pushing.svg"));
  REQUIRE(ps.size() == 2);
  // Object at start and end, the leader's and the follower's paths.
  CHECK(ps[0].lines.size() == 4);
}
