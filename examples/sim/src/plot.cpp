// SVG plots and CSV logs (see lieservo_sim/plot.hpp).
#include "lieservo_sim/plot.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <sstream>

namespace lieservo::sim {

namespace {
double niceStep(double range) {
  const double raw = range / 6;
  const double p = std::pow(10.0, std::floor(std::log10(std::max(raw, 1e-12))));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * p >= raw) return m * p;
  return 10 * p;
}
}  // namespace

bool SvgFigure::write(const std::string& path, int S) const {
  std::ofstream f(path);
  if (!f) return false;
  const int margin_l = 60, margin_b = 45, margin_t = 40, gap = 30;
  const int W = int(panels_.size()) * (S + margin_l + gap) + 20;
  const int H = S + margin_b + margin_t + 30;
  f << std::fixed << std::setprecision(2);
  f << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H
    << "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  f << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  f << "<text x=\"10\" y=\"20\" font-size=\"15\" font-weight=\"bold\">" << title_ << "</text>\n";
  for (std::size_t k = 0; k < panels_.size(); ++k) {
    const SvgPanel& p = panels_[k];
    double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
    auto grow = [&](const Vec2& q) {
      if (!q.allFinite()) return;
      x0 = std::min(x0, q.x());
      x1 = std::max(x1, q.x());
      y0 = std::min(y0, q.y());
      y1 = std::max(y1, q.y());
    };
    for (const auto& l : p.lines)
      for (const auto& q : l.pts) grow(q);
    for (const auto& m : p.markers) {
      grow(m.p + Vec2(m.radius, m.radius));
      grow(m.p - Vec2(m.radius, m.radius));
    }
    for (const auto& a : p.arrows) {
      grow(a.from);
      grow(a.to);
    }
    if (!(x1 >= x0)) x0 = -1, x1 = 1, y0 = -1, y1 = 1;
    double dx = std::max(x1 - x0, 1e-6), dy = std::max(y1 - y0, 1e-6);
    x0 -= 0.05 * dx, x1 += 0.05 * dx, y0 -= 0.05 * dy, y1 += 0.05 * dy;
    dx = x1 - x0, dy = y1 - y0;
    if (p.equal_aspect) {
      const double d = std::max(dx, dy);
      x0 -= (d - dx) / 2, x1 = x0 + d, y0 -= (d - dy) / 2, y1 = y0 + d;
      dx = dy = d;
    }
    const double ox = 10 + k * (S + margin_l + gap) + margin_l, oy = margin_t;
    auto X = [&](double x) { return ox + (x - x0) / dx * S; };
    auto Y = [&](double y) { return oy + S - (y - y0) / dy * S; };
    f << "<g>\n<rect x=\"" << ox << "\" y=\"" << oy << "\" width=\"" << S << "\" height=\"" << S
      << "\" fill=\"none\" stroke=\"#444\"/>\n";
    const double sx = niceStep(dx), sy = niceStep(dy);
    for (double t = std::ceil(x0 / sx) * sx; t <= x1; t += sx)
      f << "<line x1=\"" << X(t) << "\" y1=\"" << oy << "\" x2=\"" << X(t) << "\" y2=\"" << oy + S
        << "\" stroke=\"#eee\"/><text x=\"" << X(t) << "\" y=\"" << oy + S + 15 << "\" text-anchor=\"middle\">"
        << std::setprecision(0) << t << std::setprecision(2) << "</text>\n";
    for (double t = std::ceil(y0 / sy) * sy; t <= y1; t += sy)
      f << "<line x1=\"" << ox << "\" y1=\"" << Y(t) << "\" x2=\"" << ox + S << "\" y2=\"" << Y(t)
        << "\" stroke=\"#eee\"/><text x=\"" << ox - 5 << "\" y=\"" << Y(t) + 4 << "\" text-anchor=\"end\">"
        << std::setprecision(0) << t << std::setprecision(2) << "</text>\n";
    f << "<text x=\"" << ox + S / 2.0 << "\" y=\"" << oy - 8 << "\" text-anchor=\"middle\" font-weight=\"bold\">"
      << p.title << "</text>\n";
    f << "<text x=\"" << ox + S / 2.0 << "\" y=\"" << oy + S + 35 << "\" text-anchor=\"middle\">" << p.xlabel
      << "</text>\n";
    f << "<text transform=\"translate(" << ox - 45 << "," << oy + S / 2.0 << ") rotate(-90)\" text-anchor=\"middle\">"
      << p.ylabel << "</text>\n";
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
    for (const auto& m : p.markers)
      f << "<circle cx=\"" << X(m.p.x()) << "\" cy=\"" << Y(m.p.y()) << "\" r=\"" << std::max(2.0, m.radius / dx * S)
        << "\" " << (m.filled ? "fill=\"" + m.colour + "\"" : "fill=\"none\" stroke=\"" + m.colour + "\"")
        << "/>\n";
    // legend
    int li = 0;
    for (const auto& l : p.lines) {
      if (l.label.empty()) continue;
      const double ly = oy + 14 + 14 * li++;
      f << "<line x1=\"" << ox + 8 << "\" y1=\"" << ly - 4 << "\" x2=\"" << ox + 26 << "\" y2=\"" << ly - 4
        << "\" stroke=\"" << l.colour << "\" stroke-width=\"2\"/><text x=\"" << ox + 30 << "\" y=\"" << ly << "\">"
        << l.label << "</text>\n";
    }
    f << "</g>\n";
  }
  f << "</svg>\n";
  return bool(f);
}

bool CsvWriter::open(const std::string& path, const std::vector<std::string>& header) {
  out_.open(path);
  if (!out_) return false;
  for (std::size_t i = 0; i < header.size(); ++i) out_ << (i ? "," : "") << header[i];
  out_ << "\n";
  out_ << std::setprecision(7);
  return true;
}

void CsvWriter::row(const std::vector<double>& v) {
  if (!out_.is_open()) return;
  for (std::size_t i = 0; i < v.size(); ++i) out_ << (i ? "," : "") << v[i];
  out_ << "\n";
}

bool makeDirectories(const std::string& path) {
  std::error_code ec;
  std::filesystem::create_directories(path, ec);
  return !ec && std::filesystem::is_directory(path, ec);
}

}  // namespace lieservo::sim
