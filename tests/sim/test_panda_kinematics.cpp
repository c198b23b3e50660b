// The simulated Panda's kinematics (examples/sim panda_kinematics.hpp) against an independent
// statement of the same published chain (franka_description's URDF form: a fixed offset and
// roll-pitch-yaw per joint, then the joint's rotation about z), central differences, and the
// datasheet's limits. Bounds written before the first run.
#include <catch2/catch.hpp>

#include <cmath>

#include <Eigen/Geometry>

#include <lieservo/sampling/random.hpp>
#include <lieservo_sim/panda_kinematics.hpp>

#include "test_support.hpp"

using namespace lieservo::sim::panda;

namespace {

constexpr double kPi = 3.14159265358979323846;

/// The URDF form: joint i's frame is Trans(xyz_i) · Rot_x(roll_i) in its parent, then Rot_z(q_i).
Eigen::Matrix4d urdfFlange(const Joints& q) {
  struct Origin {
    double x, y, z, roll;
  };
  const Origin o[8] = {{0, 0, 0.333, 0},        {0, 0, 0, -kPi / 2},       {0, -0.316, 0, kPi / 2},
                       {0.0825, 0, 0, kPi / 2}, {-0.0825, 0.384, 0, -kPi / 2}, {0, 0, 0, kPi / 2},
                       {0.088, 0, 0, kPi / 2},  {0, 0, 0.107, 0}};
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  for (int i = 0; i < 8; ++i) {
    X.translate(Eigen::Vector3d(o[i].x, o[i].y, o[i].z));
    X.rotate(Eigen::AngleAxisd(o[i].roll, Eigen::Vector3d::UnitX()));
    if (i < 7) X.rotate(Eigen::AngleAxisd(q[i], Eigen::Vector3d::UnitZ()));
  }
  return X.matrix();
}

Joints randomJoints(lieservo::sampling::Rng& rng) {
  Joints q;
  for (int i = 0; i < kJoints; ++i) q[i] = lieservo::sampling::uniform(rng, lowerLimits()[i], upperLimits()[i]);
  return q;
}

}  // namespace

TEST_CASE("panda: the flange at the zero and ready configurations", "[robot][panda]") {
  // q = 0: the flange 0.088 m forward and 0.333 + 0.316 + 0.384 − 0.107 = 0.926 m up, pointing down.
  Eigen::Matrix4d expected = Eigen::Matrix4d::Identity();
  expected.topLeftCorner<3, 3>() = Eigen::Vector3d(1, -1, -1).asDiagonal();
  expected.block<3, 1>(0, 3) = Eigen::Vector3d(0.088, 0, 0.926);
  CHECK((flange(Joints::Zero()) - expected).cwiseAbs().maxCoeff() <= 1e-12);

  // Ready: in the x-z plane, pointing down, joint 7 turning the flange by −π/4 about its axis.
  const Eigen::Matrix4d T = flange(readyPose());
  CHECK(std::abs(T(1, 3)) <= 1e-9);
  CHECK(T(0, 3) == Approx(0.3069).margin(5e-4));
  CHECK(T(2, 3) == Approx(0.5903).margin(5e-4));
  CHECK(T.block<3, 1>(0, 2).isApprox(Eigen::Vector3d(0, 0, -1), 1e-9));
  CHECK(jointLimitMargin(readyPose()) == Approx(3.0718 - 3 * kPi / 4).margin(1e-9));  // joint 4, from its lower limit
  CHECK(manipulability(jacobian(readyPose())) >= 0.01);
  CHECK(manipulability(jacobian(Joints::Zero())) <= 1e-6);  // joints 1, 3 and 5 coaxial
}

TEST_CASE("panda: the DH chain equals the URDF form of the same parameters", "[robot][panda]") {
  lieservo::sampling::Rng rng(20261127);
  const long n = lieservo::test::scaledCount(100000, 10000);
  double worst = 0;
  for (long k = 0; k < n; ++k) {
    const Joints q = randomJoints(rng);
    worst = std::max(worst, (flange(q) - urdfFlange(q)).cwiseAbs().maxCoeff());
  }
  INFO("worst entry difference " << worst);
  CHECK(worst <= 1e-13);
}

TEST_CASE("panda: the Jacobian against central differences", "[robot][panda]") {
  lieservo::sampling::Rng rng(7);
  const long n = lieservo::test::scaledCount(100000, 10000);
  const double h = 1e-6;
  double worst = 0;
  for (long k = 0; k < n; ++k) {
    const Joints q = randomJoints(rng);
    const Jacobian J = jacobian(q);
    for (int i = 0; i < kJoints; ++i) {
      Joints qp = q, qm = q;
      qp[i] += h;
      qm[i] -= h;
      const Eigen::Matrix4d Tp = flange(qp), Tm = flange(qm);
      const Eigen::Vector3d v = (Tp.block<3, 1>(0, 3) - Tm.block<3, 1>(0, 3)) / (2 * h);
      // ω in {O}: R(q+h) R(q−h)ᵀ = exp(2h ω^).
      const Eigen::Matrix3d dR = Tp.topLeftCorner<3, 3>() * Tm.topLeftCorner<3, 3>().transpose();
      const Eigen::AngleAxisd aa(dR);
      const Eigen::Vector3d w = aa.angle() * aa.axis() / (2 * h);
      worst = std::max(worst, (J.block<3, 1>(0, i) - v).cwiseAbs().maxCoeff());
      worst = std::max(worst, (J.block<3, 1>(3, i) - w).cwiseAbs().maxCoeff());
    }
  }
  INFO("worst Jacobian entry error " << worst);
  CHECK(worst <= 1e-8);
}

