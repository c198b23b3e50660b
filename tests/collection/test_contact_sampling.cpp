// Surface contact pose and shear sampling (paper Section 3.1.1 (sec:surface_contact_poses), Section 3.1.2 (sec:data_collection):
// eq. 1 (eqn:disk_random_sampling), eq. 2 (eqn:sphere_random_sampling)) and the label composition
// X_fs = X_par·X_perp, ξ = log(X_fs⁻¹)^∨.
//
// Statistical tests: significance level α = 0.001 each, fixed seeds (so a test either always
// passes or always fails — no flakiness). Power (see docs/data_collection.md):
//  * KS with n = 32000: rejects with probability ≥ 0.9 any alternative whose CDF differs
//    from the null by ≥ 0.0145 somewhere (critical D = 0.0109).
//  * χ² on 32 equal-probability cells (df = 31, critical 61.10) with n = 32000: power ≥ 0.9
//    for effect size w = √(Σ(p₁−p₀)²/p₀) ≥ 0.040, e.g. one cell off by 22 % of its mass.
// Each test also shows that it rejects a plausible wrong sampler (negative control).
#include <catch2/catch.hpp>

#include <lieservo/groups/se3.hpp>
#include <lieservo/sampling.hpp>
#include "contact_sampling.hpp"
#include <lieservo/units.hpp>

#include "goodness_of_fit.hpp"
#include "test_support.hpp"

#include <cmath>
#include <vector>

using lieservo::SE3;
using lieservo::SO3;
using lieservo::Status;
using namespace lieservo::sampling;
using lieservo::test::chiSquareEqualCells;
using lieservo::test::chiSquarePValue;
using lieservo::test::ksPValue;
using lieservo::test::ksStatisticUniform;

namespace {

constexpr double kAlpha = 0.001;
constexpr std::size_t kN = 32000;
const double kPi = lieservo::pi<double>();

struct Drawn {
  std::vector<SurfaceContactPose<double>> poses;
  std::vector<ContactDraws<double>> draws;
};

Drawn drawMany(std::uint64_t seed, std::size_t n, const ContactSamplingRanges<double>& r = {}) {
  lieservo::sampling::Rng rng(seed);
  Drawn d;
  for (std::size_t i = 0; i < n; ++i) {
    ContactDraws<double> dr;
    d.poses.push_back(sampleSurfaceContactPose<double>(rng, r, &dr));
    d.draws.push_back(dr);
  }
  return d;
}

// Disk cells: 4 equal-area rings (boundaries r_max·√(k/4)) × 8 equal sectors.
std::vector<long> diskCells(const std::vector<double>& xs, const std::vector<double>& ys, double r_max) {
  std::vector<long> c(32, 0);
  for (std::size_t i = 0; i < xs.size(); ++i) {
    const double u = (xs[i] * xs[i] + ys[i] * ys[i]) / (r_max * r_max);  // uniform on [0,1] under H0
    const double t = std::atan2(ys[i], xs[i]) + kPi;                   // [0, 2π]
    const int ring = std::min(3, static_cast<int>(u * 4));
    const int sector = std::min(7, static_cast<int>(t / (2 * kPi) * 8));
    ++c[static_cast<std::size_t>(ring * 8 + sector)];
  }
  return c;
}

// Cap cells: 4 equal-area bands in 1 − cos φ × 8 azimuth sectors.
std::vector<long> capCells(const std::vector<double>& phis, const std::vector<double>& thetas, double phi_max) {
  std::vector<long> c(32, 0);
  for (std::size_t i = 0; i < phis.size(); ++i) {
    const double u = (1 - std::cos(phis[i])) / (1 - std::cos(phi_max));
    const double t = thetas[i] + kPi;
    const int band = std::min(3, static_cast<int>(u * 4));
    const int sector = std::min(7, static_cast<int>(t / (2 * kPi) * 8));
    ++c[static_cast<std::size_t>(band * 8 + sector)];
  }
  return c;
}

}  // namespace

