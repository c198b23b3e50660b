// lieservo_plot/svg_figure.hpp — the examples' one way to draw a figure: dependency-free SVG.
//
// An SvgFigure holds panels laid out in a grid (one row unless `columns` says otherwise). Each
// panel has its own axes — the data's bounding box by default (equal aspect, as the paper's
// 2-D pose plots), or fixed limits, outside which the content is clipped — and draws
// polylines, markers, arrows (sensor axes), a legend of the labelled lines and notes. Under
// the panels the figure may show a colour scale and captions. Used by the simulated tasks
// (examples/sim) and the real-data replay's scatter plots (examples/replay).
#pragma once

#include <array>
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace lieservo::plot {

using Point = Eigen::Vector2d;

struct SvgPanel {
  std::string title, xlabel, ylabel;
  bool equal_aspect = true;
  /// Fixed axis limits {x0, x1, y0, y1}; unset: the data's bounding box plus 5 %.
  std::optional<std::array<double, 4>> limits;
  struct Line {
    std::vector<Point> pts;
    std::string colour;
    double width;
    bool dashed;
    std::string label;
  };
  struct Marker {
    Point p;
    double radius;  ///< in data units; drawn at least 2 px across the radius
    std::string colour;
    bool filled;
  };
  struct Arrow {
    Point from, to;
    std::string colour;
  };
  std::vector<Line> lines;
  std::vector<Marker> markers;
  std::vector<Arrow> arrows;
  std::vector<std::string> notes;  ///< text lines in the lower right corner

  void line(std::vector<Point> pts, std::string colour, double width = 1.5, bool dashed = false,
            std::string label = "") {
    lines.push_back({std::move(pts), std::move(colour), width, dashed, std::move(label)});
  }
  void marker(const Point& p, double radius, std::string colour, bool filled = true) {
    markers.push_back({p, radius, std::move(colour), filled});
  }
  void arrow(const Point& a, const Point& b, std::string colour) { arrows.push_back({a, b, std::move(colour)}); }
  void note(std::string text) { notes.push_back(std::move(text)); }
};

class SvgFigure {
 public:
  /// `columns`: panels per row (0: all in one row).
  explicit SvgFigure(std::string title, int columns = 0) : title_(std::move(title)), columns_(columns) {}
  /// A new panel. The reference stays valid for the figure's lifetime, however many panels
  /// follow: the panels live in a std::deque, whose push_back never moves existing elements.
  SvgPanel& panel(const std::string& title, const std::string& xl, const std::string& yl) {
    panels_.push_back(SvgPanel{});
    panels_.back().title = title;
    panels_.back().xlabel = xl;
    panels_.back().ylabel = yl;
    return panels_.back();
  }
  /// A colour scale under the panels: `colours` from low to high, `low`/`high` at its ends.
  void colourScale(std::vector<std::string> colours, std::string low, std::string high) {
    scale_colours_ = std::move(colours);
    scale_low_ = std::move(low);
    scale_high_ = std::move(high);
  }
  /// A line of text under the panels (after the colour scale).
  void caption(std::string text) { captions_.push_back(std::move(text)); }
  /// Writes the figure with square panels of `panel_size` px; false if the file cannot be written.
  bool write(const std::string& path, int panel_size = 420) const;

 private:
  std::string title_;
  int columns_ = 0;
  std::deque<SvgPanel> panels_;  // not a vector: panel() hands out references
  std::vector<std::string> scale_colours_;
  std::string scale_low_, scale_high_;
  std::vector<std::string> captions_;
};

/// Blue (t = 0) → cyan → green → yellow → red (t = 1) as "#rrggbb"; t is clamped to [0, 1].
std::string heatColour(double t);

/// A tick label for value v on an axis with tick spacing `step`: as many decimals as the step
/// needs ("0.25", "10", "-3"), never "-0".
std::string tickLabel(double v, double step);

}  // namespace lieservo::plot
