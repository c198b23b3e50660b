// lieservo_ceres/smoother.hpp — the fixed-interval smoother beside the paper's filter: the whole
// trajectory of contact poses X_0 … X_{n−1} on SE(3) as one nonlinear least-squares problem in Ceres,
// under the filter's own models (Lloyd & Lepora, Section 3.2):
//
//   observation k   Z_k ~ N_c(X_k, Σ_k)           r = L_k⁻¹ ln(X_k Z_k⁻¹)^∨
//   motion k ≥ 1    X_k = exp(φ_k^) T_k X_{k−1},  r = L_φ⁻¹ ln(X_k (T_k X_{k−1})⁻¹)^∨
//                   φ_k ~ N(0, Σφ)
//
// Z_k and Σ_k come from the GDN's μ, σ by eq. 14 (eq:se3_inverse_transform); the motion model is
// eq. 23 (eqn:se3_filter_exp_state_trans_model) and its noise eq. 24 (eqn:se3_filter_exp_state_trans_cov).
//
// with Σ = L Lᵀ (Cholesky), so that each residual is whitened. The filter (Algorithm 2) uses the
// same two terms causally; the smoother uses every frame for every pose, which makes it the best
// estimate the two models allow. Residuals go through lieservo's lminus; the derivatives come
// from Jets (ceres::AutoDiffCostFunction) or from the closed-form Jacobians of lminus
// (groups/perturbation.hpp), chosen by SmootherOptions::jacobians. The poses live on
// SE3Manifold (manifold.hpp, left perturbation).
//
// Bad input gets a Status and the frame it concerns, and leaves the caller's result untouched:
// a missing frame (fewer observations than motions or the reverse, or a non-finite one), a
// covariance that is not SPD, a motion that is not a rigid transform, a solver that does not
// converge.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <string>
#include <vector>

#include <ceres/ceres.h>

#include <Eigen/Core>

#include <lieservo/estimation/concentrated_gaussian.hpp>
#include <lieservo/estimation/detail/linalg.hpp>
#include <lieservo/groups.hpp>
#include <lieservo_ceres/manifold.hpp>

namespace lieservo::ceres_adapter {

struct SmootherOptions {
  enum class Jacobians { autodiff, closed_form };
  Jacobians jacobians = Jacobians::autodiff;
  int max_iterations = 100;           ///< Levenberg–Marquardt iterations
  double function_tolerance = 1e-12;  ///< relative cost decrease that counts as converged
  double gradient_tolerance = 1e-12;
  double parameter_tolerance = 1e-12;
  int threads = 1;
};

struct SmootherReport {
  Status status = Status::ok;
  long frame = -1;          ///< the frame the error concerns (−1: none, or the whole sequence)
  std::string message;      ///< what went wrong, naming the frame; empty when ok
  int iterations = 0;       ///< Levenberg–Marquardt iterations taken
  double seconds = 0.0;     ///< wall time of ceres::Solve
  double initial_cost = 0.0, final_cost = 0.0;  ///< ½ Σ ‖r‖²
};

namespace detail {

/// L⁻¹ of the Cholesky factor of an SPD 6×6 (the whitening of a residual with that covariance):
/// the library's checked factor, the one validate() accepted.
inline Eigen::Matrix<double, 6, 6> whitening(const Eigen::Matrix<double, 6, 6>& S) {
  Eigen::Matrix<double, 6, 6> L;
  (void)lieservo::detail::choleskyChecked(S, L);  // checkInputs refused what it would refuse
  return L.triangularView<Eigen::Lower>().solve(Eigen::Matrix<double, 6, 6>::Identity());
}

/// r = W ln(X Z⁻¹)^∨ for the pose block x and a fixed Z (autodiff through Jets).
struct ObservationResidual {
  SE3<double> Z;
  Eigen::Matrix<double, 6, 6> W;
  template <class T>
  bool operator()(const T* x, T* r) const {
    const SE3<T> X = AmbientOf<SE3<double>>::read(x);
    Eigen::Map<Eigen::Matrix<T, 6, 1>> res(r);
    res = W.cast<T>() * lminus(X, Z.template cast<T>());
    return true;
  }
};

/// r = W ln(X_k (T X_{k−1})⁻¹)^∨ for the blocks x_{k−1}, x_k (autodiff through Jets).
struct MotionResidual {
  SE3<double> T_k;
  Eigen::Matrix<double, 6, 6> W;
  template <class T>
  bool operator()(const T* x_prev, const T* x, T* r) const {
    const SE3<T> prev = AmbientOf<SE3<double>>::read(x_prev);
    const SE3<T> X = AmbientOf<SE3<double>>::read(x);
    Eigen::Map<Eigen::Matrix<T, 6, 1>> res(r);
    res = W.cast<T>() * lminus(X, T_k.template cast<T>() * prev);
    return true;
  }
};

/// A tangent-space Jacobian (∂r/∂δ for X ← exp(δ^) X) as Ceres wants it, against the block's 7
/// ambient parameters: times Minus's Jacobian, so that Ceres's product with Plus's gives it back.
inline void toAmbient(const Eigen::Matrix<double, 6, 6>& J_tangent, const double* x, double* J) {
  Eigen::Matrix<double, 6, 7, Eigen::RowMajor> M;
  AmbientOf<SE3<double>>::minusJacobian(x, M.data());
  Eigen::Map<Eigen::Matrix<double, 6, 7, Eigen::RowMajor>> out(J);
  out = J_tangent * M;
}

/// The observation residual with lminus's closed-form Jacobian, ∂τ/∂X = J_l(τ)⁻¹
/// (groups/perturbation.hpp).
class ObservationCost final : public ::ceres::SizedCostFunction<6, 7> {
 public:
  ObservationCost(const SE3<double>& Z, const Eigen::Matrix<double, 6, 6>& W) : Z_(Z), W_(W) {}
  bool Evaluate(double const* const* p, double* r, double** J) const override {
    const SE3<double>::Tangent tau = lminus(AmbientOf<SE3<double>>::read(p[0]), Z_);
    Eigen::Map<Eigen::Matrix<double, 6, 1>> res(r);
    res = W_ * tau;
    if (J != nullptr && J[0] != nullptr) toAmbient(W_ * SE3<double>::leftJacobianInverse(tau), p[0], J[0]);
    return true;
  }

