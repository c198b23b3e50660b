// SVG figures (see lieservo_plot/svg_figure.hpp).
#include "lieservo_plot/svg_figure.hpp"

#include <lieservo_cli/program.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <limits>

namespace lieservo::plot {

namespace cli = lieservo::cli;

namespace {

// About six ticks per axis, at 1, 2 or 5 × 10^k.
double niceStep(double range) {
  const double raw = range / 6;
  const double p = std::pow(10.0, std::floor(std::log10(std::max(raw, 1e-12))));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * p >= raw) return m * p;
  return 10 * p;
}

// Text content and attribute values may hold &, < or > (titles, labels).
std::string escaped(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  for (char ch : s) {
    if (ch == '&') out += "&amp;";
    else if (ch == '<') out += "&lt;";
    else if (ch == '>') out += "&gt;";
    else if (ch == '"') out += "&quot;";
    else out += ch;
  }
  return out;
}

}  // namespace

std::string heatColour(double t) {
  t = std::clamp(std::isfinite(t) ? t : 0.0, 0.0, 1.0);
  auto channel = [&](double centre) {
    return static_cast<int>(std::lround(255 * std::clamp(1.5 - std::fabs(4.0 * t - centre), 0.0, 1.0)));
  };
  char b[8];
  std::snprintf(b, sizeof b, "#%02x%02x%02x", channel(3.0), channel(2.0), channel(1.0));
  return b;
}

std::string tickLabel(double v, double step) {
  const int decimals = step >= 1 ? 0 : static_cast<int>(std::ceil(-std::log10(step) - 1e-9));
  char b[48];
  std::snprintf(b, sizeof b, "%.*f", std::clamp(decimals, 0, 12), v);
  std::string s = b;
  if (s.front() == '-' && s.find_first_not_of("-0.") == std::string::npos) s.erase(0, 1);  // "-0" → "0"
  return s;
}

namespace {

// A panel's data window: fixed limits, or the data's bounding box plus 5 %; squared for an
// equal aspect.
struct Window {
  double x0, x1, y0, y1, dx, dy;
};

Window panelWindow(const SvgPanel& p) {
  double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
  double dx = 0, dy = 0;
  if (p.limits) {
    x0 = (*p.limits)[0], x1 = (*p.limits)[1], y0 = (*p.limits)[2], y1 = (*p.limits)[3];
    if (!(x1 > x0)) x0 -= 1, x1 = x0 + 2;
    if (!(y1 > y0)) y0 -= 1, y1 = y0 + 2;
    dx = x1 - x0, dy = y1 - y0;
  } else {
    auto grow = [&](const Point& q) {
      if (!q.allFinite()) return;
      x0 = std::min(x0, q.x());
      x1 = std::max(x1, q.x());
      y0 = std::min(y0, q.y());
      y1 = std::max(y1, q.y());
    };
    for (const auto& l : p.lines)
      for (const auto& q : l.pts) grow(q);
    for (const auto& m : p.markers) {
      grow(m.p + Point(m.radius, m.radius));
      grow(m.p - Point(m.radius, m.radius));
    }
    for (const auto& a : p.arrows) {
      grow(a.from);
      grow(a.to);
    }
    if (!(x1 >= x0)) x0 = -1, x1 = 1, y0 = -1, y1 = 1;
    dx = std::max(x1 - x0, 1e-6), dy = std::max(y1 - y0, 1e-6);
    x0 -= 0.05 * dx, x1 += 0.05 * dx, y0 -= 0.05 * dy, y1 += 0.05 * dy;
    dx = x1 - x0, dy = y1 - y0;
  }
  if (p.equal_aspect) {
    const double d = std::max(dx, dy);
    x0 -= (d - dx) / 2, x1 = x0 + d, y0 -= (d - dy) / 2, y1 = y0 + d;
    dx = dy = d;
  }
  return {x0, x1, y0, y1, dx, dy};
}

// Panel k at (ox, oy), S px square: its frame, grid, titles, content (clipped to fixed
// limits), legend and notes.
void writePanel(std::ostream& f, const SvgPanel& p, int k, double ox, double oy, int S) {
  const Window w = panelWindow(p);
  auto X = [&](double x) { return ox + (x - w.x0) / w.dx * S; };
  auto Y = [&](double y) { return oy + S - (y - w.y0) / w.dy * S; };
  // The frame comes first in the panel's group (tests find a panel by it).
  f << "<g>\n<rect x=\"" << ox << "\" y=\"" << oy << "\" width=\"" << S << "\" height=\"" << S
    << "\" fill=\"none\" stroke=\"#444\"/>\n";
  const double sx = niceStep(w.dx), sy = niceStep(w.dy);
  for (double t = std::ceil(w.x0 / sx) * sx; t <= w.x1 + 1e-9 * sx; t += sx)
    f << "<line x1=\"" << X(t) << "\" y1=\"" << oy << "\" x2=\"" << X(t) << "\" y2=\"" << oy + S
      << "\" stroke=\"#eee\"/><text x=\"" << X(t) << "\" y=\"" << oy + S + 15 << "\" text-anchor=\"middle\">"
      << tickLabel(t, sx) << "</text>\n";
  for (double t = std::ceil(w.y0 / sy) * sy; t <= w.y1 + 1e-9 * sy; t += sy)
    f << "<line x1=\"" << ox << "\" y1=\"" << Y(t) << "\" x2=\"" << ox + S << "\" y2=\"" << Y(t)
      << "\" stroke=\"#eee\"/><text x=\"" << ox - 5 << "\" y=\"" << Y(t) + 4 << "\" text-anchor=\"end\">"
      << tickLabel(t, sy) << "</text>\n";
  f << "<text x=\"" << ox + S / 2.0 << "\" y=\"" << oy - 8 << "\" text-anchor=\"middle\" font-weight=\"bold\">"
    << escaped(p.title) << "</text>\n";
  f << "<text x=\"" << ox + S / 2.0 << "\" y=\"" << oy + S + 35 << "\" text-anchor=\"middle\">"
    << escaped(p.xlabel) << "</text>\n";
  f << "<text transform=\"translate(" << ox - 45 << "," << oy + S / 2.0 << ") rotate(-90)\" text-anchor=\"middle\">"
    << escaped(p.ylabel) << "</text>\n";
  // With fixed limits, what lies outside them is clipped to the frame.
  if (p.limits) {
    f << "<clipPath id=\"panel" << k << "\"><rect x=\"" << ox << "\" y=\"" << oy << "\" width=\"" << S
      << "\" height=\"" << S << "\"/></clipPath>\n<g clip-path=\"url(#panel" << k << ")\">\n";
  }
  for (const auto& l : p.lines) {
    if (l.pts.size() < 2) continue;
    f << "<polyline fill=\"none\" stroke=\"" << l.colour << "\" stroke-width=\"" << l.width << "\""
      << (l.dashed ? " stroke-dasharray=\"5,4\"" : "") << " points=\"";
    for (const auto& q : l.pts)
      if (q.allFinite()) f << X(q.x()) << "," << Y(q.y()) << " ";
    f << "\"/>\n";
  }
  for (const auto& a : p.arrows)
    f << "<line x1=\"" << X(a.from.x()) << "\" y1=\"" << Y(a.from.y()) << "\" x2=\"" << X(a.to.x()) << "\" y2=\""
      << Y(a.to.y()) << "\" stroke=\"" << a.colour << "\" stroke-width=\"1\"/>\n";
  for (const auto& m : p.markers) {
    if (!m.p.allFinite()) continue;
    f << "<circle cx=\"" << X(m.p.x()) << "\" cy=\"" << Y(m.p.y()) << "\" r=\"" << std::max(2.0, m.radius / w.dx * S)
      << "\" " << (m.filled ? "fill=\"" + m.colour + "\"" : "fill=\"none\" stroke=\"" + m.colour + "\"")
      << "/>\n";
  }
  if (p.limits) f << "</g>\n";
  // Legend of the labelled lines (upper left) and notes (lower right).
  int li = 0;
  for (const auto& l : p.lines) {
    if (l.label.empty()) continue;
    const double ly = oy + 14 + 14 * li++;
    f << "<line x1=\"" << ox + 8 << "\" y1=\"" << ly - 4 << "\" x2=\"" << ox + 26 << "\" y2=\"" << ly - 4
      << "\" stroke=\"" << l.colour << "\" stroke-width=\"2\"/><text x=\"" << ox + 30 << "\" y=\"" << ly << "\">"
      << escaped(l.label) << "</text>\n";
  }
  const int nn = static_cast<int>(p.notes.size());
  for (int i = 0; i < nn; ++i)
    f << "<text x=\"" << ox + S - 6 << "\" y=\"" << oy + S - 6 - 14 * (nn - 1 - i) << "\" text-anchor=\"end\">"
      << escaped(p.notes[static_cast<std::size_t>(i)]) << "</text>\n";
  f << "</g>\n";
}

}  // namespace

