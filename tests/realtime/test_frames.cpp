// Sensor body twist → the base-frame EE-origin velocity [ṗ_OE; ω_O], against hand-computed cases
// and a finite-difference check of the rigid-body kinematics.
#include <catch2/catch.hpp>

#include <lieservo/sampling/random.hpp>
#include <lieservo/units.hpp>
#include <lieservo/groups/se3.hpp>
#include <lieservo/realtime/frames.hpp>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

using lieservo::sampling::uniform;
using lieservo::Status;
using namespace lieservo::realtime;

namespace {

Matrix3 rotX(double a) { return Eigen::AngleAxisd(a, Vector3::UnitX()).toRotationMatrix(); }
Matrix3 rotZ(double a) { return Eigen::AngleAxisd(a, Vector3::UnitZ()).toRotationMatrix(); }

Vector6 twist(double vx, double vy, double vz, double wx, double wy, double wz) {
  Vector6 t;
  t << vx, vy, vz, wx, wy, wz;
  return t;
}

Matrix4 homogeneous(const Matrix3& R, const Vector3& p) {
  Matrix4 T = Matrix4::Identity();
  T.topLeftCorner<3, 3>() = R;
  T.topRightCorner<3, 1>() = p;
  return T;
}

}  // namespace

TEST_CASE("frames: hand-computed twist conversions", "[realtime][frames]") {
  SECTION("identity pose and mount: unchanged") {
    const Vector6 xi = twist(1, 2, 3, 0.1, 0.2, 0.3);
    CHECK(sensorTwistToBase(Matrix3::Identity(), SensorMount{}, xi).isApprox(xi));
  }
  SECTION("translation scale mm → m touches only the linear part") {
    const Vector6 out = sensorTwistToBase(Matrix3::Identity(), SensorMount{}, twist(10, 0, 0, 0, 0, 0.5), 1e-3);
    CHECK(out.isApprox(twist(0.01, 0, 0, 0, 0, 0.5)));
  }
  SECTION("sensor 0.1 m along EE z, rotation about the sensor x axis moves the EE origin") {
    // ω = (ω, 0, 0) about the tip centre; the EE origin is at −0.1 z from it, so
    // ṗ_E = ω × (p_E − p_S) = (ω,0,0) × (0,0,−0.1) = (0, 0.1 ω, 0).
    SensorMount m;
    m.p_es = Vector3(0, 0, 0.1);
    const double w = 0.5;
    CHECK(sensorTwistToBase(Matrix3::Identity(), m, twist(0, 0, 0, w, 0, 0)).isApprox(twist(0, 0.1 * w, 0, w, 0, 0)));
    // Rotation about the common z axis does not move the EE origin.
    const Vector6 spin = sensorTwistToBase(Matrix3::Identity(), m, twist(0, 0, 0, 0, 0, w));
    CHECK(spin.head<3>().norm() < 1e-15);
  }
  SECTION("EE pointing down (Franka home: R_OE = Rx(π)), sensor on the flange axis") {
    // R_OE = diag(1, −1, −1). Sensor z (out of the tip) = EE z = base −z.
    // A body velocity +z of the sensor (pressing into a surface below) is base −z.
    SensorMount m;
    m.p_es = Vector3(0, 0, 0.12);
    const Matrix3 R = rotX(lieservo::pi<double>());
    CHECK(sensorTwistToBase(R, m, twist(0, 0, 0.02, 0, 0, 0)).isApprox(twist(0, 0, -0.02, 0, 0, 0)));
    // Sensor ω_x = w: base ω = (w, 0, 0); r_O = R p_ES = (0, 0, −0.12);
    // ṗ_E = r_O × ω_O = (0,0,−0.12) × (w,0,0) = (0, −0.12 w, 0).
    const double w = 0.2;
    CHECK(sensorTwistToBase(R, m, twist(0, 0, 0, w, 0, 0)).isApprox(twist(0, -0.12 * w, 0, w, 0, 0)));
  }
  SECTION("right-angle mount (paper's pushing adaptor): sensor z along EE x") {
    // R_ES = Ry(90°) = [[0,0,1],[0,1,0],[−1,0,0]]: sensor x → EE −z, sensor z → EE x.
    // p_ES = (0.08, 0, 0.05) m.
    SensorMount m;
    m.R_es = Eigen::AngleAxisd(lieservo::pi<double>() / 2, Vector3::UnitY()).toRotationMatrix();
    m.p_es = Vector3(0.08, 0, 0.05);
    // Pushing feedforward 10 mm/s along sensor z → 0.01 m/s along EE x (= base x here).
    CHECK(sensorTwistToBase(Matrix3::Identity(), m, twist(0, 0, 10, 0, 0, 0), 1e-3).isApprox(twist(0.01, 0, 0, 0, 0, 0)));
    // 10 mm/s along sensor x → base −z.
    CHECK(sensorTwistToBase(Matrix3::Identity(), m, twist(10, 0, 0, 0, 0, 0), 1e-3).isApprox(twist(0, 0, -0.01, 0, 0, 0)));
    // ω about the sensor z: ω_O = (w,0,0); ṗ_E = r_O × ω_O = (0.08,0,0.05) × (w,0,0) = (0, 0.05 w, 0).
    const double w = 0.3;
    CHECK(sensorTwistToBase(Matrix3::Identity(), m, twist(0, 0, 0, 0, 0, w)).isApprox(twist(0, 0.05 * w, 0, w, 0, 0)));
  }
}

