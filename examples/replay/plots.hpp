// examples/replay/plots.hpp — predicted-vs-actual scatter plots, one panel per ξ
// component, points coloured by predicted precision σ⁻¹ (red = high, blue = low), like
// the paper's fig:nn_pose_shear_estimate_performance / fig:bayes_filter_performance. Drawn as
// SVG with the examples' figure writer (lieservo_plot/svg_figure.hpp).
#pragma once

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace lieservo::replay {

/// Writes an SVG: six panels (ρ1..ρ3, φ1..φ3 in two rows), each on the actual values' range
/// (both axes, 5 % padding; predictions beyond it are clipped), with the line y = x.
/// `precision` may be empty (single colour, e.g. the CNN). All vectors in mm and deg
/// (precision in 1/mm, 1/deg). The markers are the only saturated colours inside a panel
/// (frame, grid, labels and the diagonal are grey or black). Throws std::runtime_error when
/// the file cannot be written.
void writeScatterPlot(const std::string& path, const std::string& title,
                      const std::vector<Eigen::Matrix<double, 6, 1>>& actual,
                      const std::vector<Eigen::Matrix<double, 6, 1>>& predicted,
                      const std::vector<Eigen::Matrix<double, 6, 1>>& precision);

}  // namespace lieservo::replay
