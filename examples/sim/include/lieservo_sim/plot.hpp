// lieservo_sim/plot.hpp — dependency-free SVG line plots and a CSV writer for the tasks.
//
// SvgFigure holds a row of panels; each panel has its own axes (equal aspect by default, as in
// the paper's 2-D pose plots), polylines, markers, arrows (sensor axes) and a title.
#pragma once

#include <deque>
#include <fstream>
#include <string>
#include <vector>

#include "common.hpp"

namespace lieservo::sim {

struct SvgPanel {
  std::string title, xlabel, ylabel;
  bool equal_aspect = true;
  struct Line {
    std::vector<Vec2> pts;
    std::string colour;
    double width;
    bool dashed;
    std::string label;
  };
  struct Marker {
    Vec2 p;
    double radius;
    std::string colour;
    bool filled;
  };
  struct Arrow {
    Vec2 from, to;
    std::string colour;
  };
  std::vector<Line> lines;
  std::vector<Marker> markers;
  std::vector<Arrow> arrows;

  void line(std::vector<Vec2> pts, std::string colour, double width = 1.5, bool dashed = false,
            std::string label = "") {
    lines.push_back({std::move(pts), std::move(colour), width, dashed, std::move(label)});
  }
  void marker(const Vec2& p, double radius, std::string colour, bool filled = true) {
    markers.push_back({p, radius, std::move(colour), filled});
  }
  void arrow(const Vec2& a, const Vec2& b, std::string colour) { arrows.push_back({a, b, std::move(colour)}); }
};

class SvgFigure {
 public:
  explicit SvgFigure(std::string title) : title_(std::move(title)) {}
  /// A new panel. The reference stays valid for the figure's lifetime, however many panels
  /// follow: the panels live in a std::deque, whose push_back never moves existing elements.
  SvgPanel& panel(const std::string& title, const std::string& xl, const std::string& yl) {
    panels_.push_back(SvgPanel{});
    panels_.back().title = title;
    panels_.back().xlabel = xl;
    panels_.back().ylabel = yl;
    return panels_.back();
  }
  /// Writes the figure; returns false if the file cannot be written.
  bool write(const std::string& path, int panel_size = 420) const;

 private:
  std::string title_;
  std::deque<SvgPanel> panels_;  // not a vector: panel() hands out references
};

/// Minimal CSV writer (header + rows of numbers).
class CsvWriter {
 public:
  CsvWriter() = default;
  bool open(const std::string& path, const std::vector<std::string>& header);
  void row(const std::vector<double>& values);
  bool isOpen() const { return out_.is_open(); }

 private:
  std::ofstream out_;
};

/// Creates a directory (and parents); returns false on failure.
bool makeDirectories(const std::string& path);

}  // namespace lieservo::sim