TEST_CASE("panda: resolved rate achieves the twist, within the joint velocity limits", "[robot][panda]") {
  lieservo::sampling::Rng rng(11);
  const long n = lieservo::test::scaledCount(100000, 10000);
  long exact = 0, scaled = 0, damped = 0;
  double worst_exact = 0, worst_over = 0;
  for (long k = 0; k < n; ++k) {
    const Joints q = randomJoints(rng);
    Twist v;
    for (int i = 0; i < 6; ++i) v[i] = lieservo::sampling::uniform(rng, -1.0, 1.0) * (i < 3 ? 0.5 : 1.0);
    const ResolvedRate r = resolvedRate(q, v);
    REQUIRE(r.dq.allFinite());
    worst_over = std::max(worst_over, (r.dq.cwiseAbs().array() / velocityLimits().array()).maxCoeff());
    if (r.lambda > 0) {
      ++damped;
      continue;
    }
    // Undamped: J dq is the commanded twist, scaled as a whole when the joints would be too fast.
    (r.scale < 1 ? scaled : exact) += 1;
    worst_exact = std::max(worst_exact, (jacobian(q) * r.dq - r.scale * v).norm() / (r.scale * v.norm()));
  }
  INFO(exact << " exact, " << scaled << " scaled, " << damped << " damped; worst relative twist error "
             << worst_exact << ", worst |dq|/limit " << worst_over);
  CHECK(worst_exact <= 1e-9);
  CHECK(worst_over <= 1.0 + 1e-12);
  CHECK(exact > 0);
  CHECK(scaled > 0);
  CHECK(damped > 0);
}

TEST_CASE("panda: at a singularity the damped step stays bounded", "[robot][panda]") {
  Twist v;
  v << 0.1, 0.0, 0.0, 0.0, 0.0, 0.5;
  const ResolvedRate r = resolvedRate(Joints::Zero(), v);
  CHECK(r.sigma_min <= 1e-6);  // zero up to the rounding of J Jᵀ's eigenvalues
  CHECK(r.lambda == Approx(ResolvedRateOptions{}.damping));
  CHECK(r.dq.allFinite());
  CHECK((r.dq.cwiseAbs().array() <= velocityLimits().array()).all());
}

TEST_CASE("panda: where damping acts, the joint speed of the exact solution is reported", "[robot][panda]") {
  // Undamped (the ready pose): dq is the exact solution, nothing more to report.
  Twist v;
  v << 0.1, 0.0, 0.0, 0.0, 0.0, 0.5;
  CHECK(resolvedRate(readyPose(), v).lambda == 0.0);
  CHECK(resolvedRate(readyPose(), v).exact_speed_ratio == 0.0);
  // The arm stretched out along the base's x (where a twist straight out from the ready pose
  // takes it under damping alone): moving further out needs joints far beyond their limits
  // (the libfranka double's reflex), while the damped step stays within them.
  Joints stretched;
  stretched << 0, 1.1391, 0, -0.46641, 0, 1.73131, 0.785398;
  const Twist out = (Twist() << 0.1, 0, 0, 0, 0, 0).finished();
  const ResolvedRate s = resolvedRate(stretched, out);
  CHECK(s.lambda > 0);
  CHECK(s.exact_speed_ratio > 1.0);
  CHECK((s.dq.cwiseAbs().array() <= velocityLimits().array()).all());
  // Inside the damping band, away from σ = 0: the ratio is that of Jᵀ(J Jᵀ)⁻¹v.
  lieservo::sampling::Rng rng(12);
  long checked = 0;
  double worst = 0;
  for (long k = 0; k < lieservo::test::scaledCount(100000, 10000) && checked < 200; ++k) {
    const Joints q = randomJoints(rng);
    Twist u;
    for (int i = 0; i < 6; ++i) u[i] = lieservo::sampling::uniform(rng, -1.0, 1.0) * (i < 3 ? 0.5 : 1.0);
    const ResolvedRate r = resolvedRate(q, u);
    if (r.lambda == 0.0 || r.sigma_min < 1e-3) continue;
    const Jacobian J = jacobian(q);
    const Joints dq = J.transpose() * (J * J.transpose()).ldlt().solve(u);
    const double ratio = (dq.cwiseAbs().array() / velocityLimits().array()).maxCoeff();
    worst = std::max(worst, std::abs(r.exact_speed_ratio - ratio) / ratio);
    ++checked;
  }
  INFO(checked << " damped configurations, worst relative difference " << worst);
  CHECK(checked >= 20);
  CHECK(worst <= 1e-6);
}
