// SvgFigure (examples/plot): what it writes can be read back — panels on a grid, data inside
// the axes, fixed limits clip, labels escaped — and a file it cannot write is reported.
#include <catch2/catch.hpp>

#include <filesystem>
#include <string>

#include <lieservo_plot/svg_figure.hpp>

#include "svg_test_util.hpp"

using namespace lieservo::plot;

namespace {
std::string tempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("lieservo_plot_" + name)).string();
}
}  // namespace

TEST_CASE("tickLabel: the decimals the step needs, no negative zero", "[plot]") {
  CHECK(tickLabel(10, 5) == "10");
  CHECK(tickLabel(-3, 1) == "-3");
  CHECK(tickLabel(0.25, 0.05) == "0.25");
  CHECK(tickLabel(0.2, 0.1) == "0.2");
  CHECK(tickLabel(-1e-17, 0.5) == "0.0");
  CHECK(tickLabel(-1e-17, 2) == "0");
  CHECK(tickLabel(0.002, 0.001) == "0.002");
}

TEST_CASE("heatColour: blue to red, clamped", "[plot]") {
  CHECK(heatColour(0.0) == "#000080");
  CHECK(heatColour(0.5) == "#80ff80");
  CHECK(heatColour(1.0) == "#800000");
  CHECK(heatColour(-3.0) == heatColour(0.0));
  CHECK(heatColour(7.0) == heatColour(1.0));
}

TEST_CASE("SvgFigure: a grid of panels, data inside the axes, limits clip", "[plot]") {
  SvgFigure fig("a <title> & more", 2);
  for (int k = 0; k < 3; ++k) {
    SvgPanel& p = fig.panel("panel " + std::to_string(k), "x", "y");
    p.line({Point(0, 0), Point(10, 5 * k)}, "#333");
    p.marker(Point(5, 1), 0.0, "#ff0000");
  }
  SvgPanel& clipped = fig.panel("fixed limits", "x", "y");
  clipped.limits = std::array<double, 4>{0, 1, 0, 1};
  clipped.marker(Point(0.5, 0.5), 0.0, "#ff0000");
  clipped.marker(Point(3.0, 0.5), 0.0, "#00ff00");  // outside: clipped by the panel's clip path
  clipped.note("a note");
  fig.caption("caption");
  const std::string path = tempPath("grid.svg");
  REQUIRE(fig.write(path, 200));
  const std::string svg = svg_test::slurp(path);
  CHECK(svg.find("a &lt;title&gt; &amp; more") != std::string::npos);
  const auto ps = svg_test::panels(svg);
  REQUIRE(ps.size() == 4);
  // Two columns: panels 0 and 2 share x, 0 and 1 share y.
  CHECK(ps[0].x == ps[2].x);
  CHECK(ps[0].y == ps[1].y);
  CHECK(ps[2].y > ps[0].y + 200);
  CHECK(ps[1].x > ps[0].x + 200);
  for (std::size_t k = 0; k < 3; ++k) {
    INFO("panel " << k);
    REQUIRE(ps[k].lines.size() == 1);
    for (const auto& q : ps[k].lines[0].pts) {
      CHECK(q.first >= ps[k].x);
      CHECK(q.first <= ps[k].x + ps[k].size);
      CHECK(q.second >= ps[k].y);
      CHECK(q.second <= ps[k].y + ps[k].size);
    }
    REQUIRE(ps[k].circles.size() == 1);
    CHECK(ps[k].inside(ps[k].circles[0].x, ps[k].circles[0].y));
  }
  REQUIRE(ps[3].circles.size() == 2);
  CHECK(ps[3].inside(ps[3].circles[0].x, ps[3].circles[0].y));
  CHECK_FALSE(ps[3].inside(ps[3].circles[1].x, ps[3].circles[1].y));
  CHECK(svg.find("clip-path=\"url(#panel3)\"") != std::string::npos);
  CHECK(svg.find("a note") != std::string::npos);
  std::filesystem::remove(path);
}

TEST_CASE("SvgFigure: an unwritable path is reported", "[plot]") {
  SvgFigure fig("x");
  fig.panel("p", "x", "y").line({Point(0, 0), Point(1, 1)}, "#333");
  CHECK_FALSE(fig.write(tempPath("no_such_dir/x.svg")));
}
