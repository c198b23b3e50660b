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
using SE3d = lieservo::SE3<double>;
using SO3d = lieservo::SO3<double>;

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

// An EE pose with rotation R (the translation does not enter the twist conversion).
SE3d pose(const Matrix3& R, const Vector3& p = Vector3::Zero()) { return SE3d(SO3d::fromMatrixUnchecked(R), p); }

SensorMount mount(const Matrix3& R, const Vector3& p) { return SensorMount{pose(R, p)}; }

}  // namespace

TEST_CASE("frames: hand-computed twist conversions", "[realtime][frames]") {
  SECTION("identity pose and mount: unchanged") {
    const Vector6 xi = twist(1, 2, 3, 0.1, 0.2, 0.3);
    CHECK(sensorTwistToBase(SE3d(), SensorMount{}, xi).isApprox(xi));
  }
  SECTION("translation scale mm → m touches only the linear part") {
    const Vector6 out = sensorTwistToBase(SE3d(), SensorMount{}, twist(10, 0, 0, 0, 0, 0.5), 1e-3);
    CHECK(out.isApprox(twist(0.01, 0, 0, 0, 0, 0.5)));
  }
  SECTION("sensor 0.1 m along EE z, rotation about the sensor x axis moves the EE origin") {
    // ω = (ω, 0, 0) about the tip centre; the EE origin is at −0.1 z from it, so
    // ṗ_E = ω × (p_E − p_S) = (ω,0,0) × (0,0,−0.1) = (0, 0.1 ω, 0).
    const SensorMount m = mount(Matrix3::Identity(), Vector3(0, 0, 0.1));
    const double w = 0.5;
    CHECK(sensorTwistToBase(SE3d(), m, twist(0, 0, 0, w, 0, 0)).isApprox(twist(0, 0.1 * w, 0, w, 0, 0)));
    // Rotation about the common z axis does not move the EE origin.
    const Vector6 spin = sensorTwistToBase(SE3d(), m, twist(0, 0, 0, 0, 0, w));
    CHECK(spin.head<3>().norm() < 1e-15);
  }
  SECTION("EE pointing down (Franka home: R_OE = Rx(π)), sensor on the flange axis") {
    // R_OE = diag(1, −1, −1). Sensor z (out of the tip) = EE z = base −z.
    // A body velocity +z of the sensor (pressing into a surface below) is base −z.
    const SensorMount m = mount(Matrix3::Identity(), Vector3(0, 0, 0.12));
    const SE3d R = pose(rotX(lieservo::pi<double>()));
    CHECK(sensorTwistToBase(R, m, twist(0, 0, 0.02, 0, 0, 0)).isApprox(twist(0, 0, -0.02, 0, 0, 0)));
    // Sensor ω_x = w: base ω = (w, 0, 0); r_O = R p_ES = (0, 0, −0.12);
    // ṗ_E = r_O × ω_O = (0,0,−0.12) × (w,0,0) = (0, −0.12 w, 0).
    const double w = 0.2;
    CHECK(sensorTwistToBase(R, m, twist(0, 0, 0, w, 0, 0)).isApprox(twist(0, -0.12 * w, 0, w, 0, 0)));
  }
  SECTION("right-angle mount (paper's pushing adaptor): sensor z along EE x") {
    // R_ES = Ry(90°) = [[0,0,1],[0,1,0],[−1,0,0]]: sensor x → EE −z, sensor z → EE x.
    // p_ES = (0.08, 0, 0.05) m.
    const SensorMount m =
        mount(Eigen::AngleAxisd(lieservo::pi<double>() / 2, Vector3::UnitY()).toRotationMatrix(), Vector3(0.08, 0, 0.05));
    // Pushing feedforward 10 mm/s along sensor z → 0.01 m/s along EE x (= base x here).
    CHECK(sensorTwistToBase(SE3d(), m, twist(0, 0, 10, 0, 0, 0), 1e-3).isApprox(twist(0.01, 0, 0, 0, 0, 0)));
    // 10 mm/s along sensor x → base −z.
    CHECK(sensorTwistToBase(SE3d(), m, twist(10, 0, 0, 0, 0, 0), 1e-3).isApprox(twist(0, 0, -0.01, 0, 0, 0)));
    // ω about the sensor z: ω_O = (w,0,0); ṗ_E = r_O × ω_O = (0.08,0,0.05) × (w,0,0) = (0, 0.05 w, 0).
    const double w = 0.3;
    CHECK(sensorTwistToBase(SE3d(), m, twist(0, 0, 0, 0, 0, w)).isApprox(twist(0, 0.05 * w, 0, w, 0, 0)));
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
    const Matrix3 R_es = Eigen::Quaterniond::UnitRandom().toRotationMatrix();
    const Vector3 p_es = 0.2 * Vector3(uniform(rng, -1.0, 1.0), uniform(rng, -1.0, 1.0), uniform(rng, -1.0, 1.0));
    const SensorMount m = mount(R_es, p_es);
    Vector6 xi;
    for (int i = 0; i < 6; ++i) xi[i] = uniform(rng, -1.0, 1.0);

    const Matrix3 R_os = R_oe * R_es;
    const Vector3 p_os = p_oe + R_oe * p_es;
    const double h = 1e-6;
    // exp of the body twist to first order is enough at h = 1e-6 (error O(h²)/h = O(h)).
    Matrix3 dR = Eigen::AngleAxisd(h * xi.tail<3>().norm(), xi.tail<3>().normalized()).toRotationMatrix();
    const Matrix3 R_os_h = R_os * dR;
    const Vector3 p_os_h = p_os + R_os * (h * xi.head<3>());
    const Matrix3 R_oe_h = R_os_h * R_es.transpose();
    const Vector3 p_oe_h = p_os_h - R_oe_h * p_es;

    const Vector3 v_fd = (p_oe_h - p_oe) / h;
    const Eigen::AngleAxisd dA(R_oe_h * R_oe.transpose());  // spatial (base) rotation increment
    const Vector3 w_fd = dA.angle() * dA.axis() / h;

    const SE3d T_oe = pose(R_oe, p_oe);
    const Vector6 out = sensorTwistToBase(T_oe, m, xi);
    CHECK((out.head<3>() - v_fd).norm() < 1e-5);
    CHECK((out.tail<3>() - w_fd).norm() < 1e-5);
    // And back.
    CHECK(baseTwistToSensor(T_oe, m, out).isApprox(xi, 1e-12));
    CHECK(baseTwistToSensor(T_oe, m, sensorTwistToBase(T_oe, m, xi, 1e-3), 1e-3).isApprox(xi, 1e-12));
  }
}

