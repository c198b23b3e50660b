// libfranka's column-major O_T_EE to the SE3 of the real-time layer, its one parse (examples/franka
// franka_frames.hpp): the layout, the round trip, the core's checks applied, outputs kept on
// errors, the sensor pose through the one mount.
#include <catch2/catch.hpp>

#include <franka_frames.hpp>
#include <lieservo/units.hpp>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

using lieservo::Status;
using namespace lieservo::franka_frames;
using Matrix3 = Eigen::Matrix3d;
using Vector3 = Eigen::Vector3d;
using SE3d = lieservo::SE3<double>;

TEST_CASE("franka frames: column-major O_T_EE is read as libfranka lays it out", "[realtime][franka]") {
  // A pose with R = Rz(90°), p = (0.3, -0.1, 0.5): column-major means translation at 12..14.
  const std::array<double, 16> a = {0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1, 0, 0.3, -0.1, 0.5, 1};
  SE3d T;
  REQUIRE(poseFromColumnMajor(a, T) == Status::ok);
  CHECK(T.rotationMatrix().isApprox(Eigen::AngleAxisd(lieservo::pi<double>() / 2, Vector3::UnitZ()).toRotationMatrix(),
                                    1e-15));
  CHECK(T.translation().isApprox(Vector3(0.3, -0.1, 0.5)));
  const Matrix4 M = homogeneous(a);
  CHECK(M(0, 1) == -1);
  CHECK(M(1, 3) == -0.1);
  CHECK(toColumnMajor(M) == a);
}

TEST_CASE("franka frames: sensor pose from O_T_EE, bad arrays rejected with outputs untouched",
          "[realtime][franka]") {
  // The mount given in mm, once in libfranka's metres; the sensor pose back in mm.
  const SensorMount m = SensorMount::fromLibraryUnits(SE3d(lieservo::SO3<double>(), Vector3(0, 0, 120)), 1e-3);
  Matrix4 M = Matrix4::Identity();
  M.topRightCorner<3, 1>() = Vector3(0.4, 0.0, 0.3);
  SE3d T;
  REQUIRE(poseFromColumnMajor(toColumnMajor(M), T) == Status::ok);
  CHECK(lieservo::realtime::sensorPose(T, m, 1e3).translation().isApprox(Vector3(400, 0, 420)));

  const std::array<double, 16> good = toColumnMajor(Matrix4::Identity());
  const SE3d before(lieservo::SO3<double>(), Vector3::Constant(5));
  T = before;
  auto bad = good;
  bad[5] = std::numeric_limits<double>::quiet_NaN();
  CHECK(poseFromColumnMajor(bad, T) == Status::non_finite_input);
  bad = good;
  bad[3] = 0.5;  // row 3, column 0: the bottom row must be (0 0 0 1)
  CHECK(poseFromColumnMajor(bad, T) == Status::invalid_argument);
  bad = good;
  bad[0] = -1;  // reflection
  CHECK(poseFromColumnMajor(bad, T) == Status::not_orthonormal);
  CHECK(T.matrix() == before.matrix());
}

TEST_CASE("franka frames: the default smoother limits are inside libfranka's documented Cartesian limits",
          "[realtime][franka]") {
  const lieservo::realtime::SmootherLimits<double> d{};
  const lieservo::realtime::SmootherLimits<double> franka = lieservo::franka_frames::documentedCartesianLimits();
  CHECK(franka.validate() == lieservo::Status::ok);
  CHECK(d.within(franka));
  CHECK_FALSE(franka.within(d));
}
