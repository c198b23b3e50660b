// examples/collection/contact_sampling.hpp — surface contact poses and post-contact shears
// for training-data collection (an example built on the library, not part of it) (paper Section 3.1.1 (sec:surface_contact_poses), Section 3.1.2 (sec:data_collection)).
//
// A sample is the Euler 6-vector (x, y, z, α, β, γ) of the sensor frame {s} in the surface
// feature frame {f} ({f}: z normal to and into the surface, aligned with {s} just out of
// contact):
//   (x, y)  translational shear, uniform over a disk of radius r_max   (eq. 1, eqn:disk_random_sampling)
//   z       contact depth, uniform in [z_min, z_max]
//   (α, β)  contact angles, uniform over a spherical cap of half-angle φ_max
//                                                                       (eq. 2, eqn:sphere_random_sampling)
//   γ       rotational shear about the normal, uniform in [γ_min, γ_max]
//
// Composition (Section 3.1.1, sec:surface_contact_poses):
//   X_perp = [ Ry(β) Rx(α) | (0, 0, z) ]   rotate by extrinsic-xyz (α, β), press in by z
//                                           along the surface normal (f's z axis)
//   X_par  = [ Rz(γ)       | (x, y, 0) ]   translate (x, y) in the surface plane, rotate γ
//                                           about the normal
//   X_fs   = X_par · X_perp = [ Rz(γ) Ry(β) Rx(α) | (x, y, z) ]
// i.e. X_fs is exactly the extrinsic-xyz Euler 6-vector (x, y, z, α, β, γ): Rz(γ) leaves
// (0, 0, z) fixed, so no cross term appears. The equality needs both the press along f's z
// axis (not along the tilted sensor axis) and the shear applied on the left (in {f}, not in
// {s}); see docs/data_collection.md. Training label: ξ = log(X_fs⁻¹)^∨ = [ρ; φ].
//
// Units: lengths in mm (the caller's unit), angles in radians inside; the ranges are given
// in mm and degrees (the paper's and the data set's units) and converted here.
// Sampling is seeded: every draw comes from the caller's uniform random bit generator via
// uniformCanonical() (sampling/random.hpp), so a seed gives the same sequence on every platform.
#pragma once

#include <lieservo/groups/se3.hpp>
#include <lieservo/groups/so3.hpp>
#include <lieservo/sampling/random.hpp>
#include <lieservo/status.hpp>
#include <lieservo/units.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace lieservo::sampling {

/// Sampling ranges at the edge, in mm and degrees. Defaults: the paper's Section 3.1.2 (sec:data_collection)
/// (and the shared data set's collect_params.json / meta.json).
template <class Scalar = double>
struct ContactSamplingRanges {
  Scalar r_max_mm = Scalar(5);          ///< disk radius of the translational shear (x, y)
  Scalar z_min_mm = Scalar(0.5);        ///< contact depth range
  Scalar z_max_mm = Scalar(6);
  Scalar phi_max_deg = Scalar(25);      ///< half-angle of the spherical cap of contact angles
  Scalar gamma_min_deg = Scalar(-5);    ///< rotational shear about the normal
  Scalar gamma_max_deg = Scalar(5);

  /// ok, non_finite_input, or invalid_argument (r_max < 0, z_min > z_max,
  /// φ_max ∉ [0°, 90°], γ_min > γ_max).
  Status validate() const noexcept {
    const Scalar v[] = {r_max_mm, z_min_mm, z_max_mm, phi_max_deg, gamma_min_deg, gamma_max_deg};
    for (Scalar s : v) {
      if (!std::isfinite(s)) return Status::non_finite_input;
    }
    if (r_max_mm < 0 || z_min_mm > z_max_mm || phi_max_deg < 0 || phi_max_deg > 90 ||
        gamma_min_deg > gamma_max_deg) {
      return Status::invalid_argument;
    }
    return Status::ok;
  }
};

/// A surface contact pose and post-contact shear: lengths in mm, angles in radians.
template <class Scalar = double>
struct SurfaceContactPose {
  using Vector6 = Eigen::Matrix<Scalar, 6, 1>;
  Scalar x{0}, y{0};                  ///< translational shear (shear_x, shear_y)
  Scalar z{0};                        ///< contact depth (pose_z)
  Scalar alpha{0}, beta{0};           ///< contact angles, extrinsic xyz (pose_Rx, pose_Ry)
  Scalar gamma{0};                    ///< rotational shear about the normal (shear_Rz)