TEST_CASE("frames: conversion matches finite differences of the rigid-body motion", "[realtime][frames]") {
  // Move the SENSOR with body twist ξ_s for a tiny h (X_OS(h) = X_OS exp(h ξ_s^)), recover the
  // EE pose X_OE(h) = X_OS(h) X_ES⁻¹, and compare (p_OE(h) − p_OE)/h and the rotation rate
  // with the converted command.
  lieservo::sampling::Rng rng(42);
  for (int trial = 0; trial < 50; ++trial) {
    const Matrix3 R_oe = Eigen::Quaterniond::UnitRandom().toRotationMatrix();
    const Vector3 p_oe(uniform(rng, -1.0, 1.0), uniform(rng, -1.0, 1.0), uniform(rng, -1.0, 1.0));
    SensorMount m;
    m.R_es = Eigen::Quaterniond::UnitRandom().toRotationMatrix();
    m.p_es = 0.2 * Vector3(uniform(rng, -1.0, 1.0), uniform(rng, -1.0, 1.0), uniform(rng, -1.0, 1.0));
    Vector6 xi;
    for (int i = 0; i < 6; ++i) xi[i] = uniform(rng, -1.0, 1.0);

    const Matrix3 R_os = R_oe * m.R_es;
    const Vector3 p_os = p_oe + R_oe * m.p_es;
    const double h = 1e-6;
    // exp of the body twist to first order is enough at h = 1e-6 (error O(h²)/h = O(h)).
    Matrix3 dR = Eigen::AngleAxisd(h * xi.tail<3>().norm(), xi.tail<3>().normalized()).toRotationMatrix();
    const Matrix3 R_os_h = R_os * dR;
    const Vector3 p_os_h = p_os + R_os * (h * xi.head<3>());
    const Matrix3 R_oe_h = R_os_h * m.R_es.transpose();
    const Vector3 p_oe_h = p_os_h - R_oe_h * m.p_es;

    const Vector3 v_fd = (p_oe_h - p_oe) / h;
    const Eigen::AngleAxisd dA(R_oe_h * R_oe.transpose());  // spatial (base) rotation increment
    const Vector3 w_fd = dA.angle() * dA.axis() / h;

    const Vector6 out = sensorTwistToBase(R_oe, m, xi);
    CHECK((out.head<3>() - v_fd).norm() < 1e-5);
    CHECK((out.tail<3>() - w_fd).norm() < 1e-5);
    // And back.
    CHECK(baseTwistToSensor(R_oe, m, out).isApprox(xi, 1e-12));
    CHECK(baseTwistToSensor(R_oe, m, sensorTwistToBase(R_oe, m, xi, 1e-3), 1e-3).isApprox(xi, 1e-12));
  }
}

