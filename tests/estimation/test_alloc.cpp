// Proof that the real-time estimation path never allocates: it counts allocations
// (tests/support/allocation_counter.hpp) over many filter steps (SE(3), double and
// float; gating on and off; bad inputs; N-ary fusion) with counting enabled. The count must be 0.
#include <catch2/catch.hpp>

#include <new>
#include <vector>

#include <lieservo/sampling/random.hpp>

#include "allocation_counter.hpp"
#include "estimation_test_helpers.hpp"

using namespace lieservo;
using namespace lieservo::est_test;

namespace {

template <class S>
void runAllocationFreeSteps(int steps) {
  using G = SE3<S>;
  using CG = ConcentratedGaussian<G>;
  using Tangent = typename G::Tangent;
  lieservo::sampling::Rng rng(53);
  // Pre-generate every input outside the counting scope.
  std::vector<G> poses;
  std::vector<Tangent> mus, sigmas;
  G sens = G::exp(randn<Tangent>(rng, 1.0));
  for (int k = 0; k < steps; ++k) {
    sens = sens * G::exp(randn<Tangent>(rng, 0.02));
    poses.push_back(sens);
    mus.push_back(randn<Tangent>(rng, 0.3));
    Tangent s;
    s << S(0.4), S(0.4), S(0.12), S(0.5 * kDeg), S(0.6 * kDeg), S(1.2 * kDeg);
    sigmas.push_back(s);
  }
  CG bad;
  bad.covariance(0, 0) = std::numeric_limits<S>::quiet_NaN();
  for (bool gating : {false, true}) {
    typename DiscriminativeBayesFilter<G>::Options opt;
    opt.gating = gating;
    DiscriminativeBayesFilter<G> filter(opt);
    DiscriminativeBayesFilter<G, ClosedFormJacobian> filter_cf(
        typename DiscriminativeBayesFilter<G, ClosedFormJacobian>::Options{});
    typename DiscriminativeBayesFilter<G>::Options opt_sqrt;  // the square-root form
    opt_sqrt.fusion.form = FusionForm::square_root;
    DiscriminativeBayesFilter<G> filter_sqrt(opt_sqrt);
    long ok = 0;
    long allocations = -1;
    {
      lieservo::test::AllocationCounter counter;
      CG obs;
      (void)fromTangentGaussian(mus[0], sigmas[0], obs);
      (void)filter.step(poses[0], obs);  // initialisation
      (void)filter_cf.step(poses[0], obs);
      (void)filter_sqrt.step(poses[0], obs);
      for (int k = 1; k < steps; ++k) {
        (void)fromTangentGaussian(mus[size_t(k)], sigmas[size_t(k)], obs);
        const Status s = filter.step(poses[size_t(k)], obs);
        ok += (s == Status::ok || s == Status::outlier_rejected);
        ok += (filter_cf.step(poses[size_t(k)], obs) == Status::ok);
        ok += (filter_sqrt.step(poses[size_t(k)], obs) == Status::ok);
        if (k % 100 == 0) (void)filter.step(poses[size_t(k)], bad);  // error path
      }
      // N-ary fusion, tolerance mode, NIS, transform, mahalanobis.
      CG f[4] = {obs, filter.filtered(), filter.belief(), filter_cf.filtered()};
      FusionResult<G> r;
      FusionOptions<S> fo;
      fo.max_iterations = 20;
      fo.tolerance = S(1e-6);
      (void)fuse<ClosedFormJacobian>(f, 4, fo, r);
      S nis;
      (void)normalizedInnovationSquared(obs, filter.belief(), nis);
      CG t;
      (void)transform(obs, poses[1], paperProcessNoise<G>(), t);
      (void)mahalanobisSquared(obs, poses[2], nis);
      allocations = counter.count();
    }
    INFO("gating " << gating << ", ok steps " << ok);
    CHECK(allocations == 0);
    CHECK(ok >= 3 * (steps - 1) - 2);
  }
}

}  // namespace

TEST_CASE("the filter step and fusion never allocate (SE(3) double)", "[estimation][realtime]") {
  // Sanity check of the counter itself.
  long n = 0;
  {
    lieservo::test::AllocationCounter counter;
    // Through a volatile pointer: a new-expression whose result does not escape may be elided
    // (C++14 [expr.new]), and clang does elide it.
    std::vector<int>* volatile v = new std::vector<int>(10);
    delete v;
    n = counter.count();
  }
  REQUIRE(n >= 1);
  runAllocationFreeSteps<double>(5000);
}

TEST_CASE("the filter step and fusion never allocate (SE(3) float)", "[estimation][realtime]") {
  runAllocationFreeSteps<float>(5000);
}
