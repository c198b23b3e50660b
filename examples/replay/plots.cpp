#include "plots.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <stdexcept>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace lieservo::replay {

namespace {

constexpr int kPanel = 330;   // plot area, px
constexpr int kMarginL = 58, kMarginB = 44, kMarginT = 30, kMarginR = 16;
constexpr int kCellW = kMarginL + kPanel + kMarginR, kCellH = kMarginT + kPanel + kMarginB;
constexpr int kHeader = 40, kLegend = 40;

const char* kNames[6] = {"xi_1 = rho_x (mm)", "xi_2 = rho_y (mm)", "xi_3 = rho_z (mm)",
                         "xi_4 = phi_x (deg)", "xi_5 = phi_y (deg)", "xi_6 = phi_z (deg)"};

std::string fmt(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", v);
  return b;
}

/// Blue (t = 0) -> cyan -> green -> yellow -> red (t = 1), BGR.
cv::Scalar heat(double t) {
  t = std::clamp(t, 0.0, 1.0);
  const double r = std::clamp(1.5 - std::fabs(4.0 * t - 3.0), 0.0, 1.0);
  const double g = std::clamp(1.5 - std::fabs(4.0 * t - 2.0), 0.0, 1.0);
  const double b = std::clamp(1.5 - std::fabs(4.0 * t - 1.0), 0.0, 1.0);
  return cv::Scalar(255 * b, 255 * g, 255 * r);
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  const std::size_t k = static_cast<std::size_t>(q * static_cast<double>(v.size() - 1));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

}  // namespace

PanelBox scatterPanelBox(int c) {
  return PanelBox{(c % 3) * kCellW + kMarginL, kHeader + (c / 3) * kCellH + kMarginT, kPanel, kPanel};
}

void writeScatterPlot(const std::string& path, const std::string& title,
                      const std::vector<std::array<double, 6>>& actual,
                      const std::vector<std::array<double, 6>>& predicted,
                      const std::vector<std::array<double, 6>>& precision) {
  const std::size_t n = std::min(actual.size(), predicted.size());
  const bool coloured = precision.size() >= n && n > 0;
  cv::Mat img(kHeader + 2 * kCellH + kLegend, 3 * kCellW, CV_8UC3, cv::Scalar(255, 255, 255));
  cv::putText(img, title, cv::Point(10, 27), cv::FONT_HERSHEY_SIMPLEX, 0.65, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);

  for (int c = 0; c < 6; ++c) {
    const PanelBox box = scatterPanelBox(c);
    const int ox = box.x, oy = box.y;
    const auto cs = static_cast<std::size_t>(c);
    // Axis range: the actual values' range (both axes), 5 % padding; predictions beyond are clipped.
    double lo = 1e300, hi = -1e300;
    for (std::size_t i = 0; i < n; ++i) {
      lo = std::min(lo, actual[i][cs]);
      hi = std::max(hi, actual[i][cs]);
    }
    if (!(hi > lo)) {
      lo -= 1.0;
      hi += 1.0;
    }
    const double pad = 0.05 * (hi - lo);
    lo -= pad;
    hi += pad;
    auto px = [&](double v) { return ox + static_cast<int>(std::lround((v - lo) / (hi - lo) * kPanel)); };
    auto py = [&](double v) { return oy + kPanel - static_cast<int>(std::lround((v - lo) / (hi - lo) * kPanel)); };

    cv::rectangle(img, cv::Rect(ox, oy, kPanel, kPanel), cv::Scalar(0, 0, 0), 1);
    cv::line(img, cv::Point(px(lo), py(lo)), cv::Point(px(hi), py(hi)), cv::Scalar(160, 160, 160), 1, cv::LINE_AA);
    // "Nice" ticks: steps of 1, 2 or 5 x 10^k, about four per axis.
    const double raw_step = (hi - lo) / 4.0;
    const double mag = std::pow(10.0, std::floor(std::log10(raw_step)));
    const double step = raw_step / mag < 1.5 ? mag : raw_step / mag < 3.5 ? 2 * mag : raw_step / mag < 7.5 ? 5 * mag : 10 * mag;
    for (double v = std::ceil(lo / step) * step; v <= hi + 1e-9 * step; v += step) {
      const double tv = std::fabs(v) < 1e-9 * step ? 0.0 : v;
      cv::line(img, cv::Point(px(tv), oy + kPanel), cv::Point(px(tv), oy + kPanel + 4), cv::Scalar(0, 0, 0));
      cv::line(img, cv::Point(ox - 4, py(tv)), cv::Point(ox, py(tv)), cv::Scalar(0, 0, 0));
      const std::string label = fmt(tv);
      cv::putText(img, label, cv::Point(px(tv) - 4 * static_cast<int>(label.size()), oy + kPanel + 17),
                  cv::FONT_HERSHEY_PLAIN, 0.9, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
      cv::putText(img, label, cv::Point(ox - 8 - 8 * static_cast<int>(label.size()), py(tv) + 4),
                  cv::FONT_HERSHEY_PLAIN, 0.9, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    }
    cv::putText(img, std::string(kNames[c]), cv::Point(ox + 4, oy - 8), cv::FONT_HERSHEY_SIMPLEX, 0.5,
                cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    cv::putText(img, "actual", cv::Point(ox + kPanel / 2 - 20, oy + kPanel + 36), cv::FONT_HERSHEY_PLAIN, 1.0,
                cv::Scalar(60, 60, 60), 1, cv::LINE_AA);
    cv::putText(img, "pred.", cv::Point(ox + 4, oy + 14), cv::FONT_HERSHEY_PLAIN, 1.0, cv::Scalar(60, 60, 60), 1,
                cv::LINE_AA);

    // Colour scale: log σ⁻¹ between its 2nd and 98th percentiles; high precision drawn last.
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), std::size_t{0});
    double llo = 0.0, lhi = 1.0;
    std::vector<double> lp(n, 0.0);
    if (coloured) {
      for (std::size_t i = 0; i < n; ++i) lp[i] = std::log10(std::max(precision[i][cs], 1e-12));
      llo = quantile(lp, 0.02);
      lhi = quantile(lp, 0.98);
      if (!(lhi > llo)) lhi = llo + 1.0;
      std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return lp[a] < lp[b]; });
    }
    cv::Mat roi = img(cv::Rect(ox + 1, oy + 1, kPanel - 1, kPanel - 1));
    for (std::size_t i : order) {
      const cv::Scalar col = coloured ? heat((lp[i] - llo) / (lhi - llo)) : cv::Scalar(180, 90, 20);
      const cv::Point p(px(actual[i][cs]) - ox - 1, py(predicted[i][cs]) - oy - 1);
      cv::circle(roi, p, 2, col, cv::FILLED, cv::LINE_AA);  // clipped to the panel by the ROI
    }
    if (coloured) {
      cv::putText(img, "1/sigma: " + fmt(std::pow(10.0, llo)) + " .. " + fmt(std::pow(10.0, lhi)),
                  cv::Point(ox + kPanel - 150, oy + kPanel - 6), cv::FONT_HERSHEY_PLAIN, 0.85, cv::Scalar(0, 0, 0),
                  1, cv::LINE_AA);
    }
  }
  // Legend.
  const int ly = kHeader + 2 * kCellH + 8;
  if (coloured) {
    for (int i = 0; i < 200; ++i)
      cv::line(img, cv::Point(20 + i, ly), cv::Point(20 + i, ly + 14), heat(i / 199.0));
    cv::putText(img, "low precision", cv::Point(20, ly + 30), cv::FONT_HERSHEY_PLAIN, 1.0, cv::Scalar(0, 0, 0), 1,
                cv::LINE_AA);
    cv::putText(img, "high", cv::Point(190, ly + 30), cv::FONT_HERSHEY_PLAIN, 1.0, cv::Scalar(0, 0, 0), 1,
                cv::LINE_AA);
    cv::putText(img, "colour: predicted precision 1/sigma per component (log scale, 2-98th percentile); grey line: y = x",
                cv::Point(240, ly + 12), cv::FONT_HERSHEY_PLAIN, 1.0, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  } else {
    cv::putText(img, "grey line: y = x", cv::Point(20, ly + 12), cv::FONT_HERSHEY_PLAIN, 1.0, cv::Scalar(0, 0, 0), 1,
                cv::LINE_AA);
  }
  bool ok = false;
  try {
    ok = cv::imwrite(path, img);
  } catch (const cv::Exception& e) {
    throw std::runtime_error(path + ": cannot write plot: " + e.what());
  }
  if (!ok) throw std::runtime_error(path + ": cannot write plot");
}

}  // namespace lieservo::replay