  /// (x, y, z, α, β, γ), radians.
  Vector6 euler6() const {
    Vector6 e;
    e << x, y, z, alpha, beta, gamma;
    return e;
  }
  /// (x, y, z, α, β, γ) with angles in degrees: the data set's label units.
  Vector6 euler6Degrees() const {
    Vector6 e;
    e << x, y, z, lieservo::rad2deg(alpha), lieservo::rad2deg(beta), lieservo::rad2deg(gamma);
    return e;
  }
  static SurfaceContactPose fromEuler6Degrees(const Vector6& e) {
    SurfaceContactPose p;
    p.x = e(0);
    p.y = e(1);
    p.z = e(2);
    p.alpha = lieservo::deg2rad(e(3));
    p.beta = lieservo::deg2rad(e(4));
    p.gamma = lieservo::deg2rad(e(5));
    return p;
  }
};

/// The uniform variates behind one sample (for diagnostics and the statistical tests).
template <class Scalar = double>
struct ContactDraws {
  Scalar r_prime{0}, disk_theta{0};   ///< eq. 1 (eqn:disk_random_sampling): r' ~ U(0,1), θ ~ U(0, 2π)
  Scalar z_unit{0};                   ///< z = z_min + (z_max − z_min)·z_unit
  Scalar phi_prime{0}, cap_theta{0};  ///< eq. 2 (eqn:sphere_random_sampling): φ' ~ U(0,1), θ ~ U(0, 2π)
  Scalar gamma_unit{0};               ///< γ = γ_min + (γ_max − γ_min)·gamma_unit
};

/// eq. 1 (eqn:disk_random_sampling): x = r cos θ, y = r sin θ, r = r_max √r'. Returns (x, y).
template <class Scalar>
Eigen::Matrix<Scalar, 2, 1> diskPoint(Scalar r_max, Scalar r_prime, Scalar theta) {
  const Scalar r = r_max * std::sqrt(r_prime);
  return {r * std::cos(theta), r * std::sin(theta)};
}

/// eq. 2 (eqn:sphere_random_sampling): φ = arccos(1 − (1 − cos φ_max) φ'), (p, q, r) =
/// (sin φ cos θ, sin φ sin θ, cos φ), α = −arcsin q, β = −atan2(p, r). Returns (α, β), radians.
template <class Scalar>
Eigen::Matrix<Scalar, 2, 1> capAngles(Scalar phi_max, Scalar phi_prime, Scalar theta) {
  const Scalar phi = std::acos(Scalar(1) - (Scalar(1) - std::cos(phi_max)) * phi_prime);
  const Scalar p = std::sin(phi) * std::cos(theta);
  const Scalar q = std::sin(phi) * std::sin(theta);
  const Scalar r = std::cos(phi);
  return {-std::asin(q), -std::atan2(p, r)};
}

/// The sensor's axis in {f} after the contact rotation: Ry(β) Rx(α) e_z =
/// (sin β cos α, −sin α, cos β cos α) = (−p, q, r) for the (p, q, r) of capAngles.
template <class Scalar>
Eigen::Matrix<Scalar, 3, 1> contactAxis(Scalar alpha, Scalar beta) {
  return {std::sin(beta) * std::cos(alpha), -std::sin(alpha), std::cos(beta) * std::cos(alpha)};
}

/// Inverse of capAngles' trigonometry: (φ, θ) with φ ∈ [0, π] the tilt of the sensor axis
/// from the surface normal and θ ∈ (−π, π] its azimuth (θ = atan2(q, p)).
template <class Scalar>
Eigen::Matrix<Scalar, 2, 1> capPolar(Scalar alpha, Scalar beta) {
  const Eigen::Matrix<Scalar, 3, 1> n = contactAxis(alpha, beta);
  const Scalar c = n(2) > Scalar(1) ? Scalar(1) : n(2);
  return {std::acos(c), std::atan2(n(1), -n(0))};
}

/// One surface contact pose and shear (Section 3.1.2, sec:data_collection, items 1–4). Draw order, fixed
/// for reproducibility: r', θ_disk, z, φ', θ_cap, γ. `ranges` must validate() (not checked
/// here: sampleSurfaceContactPoses checks it).
template <class Scalar, class URBG>
SurfaceContactPose<Scalar> sampleSurfaceContactPose(URBG& rng,
                                                   const ContactSamplingRanges<Scalar>& ranges,
                                                   ContactDraws<Scalar>* draws = nullptr) {
  constexpr Scalar two_pi = Scalar(2) * lieservo::pi<Scalar>();
  ContactDraws<Scalar> d;
  d.r_prime = uniformCanonical<Scalar>(rng);
  d.disk_theta = two_pi * uniformCanonical<Scalar>(rng);
  d.z_unit = uniformCanonical<Scalar>(rng);
  d.phi_prime = uniformCanonical<Scalar>(rng);
  d.cap_theta = two_pi * uniformCanonical<Scalar>(rng);
  d.gamma_unit = uniformCanonical<Scalar>(rng);

  SurfaceContactPose<Scalar> s;
  const auto xy = diskPoint(ranges.r_max_mm, d.r_prime, d.disk_theta);
  s.x = xy(0);
  s.y = xy(1);
  s.z = ranges.z_min_mm + (ranges.z_max_mm - ranges.z_min_mm) * d.z_unit;
  const auto ab = capAngles(lieservo::deg2rad(ranges.phi_max_deg), d.phi_prime, d.cap_theta);
  s.alpha = ab(0);
  s.beta = ab(1);
  s.gamma = lieservo::deg2rad(ranges.gamma_min_deg +
                             (ranges.gamma_max_deg - ranges.gamma_min_deg) * d.gamma_unit);
  if (draws != nullptr) *draws = d;
  return s;
}

