// Reading back the SVG figures written by lieservo_plot/svg_figure.hpp (sim and replay tests):
// one <g> per panel, opened by its frame <rect>, holding polylines and circles.
// Parsed with find, not std::regex: libstdc++'s regex recurses per character and overflows the
// stack on long polylines.
#pragma once

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace svg_test {

struct Polyline {
  std::string colour;
  std::vector<std::pair<double, double>> pts;
};
struct Circle {
  double x = 0, y = 0;
  std::string fill;
};
struct Panel {
  double x = 0, y = 0, size = 0;  ///< the frame, px
  std::vector<Polyline> lines;
  std::vector<Circle> circles;
  /// Whether (px, py) lies strictly inside the frame.
  bool inside(double px, double py) const { return px > x && px < x + size && py > y && py < y + size; }
};

inline std::string slurp(const std::string& path) {
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

/// The value of attribute `name` in the element text `e` ("" when absent).
inline std::string attribute(const std::string& e, const std::string& name) {
  const std::string key = " " + name + "=\"";
  const auto i = e.find(key);
  if (i == std::string::npos) return "";
  const auto j = e.find('"', i + key.size());
  return e.substr(i + key.size(), j - i - key.size());
}

/// The panels of an SVG written by SvgFigure. A panel with fixed limits nests its data in a
/// clipped <g>, so a panel ends at the first "</g>" that is not that group's.
inline std::vector<Panel> panels(const std::string& svg) {
  std::vector<Panel> out;
  for (auto g = svg.find("<g>"); g != std::string::npos; g = svg.find("<g>", g + 3)) {
    auto end = svg.find("</g>", g);
    const auto inner = svg.find("<g clip-path", g);
    if (inner != std::string::npos && inner < end) end = svg.find("</g>", end + 4);
    const std::string body = svg.substr(g, end - g);
    const std::string rect = body.substr(0, body.find("/>"));
    Panel p;
    p.x = std::stod(attribute(rect, "x")), p.y = std::stod(attribute(rect, "y"));
    p.size = std::stod(attribute(rect, "width"));
    for (auto l = body.find("<polyline"); l != std::string::npos; l = body.find("<polyline", l + 9)) {
      const std::string e = body.substr(l, body.find("/>", l) - l);
      Polyline pl;
      pl.colour = attribute(e, "stroke");
      std::istringstream pts(attribute(e, "points"));
      std::string xy;
      while (pts >> xy) {
        const auto comma = xy.find(',');
        pl.pts.emplace_back(std::stod(xy.substr(0, comma)), std::stod(xy.substr(comma + 1)));
      }
      p.lines.push_back(pl);
    }
    for (auto c = body.find("<circle"); c != std::string::npos; c = body.find("<circle", c + 7)) {
      const std::string e = body.substr(c, body.find("/>", c) - c);
      p.circles.push_back({std::stod(attribute(e, "cx")), std::stod(attribute(e, "cy")), attribute(e, "fill")});
    }
    out.push_back(p);
  }
  return out;
}

}  // namespace svg_test