TEST_CASE("ranges: paper defaults, validation", "[sampling]") {
  ContactSamplingRanges<double> r;
  CHECK(r.r_max_mm == 5);
  CHECK(r.z_min_mm == 0.5);
  CHECK(r.z_max_mm == 6);
  CHECK(r.phi_max_deg == 25);
  CHECK(r.gamma_min_deg == -5);
  CHECK(r.gamma_max_deg == 5);
  CHECK(r.validate() == Status::ok);
  auto bad = r;
  bad.z_min_mm = 7;
  CHECK(bad.validate() == Status::invalid_argument);
  bad = r;
  bad.phi_max_deg = 95;
  CHECK(bad.validate() == Status::invalid_argument);
  bad = r;
  bad.r_max_mm = std::nan("");
  CHECK(bad.validate() == Status::non_finite_input);
  lieservo::sampling::Rng rng(1);
  std::vector<SurfaceContactPose<double>> out(3);
  CHECK(sampleSurfaceContactPoses(rng, 10, bad, out) == Status::non_finite_input);
  CHECK(out.size() == 3);  // unchanged unless ok
}

TEST_CASE("equation mappings: disk, cap, their inverse", "[sampling]") {
  // eq. 1 (eqn:disk_random_sampling)
  const auto xy = diskPoint(5.0, 0.25, kPi / 2);
  CHECK(xy(0) == Approx(0).margin(1e-15));
  CHECK(xy(1) == Approx(2.5));
  // eq. 2 (eqn:sphere_random_sampling): φ' = 0 → no tilt; φ' = 1 → tilt φ_max
  const double phi_max = lieservo::deg2rad(25.0);
  const auto ab0 = capAngles(phi_max, 0.0, 1.234);
  CHECK(ab0(0) == Approx(0).margin(1e-15));
  CHECK(ab0(1) == Approx(0).margin(1e-15));
  lieservo::sampling::Rng rng(3);
  for (int i = 0; i < 1000; ++i) {
    const double pp = uniformCanonical<double>(rng), th = 2 * kPi * uniformCanonical<double>(rng) - kPi;
    const auto ab = capAngles(phi_max, pp, th);
    // the rotated sensor axis Ry(β)Rx(α)e_z = (−p, q, r)
    const Eigen::Vector3d n = SO3<double>::fromEulerXYZ(ab(0), ab(1), 0.0).rotationMatrix().col(2);
    const double phi = std::acos(1 - (1 - std::cos(phi_max)) * pp);
    CHECK((n - contactAxis(ab(0), ab(1))).norm() < 1e-14);
    CHECK((n - Eigen::Vector3d(-std::sin(phi) * std::cos(th), std::sin(phi) * std::sin(th), std::cos(phi))).norm() < 1e-14);
    const auto pol = capPolar(ab(0), ab(1));
    CHECK(pol(0) == Approx(phi).margin(1e-7));  // acos near 1 loses ~sqrt(eps)
    if (phi > 1e-6) CHECK(std::remainder(pol(1) - th, 2 * kPi) == Approx(0).margin(1e-9));
  }
  const auto ab1 = capAngles(phi_max, 1.0, 0.3);
  CHECK(capPolar(ab1(0), ab1(1))(0) == Approx(phi_max).epsilon(1e-12));
}

