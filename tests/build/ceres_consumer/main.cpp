// Fits an SE(3) pose to a measured one with Ceres on lieservo's SE3Manifold (residual
// lminus(X, Z), autodiff through lieservo's groups on Jets), started at the identity half a turn
// away: the estimate must reach the measurement.
#include <lieservo_ceres/manifold.hpp>

#include <ceres/ceres.h>

#include <cstdio>

namespace {

// r = lminus(X, Z): the left-perturbation error of the estimate X against a measurement Z.
struct PoseError {
  lieservo::SE3<double> Z;
  template <class T>
  bool operator()(const T* x, T* r) const {
    const lieservo::SE3<T> X = lieservo::ceres_adapter::AmbientOf<lieservo::SE3<double>>::read(x);
    Eigen::Map<Eigen::Matrix<T, 6, 1>> res(r);
    res = lieservo::lminus(X, Z.template cast<T>());
    return true;
  }
};

}  // namespace

int main() {
  using SE3d = lieservo::SE3<double>;
  const SE3d truth = SE3d::exp((SE3d::Tangent() << 10, -20, 30, 1.2, -0.8, 1.0).finished());
  double x[7] = {1, 0, 0, 0, 0, 0, 0};  // start at the identity
  ceres::Problem problem;
  problem.AddParameterBlock(x, 7, new lieservo::ceres_adapter::SE3Manifold);
  problem.AddResidualBlock(new ceres::AutoDiffCostFunction<PoseError, 6, 7>(new PoseError{truth}), nullptr, x);
  ceres::Solver::Options options;
  options.function_tolerance = options.gradient_tolerance = 1e-16;
  options.parameter_tolerance = 1e-14;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  const SE3d X = lieservo::ceres_adapter::AmbientOf<SE3d>::read(x);
  const double err = lieservo::lminus(X, truth).norm();
  std::printf("lieservo ceres consumer: %s, |X - truth| = %.3g\n", summary.IsSolutionUsable() ? "solved" : "failed", err);
  return summary.IsSolutionUsable() && err < 1e-9 ? 0 : 1;
}
