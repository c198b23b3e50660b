// libFuzzer target: the discriminative Bayesian filter (Algorithm 2, alg:se3_bayes_filter) driven by an
// arbitrary sequence of reset/step/predict/correct/configure calls with arbitrary
// inputs, for SE3 (double, float) and SE2. Properties (abort on violation):
//   * no crash, no UB (ASan+UBSan);
//   * Status::ok or outlier_rejected ⇒ belief and filtered state finite and valid;
//   * any other Status ⇒ the state (belief, filtered, sensor pose, initialised) is bitwise
//     unchanged;
//   * a non-finite observation or sensor pose is never accepted.
#include "fuzz_common.hpp"

using namespace lieservo;
using lieservo::fuzz::Bytes;

namespace {

template <class G, class Policy>
struct Snapshot {
  ConcentratedGaussian<G> bel, fil;
  G sens;
  bool init;
  explicit Snapshot(const DiscriminativeBayesFilter<G, Policy>& f)
      : bel(f.belief()), fil(f.filtered()), sens(f.sensorPose()), init(f.initialised()) {}
  bool operator==(const Snapshot& o) const {
    const typename G::Matrix a = sens.matrix(), b = o.sens.matrix();
    return init == o.init && fuzz::bitwiseEqual(bel, o.bel) && fuzz::bitwiseEqual(fil, o.fil) &&
           std::memcmp(a.data(), b.data(), sizeof(typename G::Scalar) * std::size_t(a.size())) == 0;
  }
};

template <class G, class Policy>
void run(Bytes& b) {
  using Filter = DiscriminativeBayesFilter<G, Policy>;
  using S = typename G::Scalar;
  typename Filter::Options opt;
  if (b.u8() & 1) opt.process_noise = fuzz::covariance<G>(b);
  opt.fusion.max_iterations = 1 + int(b.u8() % 8);
  opt.gating = (b.u8() & 1) != 0;
  if (b.u8() & 1) opt.gate_probability = Bytes::to<S>(b.value());
  Filter f(opt);
  for (int op = 0; op < 64 && !b.empty(); ++op) {
    Snapshot<G, Policy> before(f);
    Status s = Status::ok;
    bool inputs_finite = true;
    switch (b.u8() % 8) {
      case 0: {
        const auto o = fuzz::gaussian<G>(b);
        const G p = fuzz::groupElement<G>(b);
        inputs_finite = fuzz::allFinite(o) && p.allFinite();
        f.reset();  // back to uninitialised: this step is the initialisation
        LIESERVO_FUZZ_REQUIRE(!f.initialised());
        before = Snapshot<G, Policy>(f);
        s = f.step(p, o);
        break;
      }
      case 1: {
        const G T = fuzz::groupElement<G>(b);
        inputs_finite = T.allFinite();
        s = (b.u8() & 1) ? f.predict(T) : f.predictFromOdometry(T);  // T̄ or the odometry increment
        break;
      }
      case 2: {
        const auto o = fuzz::gaussian<G>(b);
        inputs_finite = fuzz::allFinite(o);
        s = f.correct(o);
        break;
      }
      case 3: {
        typename Filter::Options o2 = opt;
        o2.process_noise = fuzz::covariance<G>(b);
        o2.gating = (b.u8() & 1) != 0;
        s = f.configure(o2);
        if (s != Status::ok) LIESERVO_FUZZ_REQUIRE((Snapshot<G, Policy>(f) == before));
        continue;  // options are not state
      }
      case 4:
        if ((b.u8() & 15) == 0) {
          f.reset();
          LIESERVO_FUZZ_REQUIRE(!f.initialised());
          continue;
        }
        [[fallthrough]];
      default: {
        // A plausible step most of the time: small sensor motion, observation near the state.
        const G p = (b.u8() & 1) ? fuzz::groupElement<G>(b)
                                 : G::exp(b.vector<typename G::Tangent>() * S(1.0 / 4096)) * f.sensorPose();
        ConcentratedGaussian<G> o = fuzz::gaussian<G>(b);
        if (b.u8() & 1) o.mean = G::exp(b.vector<typename G::Tangent>() * S(1.0 / 1024)) * f.filtered().mean;
        inputs_finite = fuzz::allFinite(o) && p.allFinite();
        s = f.step(p, o);
        break;
      }
    }
    LIESERVO_FUZZ_REQUIRE(f.diagnostics().last_status == s);
    if (s == Status::ok || s == Status::outlier_rejected) {
      LIESERVO_FUZZ_REQUIRE(inputs_finite);
      LIESERVO_FUZZ_REQUIRE(f.initialised());
      LIESERVO_FUZZ_REQUIRE(fuzz::allFinite(f.filtered()) && fuzz::allFinite(f.belief()));
      LIESERVO_FUZZ_REQUIRE(f.filtered().validate() == Status::ok);
      LIESERVO_FUZZ_REQUIRE(std::isfinite(f.diagnostics().nis));
    } else {
      LIESERVO_FUZZ_REQUIRE((Snapshot<G, Policy>(f) == before));
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Bytes b(data, size);
  switch (b.u8() % 4) {
    case 0: run<SE3<double>, PaperJacobian>(b); break;
    case 1: run<SE3<float>, PaperJacobian>(b); break;
    case 2: run<SE3<double>, ClosedFormJacobian>(b); break;
    default: run<SE2<double>, PaperJacobian>(b); break;
  }
  return 0;
}