TEST_CASE("samples respect the ranges (default and custom)", "[sampling]") {
  for (const auto& r : {ContactSamplingRanges<double>{},
                        ContactSamplingRanges<double>{2.0, 1.0, 1.5, 10.0, -1.0, 3.0}}) {
    const Drawn d = drawMany(11, 20000, r);
    const double phi_max = lieservo::deg2rad(r.phi_max_deg);
    for (const auto& p : d.poses) {
      REQUIRE(std::hypot(p.x, p.y) <= r.r_max_mm * (1 + 1e-15));
      REQUIRE(p.z >= r.z_min_mm);
      REQUIRE(p.z <= r.z_max_mm);
      REQUIRE(capPolar(p.alpha, p.beta)(0) <= phi_max + 1e-7);
      REQUIRE(std::abs(p.alpha) <= phi_max + 1e-15);
      REQUIRE(std::abs(p.beta) <= phi_max + 1e-15);
      REQUIRE(p.gamma >= lieservo::deg2rad(r.gamma_min_deg));
      REQUIRE(p.gamma <= lieservo::deg2rad(r.gamma_max_deg));
    }
  }
  // float instantiation
  lieservo::sampling::Rng rf(1);
  for (int i = 0; i < 1000; ++i) {
    const auto p = sampleSurfaceContactPose<float>(rf, ContactSamplingRanges<float>{});
    REQUIRE(std::hypot(p.x, p.y) <= 5.0f * (1 + 1e-6f));
    REQUIRE(capPolar(p.alpha, p.beta)(0) <= lieservo::deg2rad(25.0f) + 1e-3f);
    REQUIRE((surfaceContactTransform(p).matrix() - SE3<float>::fromEulerXYZ6(p.euler6()).matrix()).cwiseAbs().maxCoeff() < 1e-5f);
  }
  // the same seed gives the same plan; sorting by depth keeps the multiset
  lieservo::sampling::Rng a(5), b(5);
  std::vector<SurfaceContactPose<double>> p1, p2;
  REQUIRE(sampleSurfaceContactPoses(a, 200, ContactSamplingRanges<double>{}, p1) == Status::ok);
  REQUIRE(sampleSurfaceContactPoses(b, 200, ContactSamplingRanges<double>{}, p2, true) == Status::ok);
  for (std::size_t i = 1; i < p2.size(); ++i) REQUIRE(p2[i - 1].z <= p2[i].z);
  double s1 = 0, s2 = 0;
  for (std::size_t i = 0; i < 200; ++i) {
    s1 += p1[i].x + p1[i].gamma;
    s2 += p2[i].x + p2[i].gamma;
  }
  CHECK(s1 == Approx(s2).epsilon(1e-12));
}

TEST_CASE("translational shear is uniform over the disk (eq. 1, eqn:disk_random_sampling)", "[sampling][statistics]") {
  const Drawn d = drawMany(2024, kN);
  std::vector<double> xs, ys, u_r2, u_theta;
  for (const auto& p : d.poses) {
    xs.push_back(p.x);
    ys.push_back(p.y);
    u_r2.push_back((p.x * p.x + p.y * p.y) / 25.0);  // area fraction: U(0,1) for a uniform disk
    u_theta.push_back((std::atan2(p.y, p.x) + kPi) / (2 * kPi));
  }
  const double chi2 = chiSquareEqualCells(diskCells(xs, ys, 5.0));
  INFO("chi2 = " << chi2 << " (df 31, critical 61.10 at alpha 0.001)");
  CHECK(chiSquarePValue(chi2, 31) > kAlpha);
  CHECK(ksPValue(ksStatisticUniform(u_r2), kN) > kAlpha);
  CHECK(ksPValue(ksStatisticUniform(u_theta), kN) > kAlpha);

  // Negative control: r = r_max·r' (uniform radius, a common mistake) is rejected by both.
  lieservo::sampling::Rng rng(2024);
  std::vector<double> wx, wy, wu;
  for (std::size_t i = 0; i < kN; ++i) {
    const double r = 5.0 * uniformCanonical<double>(rng), t = 2 * kPi * uniformCanonical<double>(rng);
    wx.push_back(r * std::cos(t));
    wy.push_back(r * std::sin(t));
    wu.push_back(r * r / 25.0);
  }
  CHECK(chiSquarePValue(chiSquareEqualCells(diskCells(wx, wy, 5.0)), 31) < kAlpha);
  CHECK(ksPValue(ksStatisticUniform(wu), kN) < kAlpha);
}