 private:
  SE3<double> Z_;
  Eigen::Matrix<double, 6, 6> W_;
};

/// The motion residual with lminus's closed-form Jacobians: ∂τ/∂X_k = J_l(τ)⁻¹, and through
/// Y = T X_{k−1} (∂Y/∂X_{k−1} = Ad(T)) ∂τ/∂X_{k−1} = −J_r(τ)⁻¹ Ad(T).
class MotionCost final : public ::ceres::SizedCostFunction<6, 7, 7> {
 public:
  MotionCost(const SE3<double>& T, const Eigen::Matrix<double, 6, 6>& W) : T_(T), Ad_T_(T.Ad()), W_(W) {}
  bool Evaluate(double const* const* p, double* r, double** J) const override {
    SE3<double>::Jacobian J_X, J_Y;
    const SE3<double>::Tangent tau =
        lminus(AmbientOf<SE3<double>>::read(p[1]), T_ * AmbientOf<SE3<double>>::read(p[0]), J_X, J_Y);
    Eigen::Map<Eigen::Matrix<double, 6, 1>> res(r);
    res = W_ * tau;
    if (J != nullptr && J[0] != nullptr) toAmbient(W_ * J_Y * Ad_T_, p[0], J[0]);
    if (J != nullptr && J[1] != nullptr) toAmbient(W_ * J_X, p[1], J[1]);
    return true;
  }

