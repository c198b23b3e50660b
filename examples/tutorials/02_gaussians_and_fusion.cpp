// Tutorial 02 — concentrated Gaussians on SE(3) and their fusion.
//
// An uncertain pose is a concentrated Gaussian: a mean X̄ and a covariance Σ of a small LEFT
// perturbation ε, X = exp(ε^) X̄ with ε ~ N(0, Σ) (paper eq. 35).
// A GDN gives its estimate in the tangent space instead: a mean μ and standard deviations σ of
// ξ = ln(X)^∨. fromTangentGaussian converts one into the other (eq. 14), and fuse() multiplies
// two such beliefs into one (Algorithm 3), iterating because the product is only Gaussian to
// first order around an operating point.
// The program checks what it claims and exits with status 1 if a check fails.
//
// Build and run:  cmake --build <build> --target lieservo_tutorial_02_gaussians_and_fusion &&
//                 <build>/examples/tutorials/lieservo_tutorial_02_gaussians_and_fusion
#include <cmath>
#include <cstdio>

#include <lieservo/lieservo.hpp>
#include <lieservo/sampling/random.hpp>

using namespace lieservo;
using SE3d = SE3<double>;
using Tangent = SE3d::Tangent;
using Gaussian = ConcentratedGaussian<SE3d>;

