// Conversions (Euler xyz, quaternion, isometry, 4x4), units, renormalisation over 1e6
// compositions, and the dataset's X_fs convention.
#include <chrono>
#include <cstdio>

#include <Eigen/Geometry>

#include "group_properties.hpp"

using lieservo::sampling::uniform;
using lieservo::SE3;
using lieservo::SO3;

TEMPLATE_TEST_CASE("Euler xyz: C = Rz(g) Ry(b) Rx(a) and round trip", "[core][conversions]", float, double) {
  using S = TestType;
  using G = SO3<S>;
  using V = typename G::Vector3;
  const double tol = 16 * lst::epsOf<S>();
  lieservo::sampling::Rng rng(1);
  for (int i = 0; i < 2000; ++i) {
    const double pi = lieservo::pi<double>();
    const S a = S(pi * uniform(rng, -1.0, 1.0)), b = S(pi / 2 * uniform(rng, -1.0, 1.0)), g = S(pi * uniform(rng, -1.0, 1.0));
    const typename G::Matrix ref = (Eigen::AngleAxis<S>(g, V::UnitZ()) * Eigen::AngleAxis<S>(b, V::UnitY()) *
                                    Eigen::AngleAxis<S>(a, V::UnitX()))
                                       .toRotationMatrix();
    const G C = G::fromEulerXYZ(a, b, g);
    CHECK(static_cast<double>((C.matrix() - ref).norm()) <= tol);
    const V e = C.toEulerXYZ();
    CHECK(static_cast<double>((G::fromEulerXYZ(e).matrix() - C.matrix()).norm()) <= tol);
    CHECK(static_cast<double>((e - V(a, b, g)).norm()) <= 1e3 * lst::epsOf<S>());
    // degrees
    const V ed = C.toEulerXYZDegrees();
    CHECK(static_cast<double>((G::fromEulerXYZDegrees(ed).matrix() - C.matrix()).norm()) <= tol);
  }
  // gimbal lock: β = ±90°, the composite still round-trips (γ is set to 0)
  for (S b : {S(lieservo::pi<double>() / 2), S(-lieservo::pi<double>() / 2)}) {
    const G C = G::fromEulerXYZ(S(0.3), b, S(-0.7));
    const V e = C.toEulerXYZ();
    CHECK(static_cast<double>((G::fromEulerXYZ(e).matrix() - C.matrix()).norm()) <= 1e3 * lst::epsOf<S>());
  }
}

TEST_CASE("Euler 6-vectors follow the dataset README (X_fs = X_par * X_perp)", "[core][conversions]") {
  using G = lieservo::SE3d;
  // (x, y, z, alpha, beta, gamma) = (shear_x, shear_y, pose_z, pose_Rx, pose_Ry, shear_Rz), mm and degrees.
  G::Vector6 v;
  v << 2.5, -1.5, 4.0, 12.0, -7.0, 3.5;
  G::Vector6 par, perp;
  par << 2.5, -1.5, 0, 0, 0, 3.5;
  perp << 0, 0, 4.0, 12.0, -7.0, 0;
  const G Xfs = G::fromEulerXYZ6Degrees(v);
  const G composed = G::fromEulerXYZ6Degrees(par) * G::fromEulerXYZ6Degrees(perp);
  CHECK(lst::matDiff(Xfs, composed) <= 1e-14);
  CHECK((Xfs.toEulerXYZ6Degrees() - v).norm() <= 1e-12);
  CHECK((Xfs.translation() - Eigen::Vector3d(2.5, -1.5, 4.0)).norm() == 0.0);
  // radians variant and units helpers
  CHECK((G::fromEulerXYZ6(lieservo::poseDegToRad(v)).matrix() - Xfs.matrix()).norm() == 0.0);
  CHECK((lieservo::poseRadToDeg(lieservo::poseDegToRad(v)) - v).norm() <= 1e-13);
}

TEST_CASE("units: deg2rad/rad2deg are constexpr and exact at simple angles", "[core][conversions]") {
  static_assert(lieservo::deg2rad(180.0) == lieservo::pi<double>(), "constexpr deg2rad");
  static_assert(lieservo::rad2deg(lieservo::pi<double>()) == 180.0, "constexpr rad2deg");
  static_assert(lieservo::deg2rad(180) == lieservo::pi<double>(), "integers compute in double");
  CHECK(lieservo::deg2rad(90.0f) == Approx(lieservo::pi<double>() / 2).epsilon(1e-7));
  CHECK(lieservo::rad2deg(1.0) == Approx(57.29577951308232).epsilon(1e-15));
}

