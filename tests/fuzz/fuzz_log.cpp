// libFuzzer target: exp/log and the checked constructors of the groups (SO2, SE2, SO3, SE3;
// double and float). Properties (abort on violation):
//   * fromMatrix rejects every non-finite input; when it accepts, the element is finite.
//   * exp of a finite tangent with |ρ| ≤ 1e6, |φ| ≤ 1e6 is finite and passes fromMatrix.
//   * for a valid element with |t| ≤ 1e6: log is finite and exp(log X) ≈ X.
//   * J(ξ) J(ξ)⁻¹ ≈ 1 for |φ| ≤ 3 and |ρ| ≤ 1e3 (J⁻¹ is singular only at |φ| = 2π).
//   * fromMatrixProjected returns ok only with a valid element, at any finite scale (this
//     target found the 2-D projection's norm over/underflow for |(c, s)| ≷ 1e±154).
#include "fuzz_common.hpp"

using namespace lieservo;
using lieservo::fuzz::Bytes;

namespace {

template <class G>
typename G::Scalar maxAbs(const typename G::Matrix& M) {
  return M.cwiseAbs().maxCoeff();
}

template <class G>
void checkGroup(Bytes& b) {
  using S = typename G::Scalar;
  using Tangent = typename G::Tangent;
  constexpr int R = detail::rotationDoF<G>();
  constexpr int T = G::DoF - R;
  const S tol = std::is_same<S, float>::value ? S(2e-3) : S(1e-9);

  // 1. exp of a tangent vector.
  const Tangent xi = b.vector<Tangent>();
  if (xi.allFinite() && xi.cwiseAbs().maxCoeff() <= S(1e6)) {
    const G X = G::exp(xi);
    LIESERVO_FUZZ_REQUIRE(X.allFinite());
    G chk;
    LIESERVO_FUZZ_REQUIRE(G::fromMatrix(X.matrix(), chk) == Status::ok);
    const Tangent l = X.log();
    LIESERVO_FUZZ_REQUIRE(l.allFinite());
    const S scale = S(1) + maxAbs<G>(X.matrix());
    LIESERVO_FUZZ_REQUIRE((G::exp(l).matrix() - X.matrix()).cwiseAbs().maxCoeff() <= tol * scale * scale);
    const S angle = xi.template tail<R>().norm();
    const S trans = T > 0 ? xi.head(T).norm() : S(0);
    if (angle <= S(3) && trans <= S(1e3)) {
      typename G::Jacobian Jinv;
      const Tangent l2 = X.logAndLeftJacobianInverse(Jinv);
      LIESERVO_FUZZ_REQUIRE(l2.allFinite() && Jinv.allFinite());
      const typename G::Jacobian P = G::leftJacobian(xi) * G::leftJacobianInverse(xi);
      LIESERVO_FUZZ_REQUIRE((P - G::Jacobian::Identity()).cwiseAbs().maxCoeff() <= tol * (S(1) + trans) * S(10));
    }
  }

  // 2. checked construction from an arbitrary matrix.
  const typename G::Matrix M = b.vector<typename G::Matrix>();
  G X;
  const Status s = G::fromMatrix(M, X);
  if (!M.allFinite()) LIESERVO_FUZZ_REQUIRE(s == Status::non_finite_input);
  if (s == Status::ok) {
    LIESERVO_FUZZ_REQUIRE(X.allFinite());
    if (maxAbs<G>(X.matrix()) <= S(1e6)) {
      const Tangent l = X.log();
      LIESERVO_FUZZ_REQUIRE(l.allFinite());
      const S scale = S(1) + maxAbs<G>(X.matrix());
      LIESERVO_FUZZ_REQUIRE((G::exp(l).matrix() - X.matrix()).cwiseAbs().maxCoeff() <= tol * scale * scale);
    }
  }
  // 3. projection.
  G P;
  const Status sp = G::fromMatrixProjected(M, P);
  if (!M.allFinite()) LIESERVO_FUZZ_REQUIRE(sp != Status::ok);
  if (sp == Status::ok) {
    G chk;
    LIESERVO_FUZZ_REQUIRE(G::fromMatrix(P.matrix(), chk) == Status::ok);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Bytes b(data, size);
  switch (b.u8() % 6) {
    case 0: checkGroup<SO2<double>>(b); break;
    case 1: checkGroup<SE2<double>>(b); break;
    case 2: checkGroup<SO3<double>>(b); break;
    case 3: checkGroup<SE3<double>>(b); break;
    case 4: checkGroup<SO3<float>>(b); break;
    default: checkGroup<SE3<float>>(b); break;
  }
  return 0;
}