bool SvgFigure::write(const std::string& path, int S) const {
  // Written under a temporary name and renamed: a killed run leaves the old figure or the new.
  const std::string tmp = cli::temporaryBeside(path);
  std::ofstream f(tmp);
  if (!f) return false;
  const int margin_l = 60, margin_b = 45, margin_t = 40, gap = 30, header = 10;
  const int n = static_cast<int>(panels_.size());
  const int cols = std::max(1, columns_ > 0 ? std::min(columns_, std::max(n, 1)) : n);
  const int rows = std::max(1, (n + cols - 1) / cols);
  const int cell_w = S + margin_l + gap, cell_h = margin_t + S + margin_b;
  const int footer = (scale_colours_.empty() ? 0 : 40) + 16 * static_cast<int>(captions_.size());
  const int W = cols * cell_w + 20;
  const int H = header + rows * cell_h + footer + 30;
  f << std::fixed << std::setprecision(2);
  f << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H
    << "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  f << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  f << "<text x=\"10\" y=\"20\" font-size=\"15\" font-weight=\"bold\">" << escaped(title_) << "</text>\n";
  for (int k = 0; k < n; ++k)
    writePanel(f, panels_[static_cast<std::size_t>(k)], k, 10 + (k % cols) * cell_w + margin_l,
               header + (k / cols) * cell_h + margin_t, S);
  // Footer: the colour scale, then the captions.
  double fy = header + rows * cell_h + 10;
  if (!scale_colours_.empty()) {
    const double w = 200.0 / static_cast<double>(scale_colours_.size());
    for (std::size_t i = 0; i < scale_colours_.size(); ++i)
      f << "<rect x=\"" << 20 + w * static_cast<double>(i) << "\" y=\"" << fy << "\" width=\"" << w + 0.5
        << "\" height=\"14\" fill=\"" << scale_colours_[i] << "\"/>\n";
    f << "<text x=\"20\" y=\"" << fy + 30 << "\">" << escaped(scale_low_) << "</text><text x=\"220\" y=\"" << fy + 30
      << "\" text-anchor=\"end\">" << escaped(scale_high_) << "</text>\n";
    fy += 40;
  }
  for (const auto& c : captions_) {
    f << "<text x=\"20\" y=\"" << fy + 12 << "\">" << escaped(c) << "</text>\n";
    fy += 16;
  }
  f << "</svg>\n";
  return cli::finishTemporary(f, tmp, path);
}

}  // namespace lieservo::plot