TEST_CASE("contact angles are uniform over the spherical cap (eq. 2, eqn:sphere_random_sampling)", "[sampling][statistics]") {
  const double phi_max = lieservo::deg2rad(25.0);
  const Drawn d = drawMany(4711, kN);
  std::vector<double> phis, thetas, u_area, u_theta;
  for (const auto& p : d.poses) {
    // recover the tilt and azimuth of the sensor axis from (α, β) alone
    const Eigen::Vector3d n = SO3<double>::fromEulerXYZ(p.alpha, p.beta, 0.0).rotationMatrix().col(2);
    const double phi = std::atan2(std::hypot(n(0), n(1)), n(2));
    const double theta = std::atan2(n(1), -n(0));
    phis.push_back(phi);
    thetas.push_back(theta);
    // the cap's area element: the area above tilt φ is ∝ 1 − cos φ, uniform on [0,1] under H0
    u_area.push_back((1 - std::cos(phi)) / (1 - std::cos(phi_max)));
    u_theta.push_back((theta + kPi) / (2 * kPi));
  }
  const double chi2 = chiSquareEqualCells(capCells(phis, thetas, phi_max));
  INFO("chi2 = " << chi2 << " (df 31, critical 61.10 at alpha 0.001)");
  CHECK(chiSquarePValue(chi2, 31) > kAlpha);
  CHECK(ksPValue(ksStatisticUniform(u_area), kN) > kAlpha);
  CHECK(ksPValue(ksStatisticUniform(u_theta), kN) > kAlpha);

  // Negative control: tilt uniform in angle, φ = φ_max·φ' (over-samples the cap's centre).
  lieservo::sampling::Rng rng(4711);
  std::vector<double> wp, wt, wu;
  for (std::size_t i = 0; i < kN; ++i) {
    const double phi = phi_max * uniformCanonical<double>(rng);
    const double t = 2 * kPi * uniformCanonical<double>(rng) - kPi;
    wp.push_back(phi);
    wt.push_back(t);
    wu.push_back((1 - std::cos(phi)) / (1 - std::cos(phi_max)));
  }
  CHECK(chiSquarePValue(chiSquareEqualCells(capCells(wp, wt, phi_max)), 31) < kAlpha);
  CHECK(ksPValue(ksStatisticUniform(wu), kN) < kAlpha);
}

TEST_CASE("depth and rotational shear are uniform", "[sampling][statistics]") {
  const Drawn d = drawMany(99, kN);
  std::vector<double> uz, ug;
  for (const auto& p : d.poses) {
    uz.push_back((p.z - 0.5) / 5.5);
    ug.push_back((lieservo::rad2deg(p.gamma) + 5.0) / 10.0);
  }
  CHECK(ksPValue(ksStatisticUniform(uz), kN) > kAlpha);
  CHECK(ksPValue(ksStatisticUniform(ug), kN) > kAlpha);
  // Negative control: the power claim — a CDF shift of 0.02 (> 0.0145) is rejected.
  for (double& u : uz) u = std::min(1.0, u + 0.02);
  CHECK(ksPValue(ksStatisticUniform(uz), kN) < kAlpha);
}