 private:
  SE3<double> T_;
  SE3<double>::Jacobian Ad_T_;
  Eigen::Matrix<double, 6, 6> W_;
};

inline void write(const SE3<double>& X, double* a) {
  const Eigen::Quaterniond q = X.so3().unitQuaternion();
  a[0] = q.w(), a[1] = q.x(), a[2] = q.y(), a[3] = q.z();
  for (int i = 0; i < 3; ++i) a[4 + i] = X.translation()[i];
}

inline SmootherReport refuse(Status s, long frame, const std::string& what) {
  SmootherReport r;
  r.status = s;
  r.frame = frame;
  r.message = (frame >= 0 ? "frame " + std::to_string(frame) + ": " : std::string()) + what + " (" + describe(s) + ")";
  return r;
}

/// The first frame whose inputs cannot be used, as a refusal; ok when every frame is usable.
inline SmootherReport checkInputs(const std::vector<ConcentratedGaussian<SE3<double>>>& obs,
                                  const std::vector<SE3<double>>& motions, const SE3<double>::Jacobian& Q) {
  if (obs.empty()) return refuse(Status::invalid_argument, -1, "an empty sequence");
  if (obs.size() != motions.size()) {
    const std::size_t k = std::min(obs.size(), motions.size());
    return refuse(Status::invalid_argument, static_cast<long>(k),
                  obs.size() < motions.size() ? "missing: no observation for this motion" : "missing: no motion for this observation");
  }
  if (const Status s = checkCovariance(Q); s != Status::ok) return refuse(s, -1, "the process noise Σφ");
  for (std::size_t k = 0; k < obs.size(); ++k) {
    const long f = static_cast<long>(k);
    if (!obs[k].mean.matrix().allFinite() || !obs[k].covariance.allFinite())
      return refuse(Status::non_finite_input, f, "missing: the observation is not finite");
    if (const Status s = validate(obs[k]); s != Status::ok) return refuse(s, f, "the observation");
    if (k > 0 && !motions[k].matrix().allFinite()) return refuse(Status::non_finite_input, f, "missing: the motion is not finite");
    if (const Status s = validateElement(motions[k]); k > 0 && s != Status::ok) return refuse(s, f, "the motion");
  }
  return {};
}

}  // namespace detail

/// Smooths the sequence: on success `poses` holds the MAP trajectory X_0 … X_{n−1}; on any error
/// it is left as it was, and the report names the status and the frame. `observations[k]`: the
/// GDN's estimate at frame k as a concentrated Gaussian (eq. 14); `motions[k]`, k ≥ 1: the known
/// sensor motion T_k between frames k−1 and k (motions[0] is not used); `process_noise`: Σφ.
/// `initial`: the starting trajectory (the observations' means when empty).
inline SmootherReport smooth(const std::vector<ConcentratedGaussian<SE3<double>>>& observations,
                             const std::vector<SE3<double>>& motions, const SE3<double>::Jacobian& process_noise,
                             std::vector<SE3<double>>& poses, const SmootherOptions& options = {},
                             const std::vector<SE3<double>>& initial = {}) {
  SmootherReport report = detail::checkInputs(observations, motions, process_noise);
  if (report.status != Status::ok) return report;
  const std::size_t n = observations.size();
  if (!initial.empty() && initial.size() != n)
    return detail::refuse(Status::invalid_argument, static_cast<long>(std::min(n, initial.size())),
                          "the initial trajectory has a different length");
  std::vector<double> x(7 * n);
  for (std::size_t k = 0; k < n; ++k) detail::write(initial.empty() ? observations[k].mean : initial[k], &x[7 * k]);

  ::ceres::Problem::Options po;
  po.manifold_ownership = ::ceres::DO_NOT_TAKE_OWNERSHIP;  // one manifold for every block
  ::ceres::Problem problem(po);
  SE3Manifold manifold;
  const bool autodiff = options.jacobians == SmootherOptions::Jacobians::autodiff;
  const Eigen::Matrix<double, 6, 6> W_motion = detail::whitening(process_noise);
  for (std::size_t k = 0; k < n; ++k) {
    double* xk = &x[7 * k];
    problem.AddParameterBlock(xk, 7, &manifold);
    const Eigen::Matrix<double, 6, 6> W = detail::whitening(observations[k].covariance);
    ::ceres::CostFunction* obs =
        autodiff ? static_cast<::ceres::CostFunction*>(new ::ceres::AutoDiffCostFunction<detail::ObservationResidual, 6, 7>(
                       new detail::ObservationResidual{observations[k].mean, W}))
                 : new detail::ObservationCost(observations[k].mean, W);
    problem.AddResidualBlock(obs, nullptr, xk);
    if (k == 0) continue;
    ::ceres::CostFunction* motion =
        autodiff ? static_cast<::ceres::CostFunction*>(new ::ceres::AutoDiffCostFunction<detail::MotionResidual, 6, 7, 7>(
                       new detail::MotionResidual{motions[k], W_motion}))
                 : new detail::MotionCost(motions[k], W_motion);
    problem.AddResidualBlock(motion, nullptr, &x[7 * (k - 1)], xk);
  }

  ::ceres::Solver::Options so;
  so.linear_solver_type = ::ceres::SPARSE_NORMAL_CHOLESKY;  // a chain: block-tridiagonal normal equations
  so.max_num_iterations = options.max_iterations;
  so.function_tolerance = options.function_tolerance;
  so.gradient_tolerance = options.gradient_tolerance;
  so.parameter_tolerance = options.parameter_tolerance;
  so.num_threads = options.threads;
  so.logging_type = ::ceres::SILENT;
  ::ceres::Solver::Summary summary;
  const auto t0 = std::chrono::steady_clock::now();
  ::ceres::Solve(so, &problem, &summary);
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  report.iterations = static_cast<int>(summary.iterations.size()) - 1;  // iteration 0 is the start
  report.initial_cost = summary.initial_cost;
  report.final_cost = summary.final_cost;
  if (summary.termination_type != ::ceres::CONVERGENCE) {
    // Which frame: the one whose observation residual is largest where the solver stopped.
    long worst = 0;
    double worst_norm = -1.0;
    for (std::size_t k = 0; k < n; ++k) {
      const double e = lminus(ceres_adapter::AmbientOf<SE3<double>>::read(&x[7 * k]), observations[k].mean).norm();
      if (e > worst_norm) worst_norm = e, worst = static_cast<long>(k);
    }
    const SmootherReport refused = detail::refuse(Status::not_converged, worst,
                                                  "the largest observation residual where the solver stopped after " +
                                                      std::to_string(report.iterations) + " iterations (" + summary.message + ")");
    report.status = refused.status;
    report.frame = refused.frame;
    report.message = refused.message;
    return report;
  }
  std::vector<SE3<double>> out(n);
  for (std::size_t k = 0; k < n; ++k) out[k] = AmbientOf<SE3<double>>::read(&x[7 * k]);
  poses.swap(out);
  return report;
}

}  // namespace lieservo::ceres_adapter
