#include "plots.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <stdexcept>

#include <lieservo_plot/svg_figure.hpp>

namespace lieservo::replay {

namespace {

const char* kNames[6] = {"ξ1 = ρx (mm)", "ξ2 = ρy (mm)", "ξ3 = ρz (mm)",
                         "ξ4 = φx (deg)", "ξ5 = φy (deg)", "ξ6 = φz (deg)"};

std::string fmt(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", v);
  return b;
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  const std::size_t k = static_cast<std::size_t>(q * static_cast<double>(v.size() - 1));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

}  // namespace

void writeScatterPlot(const std::string& path, const std::string& title,
                      const std::vector<Eigen::Matrix<double, 6, 1>>& actual,
                      const std::vector<Eigen::Matrix<double, 6, 1>>& predicted,
                      const std::vector<Eigen::Matrix<double, 6, 1>>& precision) {
  const std::size_t n = std::min(actual.size(), predicted.size());
  const bool coloured = precision.size() >= n && n > 0;
  plot::SvgFigure fig(title, 3);
  for (std::size_t c = 0; c < 6; ++c) {
    plot::SvgPanel& P = fig.panel(kNames[c], "actual", "predicted");
    // Axis range: the actual values' range (both axes), 5 % padding.
    double lo = 1e300, hi = -1e300;
    for (std::size_t i = 0; i < n; ++i) {
      lo = std::min(lo, actual[i][c]);
      hi = std::max(hi, actual[i][c]);
    }
    if (!(hi > lo)) {
      lo -= 1.0;
      hi += 1.0;
    }
    const double pad = 0.05 * (hi - lo);
    lo -= pad;
    hi += pad;
    P.limits = std::array<double, 4>{lo, hi, lo, hi};
    P.line({plot::Point(lo, lo), plot::Point(hi, hi)}, "#a0a0a0", 1.0);

    // Colour scale: log σ⁻¹ between its 2nd and 98th percentiles; high precision drawn last.
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), std::size_t{0});
    double llo = 0.0, lhi = 1.0;
    std::vector<double> lp(n, 0.0);
    if (coloured) {
      for (std::size_t i = 0; i < n; ++i) lp[i] = std::log10(std::max(precision[i][c], 1e-12));
      llo = quantile(lp, 0.02);
      lhi = quantile(lp, 0.98);
      if (!(lhi > llo)) lhi = llo + 1.0;
      std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return lp[a] < lp[b]; });
      P.note("1/σ: " + fmt(std::pow(10.0, llo)) + " .. " + fmt(std::pow(10.0, lhi)));
    }
    for (std::size_t i : order)
      P.marker(plot::Point(actual[i][c], predicted[i][c]), 0.0,
               coloured ? plot::heatColour((lp[i] - llo) / (lhi - llo)) : std::string("#145ab4"));
  }
  if (coloured) {
    std::vector<std::string> scale;
    for (int i = 0; i < 50; ++i) scale.push_back(plot::heatColour(i / 49.0));
    fig.colourScale(scale, "low precision", "high");
    fig.caption("colour: predicted precision 1/σ per component (log scale, 2nd–98th percentile); grey line: y = x");
  } else {
    fig.caption("grey line: y = x");
  }
  if (!fig.write(path, 330)) throw std::runtime_error(path + ": cannot write plot");
}

}  // namespace lieservo::replay