TEMPLATE_TEST_CASE("Quaternion conversions", "[core][conversions]", float, double) {
  using S = TestType;
  using G = SO3<S>;
  const double tol = 16 * lst::epsOf<S>();
  lieservo::sampling::Rng rng(2);
  for (int i = 0; i < 2000; ++i) {
    const G C = G::sampleUniform(rng);
    const Eigen::Quaternion<S> q = C.unitQuaternion();
    CHECK(q.w() >= S(0));
    CHECK(std::abs(static_cast<double>(q.norm()) - 1) <= tol);
    CHECK(static_cast<double>((q.toRotationMatrix() - C.matrix()).norm()) <= tol);
    CHECK(static_cast<double>((G::fromQuaternion(q).matrix() - C.matrix()).norm()) <= tol);
    // non-unit and sign-flipped quaternions describe the same rotation
    const Eigen::Quaternion<S> q2(S(-3) * q.coeffs());
    CHECK(static_cast<double>((G::fromQuaternion(q2).matrix() - C.matrix()).norm()) <= tol);
  }
}

TEMPLATE_TEST_CASE("Isometry and 4x4 conversions", "[core][conversions]", float, double) {
  using S = TestType;
  using G = SE3<S>;
  lieservo::sampling::Rng rng(3);
  for (int i = 0; i < 200; ++i) {
    const G X = G::sampleUniform(rng, S(10));
    const typename G::Isometry T = X.isometry();
    CHECK(static_cast<double>((T.matrix() - X.matrix()).norm()) == 0.0);
    CHECK(lst::matDiff(G::fromIsometry(T), X) == 0.0);
    CHECK(lst::matDiff(G::fromMatrixUnchecked(X.matrix()), X) == 0.0);
    const typename G::Point p = G::Point::Random();
    CHECK(static_cast<double>((T * p - X * p).norm()) <= 64 * lst::epsOf<S>());
    G Y;
    REQUIRE(G::fromMatrix(X.matrix(), Y) == lieservo::Status::ok);
    CHECK(lst::matDiff(Y, X) == 0.0);
  }
}

TEST_CASE("1e6 compositions stay orthonormal with normalize() every 100", "[core][conversions]") {
  using G = lieservo::SO3d;
  lieservo::sampling::Rng rng(4);
  std::vector<G> steps;
  for (int i = 0; i < 64; ++i) steps.push_back(G::exp(lst::randomTangent<G>(rng, 0.3, 0.0)));
  G C, raw;
  double worst = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 1; i <= 1000000; ++i) {
    C = C * steps[static_cast<size_t>(i) & 63];
    raw = raw * steps[static_cast<size_t>(i) & 63];
    if (i % 100 == 0) {
      C.normalize();
      worst = std::max(worst, (C.matrix().transpose() * C.matrix() - Eigen::Matrix3d::Identity()).norm());
    }
  }
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double drift = (raw.matrix().transpose() * raw.matrix() - Eigen::Matrix3d::Identity()).norm();
  std::printf("1e6 SO3 compositions: with normalize()/100 max |C^T C - I| = %.2e; without = %.2e (%.3f s)\n", worst,
              drift, secs);
  CHECK(worst <= 1e-12);
  CHECK((C.matrix().transpose() * C.matrix() - Eigen::Matrix3d::Identity()).norm() <= 1e-12);
  CHECK(C.matrix().determinant() > 0);
  // SE3 uses the same policy
  lieservo::SE3d X;
  const lieservo::SE3d step = lieservo::SE3d::exp(lieservo::SE3d::Tangent::Constant(0.01));
  for (int i = 1; i <= 100000; ++i) {
    X = X * step;
    if (i % 100 == 0) X.normalize();
  }
  CHECK((X.rotationMatrix().transpose() * X.rotationMatrix() - Eigen::Matrix3d::Identity()).norm() <= 1e-12);
}

TEST_CASE("normalize() repairs drifted rotations and is idempotent", "[core][conversions]") {
  using G = lieservo::SO3d;
  lieservo::sampling::Rng rng(5);
  for (int i = 0; i < 1000; ++i) {
    const G C = G::sampleUniform(rng);
    G D = G::fromMatrixUnchecked(C.matrix() + 1e-6 * Eigen::Matrix3d::Random());
    D.normalize();
    CHECK((D.matrix().transpose() * D.matrix() - Eigen::Matrix3d::Identity()).norm() <= 4e-16 * 8);
    CHECK(D.matrix().determinant() > 0);
    CHECK((D.matrix() - C.matrix()).norm() <= 1e-5);
    G E = C;
    E.normalize();
    CHECK((E.matrix() - C.matrix()).norm() <= 8e-16);
  }
}

TEST_CASE("SO3 uniform sampling looks uniform", "[core][conversions]") {
  using G = lieservo::SO3d;
  lieservo::sampling::Rng rng(6);
  Eigen::Matrix3d mean = Eigen::Matrix3d::Zero();
  double mean_cos = 0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    const G C = G::sampleUniform(rng);
    mean += C.matrix();
    mean_cos += (C.matrix().trace() - 1) / 2;
  }
  mean /= n;
  mean_cos /= n;
  // Haar measure: E[C] = 0 and E[cos θ] = −1/2 (density (1 − cos θ)/π on [0, π]).
  CHECK(mean.norm() <= 0.05);
  CHECK(mean_cos == Approx(-0.5).margin(0.02));
}
