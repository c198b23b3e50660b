// examples/replay/plots.hpp — predicted-vs-actual scatter plots, one panel per ξ
// component, points coloured by predicted precision σ⁻¹ (red = high, blue = low), like
// the paper's fig:nn_pose_shear_estimate_performance / fig:bayes_filter_performance.
#pragma once

#include <array>
#include <string>
#include <vector>

namespace lieservo::replay {

/// A panel's plot area in the written image (pixels; the 1-px frame included).
struct PanelBox {
  int x = 0, y = 0, width = 0, height = 0;
};

/// Where writeScatterPlot draws the panel of ξ component c (0..5): row c / 3, column c % 3.
PanelBox scatterPanelBox(int c);

/// Writes a PNG (cv::imwrite). `precision` may be empty (single colour, e.g. the CNN).
/// All vectors in mm and deg (precision in 1/mm, 1/deg). The markers are the only saturated
/// colours inside a panel (frame, ticks, labels and the diagonal are grey or black). Throws std::runtime_error when
/// the file cannot be written.
void writeScatterPlot(const std::string& path, const std::string& title,
                      const std::vector<std::array<double, 6>>& actual,
                      const std::vector<std::array<double, 6>>& predicted,
                      const std::vector<std::array<double, 6>>& precision);

}  // namespace lieservo::replay