namespace {

int failures = 0;
void check(bool ok, const char* what) {
  std::printf("  %-70s %s\n", what, ok ? "ok" : "FAILED");
  failures += !ok;
}

void print(const char* name, const Gaussian& g) {
  const Tangent m = g.mean.log();
  std::printf("  %-12s mean ln = (%6.2f %6.2f %6.2f mm, %6.2f %6.2f %6.2f deg)  sd = (%.2f %.2f %.2f mm, %.2f %.2f %.2f deg)\n",
              name, m[0], m[1], m[2], rad2deg(m[3]), rad2deg(m[4]), rad2deg(m[5]), std::sqrt(g.covariance(0, 0)),
              std::sqrt(g.covariance(1, 1)), std::sqrt(g.covariance(2, 2)), rad2deg(std::sqrt(g.covariance(3, 3))),
              rad2deg(std::sqrt(g.covariance(4, 4))), rad2deg(std::sqrt(g.covariance(5, 5))));
}

// The true contact: 2 mm shear, 3 mm deep, tilted 10° and twisted 5°.
Tangent trueContact() {
  Tangent truth;
  truth << 2.0, 0.0, 3.0, deg2rad(10.0), 0.0, deg2rad(5.0);
  return truth;
}

// 1. Two estimates of it, as two GDN outputs would be: (μ, σ) in the tangent space, each made a
//    concentrated Gaussian on SE(3).
bool lessonFromTangent(const Tangent& truth, Gaussian& a, Gaussian& b) {
  Tangent mu_a = truth, mu_b = truth, sigma_a, sigma_b;
  mu_a[0] += 0.4;  // estimate a is 0.4 mm off in x and sure about the rotation
  mu_b[3] += deg2rad(2.0);  // estimate b is 2° off in α and sure about the translation
  sigma_a << 0.5, 0.5, 0.2, deg2rad(0.5), deg2rad(0.5), deg2rad(1.0);
  sigma_b << 0.1, 0.1, 0.05, deg2rad(3.0), deg2rad(3.0), deg2rad(3.0);

  std::printf("1. from the GDN's tangent (mu, sigma) to a concentrated Gaussian\n");
  const bool ok = fromTangentGaussian(mu_a, sigma_a, a) == Status::ok && fromTangentGaussian(mu_b, sigma_b, b) == Status::ok;
  check(ok, "fromTangentGaussian: ok for both");
  print("a", a);
  print("b", b);
  // b's translation sd comes out as 0.13, 0.14, 0.07 mm, not its σ of 0.10, 0.10, 0.05: Σ =
  // J(μ) diag(σ²) J(μ)ᵀ (eq. 14) is the covariance of a LEFT perturbation of the whole pose,
  // and J's upper-right block (≈ ½ ρ^ at small angles) turns a tangent rotation error dφ into
  // a translation error ½ ρ × dφ. With ρ = (2, 0, 3) mm and b's 3° (0.052 rad) that adds
  // 0.078, 0.094 and 0.052 mm in quadrature: √(0.10² + 0.078²) = 0.13, and so on.
  std::printf("  (b's translation sd exceeds its sigma: J(mu) carries its 3 deg rotation spread into the\n"
              "   translation as 1/2 rho x dphi, about 0.08, 0.09, 0.05 mm in quadrature)\n");
  {  // the claim, checked: sd_i² ≈ σ_i² + Σ_j (½ ρ^_ij σ_φj)² (first order in the angles)
    const Eigen::Matrix3d half_rho_hat = 0.5 * SO3d::hat(Eigen::Vector3d(mu_b.head<3>()));
    bool close = true;
    for (int i = 0; i < 3; ++i) {
      const double leak = half_rho_hat.row(i).cwiseProduct(sigma_b.tail<3>().transpose()).norm();
      close = close && std::abs(std::sqrt(b.covariance(i, i)) - std::hypot(sigma_b[i], leak)) < 0.01;
    }
    check(close, "b's sd = sqrt(sigma^2 + (rho x sigma_phi / 2)^2) within 0.01 mm");
  }
  check((a.mean.log() - mu_a).norm() < 1e-12, "the mean is exp(mu)");
  return ok;
}

// 2. Fusion: the normalised product of the two (Algorithm 3).
bool lessonFusion(const Tangent& truth, const Gaussian& a, const Gaussian& b, FusionResult<SE3d>& r) {
  std::printf("2. fusion: each estimate corrects the other where it is the surer one\n");
  FusionOptions<double> options;  // the paper's real-time mode: 5 iterations
  const bool ok = fuse(a, b, options, r) == Status::ok;
  check(ok, "fuse: ok");
  print("fused", r.fused);
  const Tangent err_a = lminus(a.mean, SE3d::exp(truth)), err_b = lminus(b.mean, SE3d::exp(truth));
  const Tangent err_f = lminus(r.fused.mean, SE3d::exp(truth));
  std::printf("  error |x| a %.3f, b %.3f, fused %.3f mm;  |alpha| a %.3f, b %.3f, fused %.3f deg\n",
              std::abs(err_a[0]), std::abs(err_b[0]), std::abs(err_f[0]), rad2deg(std::abs(err_a[3])),
              rad2deg(std::abs(err_b[3])), rad2deg(std::abs(err_f[3])));
  check(std::abs(err_f[0]) < std::abs(err_a[0]) && std::abs(err_f[3]) < std::abs(err_b[3]),
        "fused x beats a, fused alpha beats b");
  bool tighter = true;
  for (int i = 0; i < 6; ++i)
    tighter = tighter && r.fused.covariance(i, i) < 1.01 * std::min(a.covariance(i, i), b.covariance(i, i));
  // (exactly so for a linear product; the 1 % allows for the Jacobians around the operating point)
  check(tighter, "every fused variance is below both inputs' (information adds up)");
  return ok;
}

// 3. The iteration: fusion relinearises about its latest estimate.
bool lessonIteration(const Gaussian& a, const Gaussian& b, const FusionResult<SE3d>& r) {
  std::printf("3. the iteration: each update moves the operating point less\n");
  for (int n = 1; n <= 5; ++n) {
    FusionOptions<double> o;
    o.max_iterations = n;
    FusionResult<SE3d> rn;
    if (fuse(a, b, o, rn) != Status::ok) return false;
    std::printf("  %d iteration(s): last step %.2e, distance to the 5-iteration result %.2e\n", n, rn.step_norm,
                lminus(rn.fused.mean, r.fused.mean).norm());
  }
  return true;
}

// 4. What the covariance means: the spread of left perturbations.
void lessonMonteCarlo(const Gaussian& g) {
  std::printf("4. Monte Carlo: samples X = exp(eps^) Xbar with eps ~ N(0, Sigma) have covariance Sigma\n");
  sampling::Rng rng(2);
  const Eigen::LLT<SE3d::Jacobian> llt(g.covariance);
  SE3d::Jacobian S = SE3d::Jacobian::Zero();
  const int N = 20000;
  for (int k = 0; k < N; ++k) {
    const Tangent z = sampling::standardNormalVector<6>(rng);  // z ~ N(0, I)
    const SE3d X = lplus(g.mean, Tangent(llt.matrixL() * z));
    const Tangent e = lminus(X, g.mean);
    S += e * e.transpose() / N;
  }
  double worst = 0;
  for (int i = 0; i < 6; ++i) worst = std::max(worst, std::abs(S(i, i) / g.covariance(i, i) - 1));
  std::printf("  largest relative difference of a sample variance: %.3f (expected ~ sqrt(2/N) = %.3f)\n", worst,
              std::sqrt(2.0 / N));
  check(worst < 5 * std::sqrt(2.0 / N), "sample variances within 5 standard errors");
}

}  // namespace

int main() {
  const Tangent truth = trueContact();
  Gaussian a, b;
  FusionResult<SE3d> r;
  if (lessonFromTangent(truth, a, b) && lessonFusion(truth, a, b, r)) {
    if (!lessonIteration(a, b, r)) return 1;
    lessonMonteCarlo(r.fused);
  }
  std::printf("%s\n", failures == 0 ? "all checks passed" : "SOME CHECKS FAILED");
  return failures == 0 ? 0 : 1;
}