TEST_CASE("frames: sensor pose and checked conversion from the EE pose T_OE", "[realtime][frames]") {
  SensorMount m;
  m.R_es = rotZ(0.3);
  m.p_es = Vector3(0, 0, 120);  // mm: the pose output is in mm
  const Matrix3 R = rotX(lieservo::pi<double>());
  const Matrix4 T = homogeneous(R, Vector3(0.4, 0.0, 0.3));
  Matrix4 X;
  REQUIRE(sensorPoseFromHomogeneous(T, m, 1e3, X) == Status::ok);
  CHECK(X.topLeftCorner<3, 3>().isApprox(R * m.R_es));
  CHECK(X.topRightCorner<3, 1>().isApprox(Vector3(400, 0, 300 - 120)));

  SensorMount m_m = m;
  m_m.p_es = Vector3(0, 0, 0.12);
  Vector6 out = Vector6::Constant(9);
  REQUIRE(sensorTwistToBaseChecked(T, m_m, twist(0, 0, 10, 0, 0, 0), 1e-3, out) == Status::ok);
  CHECK(out.isApprox(twist(0, 0, -0.01, 0, 0, 0)));
}

TEST_CASE("frames: bad poses and twists are rejected with outputs untouched", "[realtime][frames]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Matrix4 good = Matrix4::Identity();
  Matrix3 R = Matrix3::Constant(5);
  Vector3 p = Vector3::Constant(5);
  Matrix4 M = Matrix4::Constant(5);
  Vector6 out = Vector6::Constant(5);
  SensorMount m;

  Matrix4 bad = good;
  bad(1, 1) = nan;
  CHECK(poseFromHomogeneous(bad, R, p) == Status::non_finite_input);
  bad = good;
  bad(3, 0) = 0.5;  // the bottom row must be (0 0 0 1)
  CHECK(poseFromHomogeneous(bad, R, p) == Status::invalid_argument);
  bad = good;
  bad(0, 0) = 1.1;  // scaled rotation
  CHECK(poseFromHomogeneous(bad, R, p) == Status::not_orthonormal);
  bad = good;
  bad(0, 0) = -1;  // reflection: det −1
  CHECK(sensorPoseFromHomogeneous(bad, m, 1.0, M) == Status::not_orthonormal);
  CHECK(R == Matrix3::Constant(5));
  CHECK(p == Vector3::Constant(5));
  CHECK(M == Matrix4::Constant(5));

  CHECK(sensorTwistToBaseChecked(bad, m, Vector6::Zero(), 1.0, out) == Status::not_orthonormal);
  Vector6 xi = Vector6::Zero();
  xi[3] = nan;
  CHECK(sensorTwistToBaseChecked(good, m, xi, 1.0, out) == Status::non_finite_input);
  CHECK(sensorTwistToBaseChecked(good, m, Vector6::Zero(), 0.0, out) == Status::invalid_argument);
  CHECK(sensorPoseFromHomogeneous(good, m, -1.0, M) == Status::invalid_argument);
  CHECK(out == Vector6::Constant(5));
  CHECK(M == Matrix4::Constant(5));

  SensorMount skew;
  skew.R_es(0, 1) = 0.01;
  CHECK(skew.validate() == Status::not_orthonormal);
  skew = SensorMount{};
  skew.p_es[0] = nan;
  CHECK(skew.validate() == Status::non_finite_input);
  // Small numerical noise in a robot-supplied rotation is accepted.
  Matrix4 noisy = good;
  noisy(1, 0) = 1e-9;
  CHECK(poseFromHomogeneous(noisy, R, p) == Status::ok);
}

TEST_CASE("frames: the conversion is Ad(X_O'S) of the library's SE3 (mixed twist)", "[realtime][frames]") {
  // [ṗ_OE; ω_O] = Ad(X_O'S) ξ_s with X_O'S = (R_OS, R_OE p_ES), Ad = [[C, r^C], [0, C]].
  using SE3d = lieservo::SE3<double>;
  using SO3d = lieservo::SO3<double>;
  lieservo::sampling::Rng rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    const Matrix3 R_oe = Eigen::Quaterniond::UnitRandom().toRotationMatrix();
    SensorMount m;
    m.R_es = Eigen::Quaterniond::UnitRandom().toRotationMatrix();
    m.p_es = 0.2 * Vector3(uniform(rng, -1.0, 1.0), uniform(rng, -1.0, 1.0), uniform(rng, -1.0, 1.0));
    Vector6 xi;
    for (int i = 0; i < 6; ++i) xi[i] = uniform(rng, -1.0, 1.0);
    const SE3d X(SO3d::fromMatrixUnchecked(R_oe * m.R_es), R_oe * m.p_es);
    CHECK((X.Ad() * xi).isApprox(sensorTwistToBase(R_oe, m, xi), 1e-12));
  }
}
