// libFuzzer target: the controllers (MimoPid, TactileServoController, PushingController)
// driven by arbitrary configure/step/setReference/setTarget/reset sequences with arbitrary
// inputs, SE3 double. Properties (abort on violation):
//   * no crash, no UB (ASan+UBSan);
//   * Status::ok ⇒ the output twist is finite;
//   * a non-finite or non-orthonormal pose is never accepted;
//   * any other Status ⇒ the output and the controller's exposed state are unchanged.
#include <lieservo/control.hpp>

#include "fuzz_common.hpp"

using namespace lieservo;
using lieservo::fuzz::Bytes;

namespace {

using G = SE3<double>;
using V = G::Tangent;

bool bitwiseEqual(const V& a, const V& b) { return std::memcmp(a.data(), b.data(), sizeof(double) * 6) == 0; }

bool validPose(const G& X) { return validateElement(X) == Status::ok; }

// Arbitrary PID options: mostly the paper's shape (diagonal, clipped), sometimes anything.
MimoPid<double, 6>::Options pidOptions(Bytes& b) {
  auto o = MimoPid<double, 6>::Options::diagonal(b.vector<V>(), b.vector<V>(), b.vector<V>());
  if (b.u8() & 1) o.clipOutput(b.value(), b.value());
  if (b.u8() & 1) o.clipIntegral(b.value(), b.value());
  if (b.u8() & 1) o.smoothing = b.value();
  if (b.u8() & 1) o.smoothing_time_constant = b.value();
  return o;
}

void servo(Bytes& b) {
  TactileServoController<G>::Options o;
  if (b.u8() & 1) o = surfaceFollowingPreset<double>();
  if (b.u8() & 1) o.pid = pidOptions(b);
  if (b.u8() & 1) o.reference = fuzz::groupElement<G>(b);
  if (b.u8() & 1) o.feedforward = b.vector<V>();
  TactileServoController<G> c(o);
  for (int op = 0; op < 64 && !b.empty(); ++op) {
    const V error_before = c.tangentError();
    const G reference_before = c.options().reference;
    switch (b.u8() % 4) {
      case 0: {
        const G r = fuzz::groupElement<G>(b);
        const Status s = c.setReference(r);
        LIESERVO_FUZZ_REQUIRE((s == Status::ok) == validPose(r));
        if (s != Status::ok) LIESERVO_FUZZ_REQUIRE(c.options().reference.matrix() == reference_before.matrix());
        break;
      }
      case 1: {
        TactileServoController<G>::Options o2 = c.options();
        o2.pid = pidOptions(b);
        if (c.configure(o2) != Status::ok)
          LIESERVO_FUZZ_REQUIRE(c.options().reference.matrix() == reference_before.matrix());
        break;
      }
      case 2:
        c.reset();
        LIESERVO_FUZZ_REQUIRE(c.tangentError().isZero(0.0));
        break;
      default: {
        const G X_sf = (b.u8() & 1) ? fuzz::groupElement<G>(b) : G::exp(b.vector<V>() * (1.0 / 1024));
        const double dt = (b.u8() & 1) ? b.value() : 0.05;
        V u = V::Constant(7.0);
        const V u_before = u;
        const Status s = c.step(X_sf, dt, u);
        if (s == Status::ok) {
          LIESERVO_FUZZ_REQUIRE(validPose(X_sf) && dt > 0 && std::isfinite(dt));
          LIESERVO_FUZZ_REQUIRE(detail::allFinite(u));
        } else {
          LIESERVO_FUZZ_REQUIRE(bitwiseEqual(u, u_before));
          LIESERVO_FUZZ_REQUIRE(bitwiseEqual(c.tangentError(), error_before));
        }
        break;
      }
    }
  }
}

void pushing(Bytes& b) {
  PushingController<SE3d>::Options o = pushingPreset<double>(PushingConfiguration::single_arm);
  if (b.u8() & 1) o.alignment_cutoff = b.value();
  if (b.u8() & 1) o.termination_radius = b.value();
  if (b.u8() & 1) o.target = fuzz::groupElement<G>(b);
  PushingController<SE3d> c(o);
  for (int op = 0; op < 64 && !b.empty(); ++op) {
    const G target_before = c.options().target;
    const bool terminated_before = c.terminated();
    switch (b.u8() % 4) {
      case 0: {
        const G t = fuzz::groupElement<G>(b);
        const Status s = c.setTarget(t);
        LIESERVO_FUZZ_REQUIRE((s == Status::ok) == validPose(t));
        if (s != Status::ok) {
          LIESERVO_FUZZ_REQUIRE(c.options().target.matrix() == target_before.matrix());
          LIESERVO_FUZZ_REQUIRE(c.terminated() == terminated_before);
        }
        break;
      }
      case 1: {
        const G r = fuzz::groupElement<G>(b);
        LIESERVO_FUZZ_REQUIRE((c.setReference(r) == Status::ok) == validPose(r));
        break;
      }
      case 2:
        c.reset();
        LIESERVO_FUZZ_REQUIRE(!c.terminated());
        break;
      default: {
        const G X_ws = (b.u8() & 1) ? fuzz::groupElement<G>(b) : G::exp(b.vector<V>());
        const G X_sf = (b.u8() & 1) ? fuzz::groupElement<G>(b) : G::exp(b.vector<V>() * (1.0 / 1024));
        const double dt = (b.u8() & 1) ? b.value() : 0.05;
        V u = V::Constant(7.0);
        const V u_before = u;
        const Status s = c.step(X_ws, X_sf, dt, u);
        if (s == Status::ok) {
          LIESERVO_FUZZ_REQUIRE(validPose(X_ws) && validPose(X_sf));
          LIESERVO_FUZZ_REQUIRE(detail::allFinite(u));
        } else {
          LIESERVO_FUZZ_REQUIRE(bitwiseEqual(u, u_before));
          LIESERVO_FUZZ_REQUIRE(c.terminated() == terminated_before);
        }
        break;
      }
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Bytes b(data, size);
  if (b.u8() & 1)
    servo(b);
  else
    pushing(b);
  return 0;
}