TEST_CASE("frames: the sensor pose from the EE pose T_OE and the one mount", "[realtime][frames]") {
  // The mount in mm from the user, once in the robot's metres; the pose back in mm.
  const SensorMount m = SensorMount::fromLibraryUnits(pose(rotZ(0.3), Vector3(0, 0, 120)), 1e-3);
  CHECK(m.X_es.translation().isApprox(Vector3(0, 0, 0.12)));
  const Matrix3 R = rotX(lieservo::pi<double>());
  SE3d T;
  REQUIRE(poseFromHomogeneous(homogeneous(R, Vector3(0.4, 0.0, 0.3)), T) == Status::ok);
  const SE3d X = sensorPose(T, m, 1e3);
  CHECK(X.rotationMatrix().isApprox(R * rotZ(0.3)));
  CHECK(X.translation().isApprox(Vector3(400, 0, 300 - 120)));
  // The same mount converts the twist: 10 mm/s along the sensor's z is 0.01 m/s along base −z.
  CHECK(sensorTwistToBase(T, m, twist(0, 0, 10, 0, 0, 0), 1e-3).isApprox(twist(0, 0, -0.01, 0, 0, 0)));
}

TEST_CASE("frames: bad poses and mounts are rejected with outputs untouched", "[realtime][frames]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Matrix4 good = Matrix4::Identity();
  const SE3d before = pose(rotZ(0.7), Vector3(5, 5, 5));
  SE3d X = before;

  Matrix4 bad = good;
  bad(1, 1) = nan;
  CHECK(poseFromHomogeneous(bad, X) == Status::non_finite_input);
  bad = good;
  bad(3, 0) = 0.5;  // the bottom row must be (0 0 0 1)
  CHECK(poseFromHomogeneous(bad, X) == Status::invalid_argument);
  bad = good;
  bad(0, 0) = 1.1;  // scaled rotation
  CHECK(poseFromHomogeneous(bad, X) == Status::not_orthonormal);
  bad = good;
  bad(0, 0) = -1;  // reflection: det −1
  CHECK(poseFromHomogeneous(bad, X) == Status::not_orthonormal);
  CHECK(X.matrix() == before.matrix());

  Matrix3 skewed = Matrix3::Identity();
  skewed(0, 1) = 0.01;
  CHECK(mount(skewed, Vector3::Zero()).validate() == Status::not_orthonormal);
  CHECK(mount(Matrix3::Identity(), Vector3(nan, 0, 0)).validate() == Status::non_finite_input);
  CHECK(SensorMount{}.validate() == Status::ok);
  // Small numerical noise in a robot-supplied rotation is accepted.
  Matrix4 noisy = good;
  noisy(1, 0) = 1e-9;
  CHECK(poseFromHomogeneous(noisy, X) == Status::ok);
}

TEST_CASE("frames: the conversion is Ad(X_O'S) of the library's SE3 (mixed twist)", "[realtime][frames]") {
  // [ṗ_OE; ω_O] = Ad(X_O'S) ξ_s with X_O'S = (R_OS, R_OE p_ES), Ad = [[C, r^C], [0, C]].
  lieservo::sampling::Rng rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    const Matrix3 R_oe = Eigen::Quaterniond::UnitRandom().toRotationMatrix();
    const Matrix3 R_es = Eigen::Quaterniond::UnitRandom().toRotationMatrix();
    const Vector3 p_es = 0.2 * Vector3(uniform(rng, -1.0, 1.0), uniform(rng, -1.0, 1.0), uniform(rng, -1.0, 1.0));
    Vector6 xi;
    for (int i = 0; i < 6; ++i) xi[i] = uniform(rng, -1.0, 1.0);
    const SE3d X(SO3d::fromMatrixUnchecked(R_oe * R_es), R_oe * p_es);
    CHECK((X.Ad() * xi).isApprox(sensorTwistToBase(pose(R_oe), mount(R_es, p_es), xi), 1e-12));
  }
}
