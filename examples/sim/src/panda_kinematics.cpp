// lieservo_sim/panda_kinematics.cpp — see panda_kinematics.hpp.
#include <lieservo_sim/panda_kinematics.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

namespace lieservo::sim::panda {

Eigen::Matrix4d linkTransform(const Link& l, double theta) {
  const double ca = std::cos(l.alpha), sa = std::sin(l.alpha);
  const double ct = std::cos(theta), st = std::sin(theta);
  Eigen::Matrix4d T;
  T << ct, -st, 0.0, l.a,             //
      st * ca, ct * ca, -sa, -sa * l.d,  //
      st * sa, ct * sa, ca, ca * l.d,    //
      0.0, 0.0, 0.0, 1.0;
  return T;
}

namespace {

/// The frames of joints 1–7 (each origin on its joint's axis z) and the flange.
std::array<Eigen::Matrix4d, kJoints + 1> frames(const Joints& q) {
  std::array<Eigen::Matrix4d, kJoints + 1> T;
  Eigen::Matrix4d X = Eigen::Matrix4d::Identity();
  for (int i = 0; i <= kJoints; ++i) {
    X = X * linkTransform(kLinks[std::size_t(i)], i < kJoints ? q[i] : 0.0);
    T[std::size_t(i)] = X;
  }
  return T;
}

}  // namespace

Eigen::Matrix4d flange(const Joints& q) { return frames(q)[kJoints]; }

Jacobian jacobian(const Joints& q) {
  const auto T = frames(q);
  const Eigen::Vector3d p_e = T[kJoints].block<3, 1>(0, 3);
  Jacobian J;
  for (int i = 0; i < kJoints; ++i) {
    const Eigen::Vector3d z = T[std::size_t(i)].block<3, 1>(0, 2);
    const Eigen::Vector3d p = T[std::size_t(i)].block<3, 1>(0, 3);
    J.block<3, 1>(0, i) = z.cross(p_e - p);
    J.block<3, 1>(3, i) = z;
  }
  return J;
}

double manipulability(const Jacobian& J) {
  return std::sqrt(std::max(0.0, (J * J.transpose()).determinant()));
}

double jointLimitMargin(const Joints& q) {
  return std::min((q - lowerLimits()).minCoeff(), (upperLimits() - q).minCoeff());
}

ResolvedRate resolvedRate(const Joints& q, const Twist& v, const ResolvedRateOptions& options) {
  ResolvedRate r;
  const Jacobian J = jacobian(q);
  const Eigen::Matrix<double, 6, 6> JJt = J * J.transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eig(JJt, Eigen::EigenvaluesOnly);
  r.sigma_min = std::sqrt(std::max(0.0, eig.eigenvalues()[0]));
  // Damping fades in below the band (Nakamura's rule): exact inverse kinematics elsewhere.
  if (r.sigma_min < options.singular_band) {
    const double f = r.sigma_min / options.singular_band;
    r.lambda = options.damping * std::sqrt(1.0 - f * f);
    // J⁺v = Σ v_i (u_iᵀv / σ_i): a twist component along a vanishing σ_i needs unbounded speed.
    const Eigen::JacobiSVD<Jacobian> svd(J, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Joints exact = Joints::Zero();
    for (int i = 0; i < 6; ++i) {
      const double c = svd.matrixU().col(i).dot(v);
      if (c == 0.0) continue;
      const double s = svd.singularValues()[i];
      if (s == 0.0) {
        r.exact_speed_ratio = std::numeric_limits<double>::infinity();
        break;
      }
      exact += svd.matrixV().col(i) * (c / s);
    }
    if (r.exact_speed_ratio == 0.0) r.exact_speed_ratio = (exact.cwiseAbs().array() / velocityLimits().array()).maxCoeff();
  }
  const Eigen::Matrix<double, 6, 6> A = JJt + r.lambda * r.lambda * Eigen::Matrix<double, 6, 6>::Identity();
  r.dq = J.transpose() * A.ldlt().solve(v);
  const double over = (r.dq.cwiseAbs().array() / velocityLimits().array()).maxCoeff();
  if (over > 1.0) {  // the whole motion slower, not a different direction
    r.scale = 1.0 / over;
    r.dq *= r.scale;
  }
  return r;
}

}  // namespace lieservo::sim::panda
