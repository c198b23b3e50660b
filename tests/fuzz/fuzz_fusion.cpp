// libFuzzer target: concentrated-Gaussian operations and data fusion (Algorithm 3, alg:se3_data_fusion)
// on SE3 (double, float), SE2 and SO3 with arbitrary inputs. Properties (abort on violation):
//   * every function returns (no crash, no UB — the build uses ASan+UBSan);
//   * Status::ok ⇒ every output is finite (and a fused/transformed Gaussian validates);
//   * Status ≠ ok ⇒ the output object is bitwise untouched;
//   * non-finite input never yields Status::ok.
#include "fuzz_common.hpp"

using namespace lieservo;
using lieservo::fuzz::Bytes;

namespace {

template <class Policy, class G>
void fuseWith(Bytes& b, const ConcentratedGaussian<G>* f, int count) {
  using S = typename G::Scalar;
  FusionOptions<S> o;
  o.max_iterations = int(b.u8() % 12);  // 0 is invalid
  const std::uint8_t tm = b.u8();
  o.tolerance = (tm & 1) ? Bytes::to<S>(b.value()) : S(0);
  o.require_convergence = (tm & 2) != 0;
  FusionResult<G> r;
  r.fused.mean = fuzz::groupElement<G>(b);
  r.iterations = 12345;
  const FusionResult<G> before = r;
  const Status s = fuse<Policy>(f, count, o, r);
  bool inputs_finite = true;
  for (int i = 0; i < count; ++i) inputs_finite = inputs_finite && fuzz::allFinite(f[i]);
  if (!inputs_finite) LIESERVO_FUZZ_REQUIRE(s != Status::ok);
  if (s == Status::ok) {
    LIESERVO_FUZZ_REQUIRE(fuzz::allFinite(r.fused));
    LIESERVO_FUZZ_REQUIRE(r.fused.validate() == Status::ok);
    LIESERVO_FUZZ_REQUIRE(std::isfinite(r.step_norm) && std::isfinite(r.max_rotation_separation));
    LIESERVO_FUZZ_REQUIRE(std::isfinite(r.step_sigmas) && r.step_sigmas >= S(0));
    LIESERVO_FUZZ_REQUIRE(r.iterations >= 1 && r.iterations <= o.max_iterations);
    // The converged rule: met exactly when the last update was under the tolerance, and
    // required unless asked otherwise; the fixed count never claims it.
    if (o.tolerance > S(0)) {
      LIESERVO_FUZZ_REQUIRE(r.converged == (r.step_sigmas < o.tolerance));
      if (o.require_convergence) LIESERVO_FUZZ_REQUIRE(r.converged);
    } else {
      LIESERVO_FUZZ_REQUIRE(!r.converged && r.iterations == o.max_iterations);
    }
  } else {
    LIESERVO_FUZZ_REQUIRE(fuzz::bitwiseEqual(r.fused, before.fused) && r.iterations == 12345);
  }
}

template <class G>
void run(Bytes& b) {
  using S = typename G::Scalar;
  using CG = ConcentratedGaussian<G>;
  const int count = 1 + int(b.u8() % 4);
  CG f[4];
  for (int i = 0; i < count; ++i) {
    const std::uint8_t how = b.u8();
    if ((how & 3) == 0 && i > 0) {
      f[i] = f[i - 1];  // repeated observation
    } else {
      f[i] = fuzz::gaussian<G>(b);
    }
  }
  switch (b.u8() % 4) {
    case 0: fuseWith<PaperJacobian>(b, f, count); break;
    case 1: fuseWith<ClosedFormJacobian>(b, f, count); break;
    case 2: fuseWith<SeriesJacobian<1>>(b, f, count); break;
    default: fuseWith<SeriesJacobian<4>>(b, f, count); break;
  }

  // Transform (eq. 41, eqn:se3_rv_probabilistic_transform_2).
  {
    CG out = fuzz::gaussian<G>(b);
    const CG before = out;
    const G T = fuzz::groupElement<G>(b);
    const typename G::Jacobian Sphi = fuzz::covariance<G>(b);
    const Status s = transform(f[0], T, Sphi, out);
    if (s == Status::ok) {
      LIESERVO_FUZZ_REQUIRE(fuzz::allFinite(out) && out.validate() == Status::ok);
    } else {
      LIESERVO_FUZZ_REQUIRE(fuzz::bitwiseEqual(out, before));
    }
  }
  // Tangent conversions (eq. 14, eq:se3_inverse_transform, eq. 38 (eqn:glob_tangent_space_pdf)).
  {
    CG out;
    const CG before = out;
    const typename G::Tangent mu = b.vector<typename G::Tangent>();
    const typename G::Tangent sg = b.sigmas<typename G::Tangent>();
    const Status s = (b.u8() & 1) ? fromTangentGaussian(mu, sg, out)
                                  : fromTangentGaussian<PaperJacobian>(mu, sg, out);
    if (!mu.allFinite() || !sg.allFinite()) LIESERVO_FUZZ_REQUIRE(s != Status::ok);
    if (s == Status::ok) {
      LIESERVO_FUZZ_REQUIRE(fuzz::allFinite(out) && out.validate() == Status::ok);
    } else {
      LIESERVO_FUZZ_REQUIRE(fuzz::bitwiseEqual(out, before));
    }
    typename G::Tangent m2 = G::Tangent::Zero();
    typename G::Jacobian S2 = G::Jacobian::Zero();
    if (toTangentGaussian(f[0], m2, S2) == Status::ok) {
      LIESERVO_FUZZ_REQUIRE(m2.allFinite() && S2.allFinite());
    } else {
      LIESERVO_FUZZ_REQUIRE(m2.isZero(S(0)) && S2.isZero(S(0)));
    }
  }
  // NIS and Mahalanobis distance.
  {
    S nis = S(-1);
    typename G::Tangent nu;
    if (normalizedInnovationSquared(f[0], f[count - 1], nis, &nu) == Status::ok) {
      LIESERVO_FUZZ_REQUIRE(std::isfinite(nis) && nis >= S(0) && nu.allFinite());
    } else {
      LIESERVO_FUZZ_REQUIRE(nis == S(-1));
    }
    S d2 = S(-1);
    if (mahalanobisSquared(f[0], fuzz::groupElement<G>(b), d2) == Status::ok) {
      LIESERVO_FUZZ_REQUIRE(std::isfinite(d2) && d2 >= S(0));
    } else {
      LIESERVO_FUZZ_REQUIRE(d2 == S(-1));
    }
  }
  // Unchecked operations must not crash (their outputs may be non-finite for bad inputs).
  (void)inverse(f[0]);
  (void)compose(f[0], f[count - 1]);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Bytes b(data, size);
  switch (b.u8() % 4) {
    case 0: run<SE3<double>>(b); break;
    case 1: run<SE3<float>>(b); break;
    case 2: run<SE2<double>>(b); break;
    default: run<SO3<double>>(b); break;
  }
  return 0;
}
