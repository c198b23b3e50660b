// libfranka's column-major O_T_EE to the real-time layer's Matrix4 (examples/franka
// franka_frames.hpp): the layout, the round trip, the core's checks applied, outputs kept on
// errors.
#include <catch2/catch.hpp>

#include <franka_frames.hpp>
#include <lieservo/units.hpp>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

using lieservo::Status;
using namespace lieservo::franka_frames;

TEST_CASE("franka frames: column-major O_T_EE is read as libfranka lays it out", "[realtime][franka]") {
  // A pose with R = Rz(90°), p = (0.3, -0.1, 0.5): column-major means translation at 12..14.
  const std::array<double, 16> a = {0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1, 0, 0.3, -0.1, 0.5, 1};
  Matrix3 R = Matrix3::Zero();  // (initialised: GCC 12 cannot see that ok means written)
  Vector3 p = Vector3::Zero();
  REQUIRE(poseFromColumnMajor(a, R, p) == Status::ok);
  CHECK(R.isApprox(Eigen::AngleAxisd(lieservo::pi<double>() / 2, Vector3::UnitZ()).toRotationMatrix(), 1e-15));
  CHECK(p.isApprox(Vector3(0.3, -0.1, 0.5)));
  const Matrix4 M = homogeneous(a);
  CHECK(M(0, 1) == -1);
  CHECK(M(1, 3) == -0.1);
  CHECK(toColumnMajor(M) == a);
}

TEST_CASE("franka frames: sensor pose from O_T_EE, bad arrays rejected with outputs untouched",
          "[realtime][franka]") {
  SensorMount m;
  m.p_es = Vector3(0, 0, 120);  // mm
  Matrix4 T = Matrix4::Identity();
  T.topRightCorner<3, 1>() = Vector3(0.4, 0.0, 0.3);
  Matrix4 X;
  REQUIRE(sensorPoseFromColumnMajor(toColumnMajor(T), m, 1e3, X) == Status::ok);
  CHECK(X.topRightCorner<3, 1>().isApprox(Vector3(400, 0, 420)));

  const std::array<double, 16> good = toColumnMajor(Matrix4::Identity());
  Matrix3 R = Matrix3::Constant(5);
  Vector3 p = Vector3::Constant(5);
  X = Matrix4::Constant(5);
  auto bad = good;
  bad[5] = std::numeric_limits<double>::quiet_NaN();
  CHECK(poseFromColumnMajor(bad, R, p) == Status::non_finite_input);
  bad = good;
  bad[3] = 0.5;  // row 3, column 0: the bottom row must be (0 0 0 1)
  CHECK(poseFromColumnMajor(bad, R, p) == Status::invalid_argument);
  bad = good;
  bad[0] = -1;  // reflection
  CHECK(sensorPoseFromColumnMajor(bad, m, 1e3, X) == Status::not_orthonormal);
  CHECK(R == Matrix3::Constant(5));
  CHECK(p == Vector3::Constant(5));
  CHECK(X == Matrix4::Constant(5));
}

TEST_CASE("franka frames: the default smoother limits are inside libfranka's documented Cartesian limits",
          "[realtime][franka]") {
  const lieservo::realtime::SmootherLimits<double> d{};
  const lieservo::realtime::SmootherLimits<double> franka = lieservo::franka_frames::documentedCartesianLimits();
  CHECK(franka.validate() == lieservo::Status::ok);
  CHECK(d.within(franka));
  CHECK_FALSE(franka.within(d));
}