/// Default ranges (the paper's).
template <class Scalar = double, class URBG>
SurfaceContactPose<Scalar> sampleSurfaceContactPose(URBG& rng) {
  return sampleSurfaceContactPose<Scalar>(rng, ContactSamplingRanges<Scalar>{});
}

/// n samples in draw order (optionally stably sorted by increasing depth z, as the shared
/// data set's rows are). The same seed and n give the same sequence: the collection tool
/// regenerates it on resume. Returns ranges.validate()'s status; out unchanged unless ok.
template <class Scalar, class URBG>
Status sampleSurfaceContactPoses(URBG& rng, std::size_t n, const ContactSamplingRanges<Scalar>& ranges,
                                 std::vector<SurfaceContactPose<Scalar>>& out,
                                 bool sort_by_depth = false) {
  const Status st = ranges.validate();
  if (st != Status::ok) return st;
  std::vector<SurfaceContactPose<Scalar>> v;
  v.reserve(n);
  for (std::size_t i = 0; i < n; ++i) v.push_back(sampleSurfaceContactPose<Scalar>(rng, ranges));
  if (sort_by_depth) {
    std::stable_sort(v.begin(), v.end(),
                     [](const SurfaceContactPose<Scalar>& a, const SurfaceContactPose<Scalar>& b) {
                       return a.z < b.z;
                     });
  }
  out.swap(v);
  return Status::ok;
}

/// X_perp: rotate by extrinsic-xyz (α, β), then press in by z along the surface normal
/// (f's z axis): [Ry(β) Rx(α) | (0, 0, z)] = Euler6(0, 0, z, α, β, 0) — the data set's pose_*
/// columns. (Section 3.1.1, sec:surface_contact_poses, "normal contact motion")
template <class Scalar>
SE3<Scalar> normalContactTransform(Scalar z, Scalar alpha, Scalar beta) {
  return SE3<Scalar>(SO3<Scalar>::fromEulerXYZ(alpha, beta, Scalar(0)),
                     typename SE3<Scalar>::Vector3(Scalar(0), Scalar(0), z));
}

/// X_par: translate by (x, y) in the surface plane and rotate γ about the normal:
/// [Rz(γ) | (x, y, 0)] = Euler6(x, y, 0, 0, 0, γ) — the data set's shear_* columns.
/// (Section 3.1.1, sec:surface_contact_poses, "tangential shear motion")
template <class Scalar>
SE3<Scalar> shearTransform(Scalar x, Scalar y, Scalar gamma) {
  return SE3<Scalar>(SO3<Scalar>::fromEulerXYZ(Scalar(0), Scalar(0), gamma),
                     typename SE3<Scalar>::Vector3(x, y, Scalar(0)));
}

/// X_fs = X_par · X_perp (Section 3.1.1, sec:surface_contact_poses). Equals SE3::fromEulerXYZ6(pose.euler6())
/// exactly in exact arithmetic (see the file comment); computed here by the composition.
template <class Scalar>
SE3<Scalar> surfaceContactTransform(const SurfaceContactPose<Scalar>& pose) {
  return shearTransform(pose.x, pose.y, pose.gamma) *
         normalContactTransform(pose.z, pose.alpha, pose.beta);
}

/// Training label ξ = log(X_fs⁻¹)^∨ = [ρ; φ] (mm, radians; translation first).
template <class Scalar>
typename SE3<Scalar>::Tangent surfaceContactLabel(const SE3<Scalar>& X_fs) {
  return X_fs.inverse().log();
}

template <class Scalar>
typename SE3<Scalar>::Tangent surfaceContactLabel(const SurfaceContactPose<Scalar>& pose) {
  return surfaceContactLabel(surfaceContactTransform(pose));
}

}  // namespace lieservo::sampling