TEST_CASE("X_par * X_perp equals the Euler 6-vector (x, y, z, alpha, beta, gamma) exactly", "[sampling][composition]") {
  // Holds for any angles, not only the sampled ranges: Rz(γ) fixes the normal (0, 0, z).
  ContactSamplingRanges<double> wide{20.0, -10.0, 10.0, 89.0, -180.0, 180.0};
  for (const auto& r : {ContactSamplingRanges<double>{}, wide}) {
    const Drawn d = drawMany(7, 2000, r);
    for (const auto& p : d.poses) {
      const SE3<double> X_fs = surfaceContactTransform(p);
      const SE3<double> E = SE3<double>::fromEulerXYZ6(p.euler6());
      REQUIRE((X_fs.matrix() - E.matrix()).cwiseAbs().maxCoeff() < 1e-13);
      REQUIRE((X_fs.toEulerXYZ6() - p.euler6()).cwiseAbs().maxCoeff() < 1e-11);
      // the two factors are the data set's pose_* and shear_* 6-vectors
      Eigen::Matrix<double, 6, 1> pose6, shear6;
      pose6 << 0, 0, p.z, p.alpha, p.beta, 0;
      shear6 << p.x, p.y, 0, 0, 0, p.gamma;
      REQUIRE(normalContactTransform(p.z, p.alpha, p.beta).isApprox(SE3<double>::fromEulerXYZ6(pose6), 1e-14));
      REQUIRE(shearTransform(p.x, p.y, p.gamma).isApprox(SE3<double>::fromEulerXYZ6(shear6), 1e-14));
      // label ξ = log(X_fs⁻¹)^∨
      REQUIRE((surfaceContactLabel(p) - E.inverse().log()).cwiseAbs().maxCoeff() < 1e-11);
    }
  }
}

TEST_CASE("other composition orders do NOT give the Euler 6-vector", "[sampling][composition]") {
  // Documents why the definition matters (docs/data_collection.md): the worst-case gap over
  // the paper's ranges for three plausible misreadings.
  const Drawn d = drawMany(8, 5000);
  double gap_axis = 0, gap_order = 0, gap_par = 0, gap_order_rot = 0;
  for (const auto& p : d.poses) {
    const SE3<double> E = SE3<double>::fromEulerXYZ6(p.euler6());
    const SE3<double> X_par = shearTransform(p.x, p.y, p.gamma);
    const SE3<double> X_perp = normalContactTransform(p.z, p.alpha, p.beta);
    // (a) press along the tilted sensor axis: X_perp' = R(α,β)·T(0,0,z)
    const SE3<double> R_ab(SO3<double>::fromEulerXYZ(p.alpha, p.beta, 0.0), Eigen::Vector3d::Zero());
    const SE3<double> X_perp_axis = R_ab * SE3<double>(SO3<double>(), Eigen::Vector3d(0, 0, p.z));
    gap_axis = std::max(gap_axis, ((X_par * X_perp_axis).translation() - E.translation()).norm());
    // (b) shear applied in the sensor frame: X_perp·X_par
    const SE3<double> B = X_perp * X_par;
    gap_order = std::max(gap_order, (B.translation() - E.translation()).norm());
    gap_order_rot = std::max(gap_order_rot, (B.so3().inverse() * E.so3()).log().norm());
    // (c) X_par as "rotate γ, then translate in the rotated frame": Rz(γ)·T(x, y, 0)
    const SE3<double> Rz(SO3<double>::fromEulerXYZ(0.0, 0.0, p.gamma), Eigen::Vector3d::Zero());
    const SE3<double> X_par_c = Rz * SE3<double>(SO3<double>(), Eigen::Vector3d(p.x, p.y, 0));
    gap_par = std::max(gap_par, ((X_par_c * X_perp).translation() - E.translation()).norm());
  }
  INFO("max gaps over the paper's ranges: (a) " << gap_axis << " mm, (b) " << gap_order << " mm / "
                                              << gap_order_rot << " rad, (c) " << gap_par << " mm");
  CHECK(gap_axis > 2.0);       // |z(n − e_z)| = 2z·sin(φ/2) ≤ 2·6·sin 12.5° = 2.60 mm
  CHECK(gap_order > 1.5);      // |(R(α,β) − I)(x, y, 0)| ≤ 2·r_max·sin(φ_max/2) = 2.16 mm
  CHECK(gap_order_rot > 0.01); // Ry(β)Rx(α)Rz(γ) ≠ Rz(γ)Ry(β)Rx(α)
  CHECK(gap_par > 0.3);        // ≈ 2·r_max·sin(γ_max/2) = 0.436 mm
  WARN("composition gaps (a) axis " << gap_axis << " mm, (b) order " << gap_order << " mm/" << gap_order_rot
                                    << " rad, (c) Rz*T " << gap_par << " mm");
}
