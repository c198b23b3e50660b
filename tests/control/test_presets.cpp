// Presets (Appendix D (sec:controller_parameters), Tables 6–9): library-unit values, and the proof
// of the conversion: a per-step PID in the paper's units (mm, deg; Σe, Δē, no dt) and the
// converted library PID (mm, rad; per second) command the same velocities at the paper rate.
#include <catch2/catch.hpp>

#include "control_test_util.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <lieservo/control/presets.hpp>
#include <lieservo/units.hpp>

using namespace lieservo;
using V6 = Eigen::Matrix<double, 6, 1>;
using M6 = Eigen::Matrix<double, 6, 6>;
using G = SE3<double>;

namespace {
const double T = 1.0 / 20.0;  // the default assumed paper control period
using lieservo::test::kInf;
const double kDeg = pi<double>() / 180.0;

V6 diag(const M6& m) { return m.diagonal(); }
bool isDiagonal(const M6& m) { return (m - M6(m.diagonal().asDiagonal())).isZero(0); }
using lieservo::test::v6;
G pose(double x, double y, double z, double a_deg, double b_deg, double g_deg) {
  return G::fromEulerXYZ6Degrees(v6(x, y, z, a_deg, b_deg, g_deg));
}

// A per-step PID in the paper's units (what the gains were tuned for, by assumption).
struct PaperStepPid {
  double kp, ki, kd, clip, out_clip;
  double sum = 0, ebar = 0;
  bool started = false;
  double step(double e) {
    sum = std::clamp(sum + e, -clip, clip);
    double d = 0;
    if (started) {
      const double prev = ebar;
      ebar = 0.5 * e + 0.5 * ebar;
      d = ebar - prev;
    } else {
      ebar = e;
      started = true;
    }
    return std::clamp(kp * e + ki * sum + kd * d, -out_clip, out_clip);
  }
};
}  // namespace

TEST_CASE("presets: Table 6 object tracking in library units", "[control][presets]") {
  const auto o = objectTrackingPreset<double>();
  CHECK(isDiagonal(o.pid.kp));
  CHECK(isDiagonal(o.pid.ki));
  CHECK(isDiagonal(o.pid.kd));
  CHECK(diag(o.pid.kp).isApprox(v6(5, 5, 5, 2, 2, 0)));
  CHECK(diag(o.pid.ki).isApprox(v6(10, 10, 10, 4, 4, 4)));                      // Ki_step / T
  CHECK(diag(o.pid.kd).isApprox(v6(0.025, 0.025, 0.025, 0.01, 0.01, 0.01)));   // Kd_step · T
  CHECK(o.pid.integral_max == V6::Constant(kInf));  // "Not used"
  CHECK(o.pid.integral_min == V6::Constant(-kInf));
  CHECK(o.pid.output_max == V6::Constant(kInf));
  CHECK(o.reference.isApprox(pose(0, 0, 6, 0, 0, 0), 1e-15));
  CHECK(o.feedforward.isZero());
  CHECK(o.pid.smoothing_time_constant == Approx(T / std::log(2.0)));  // α(T) = 0.5
  MimoPid<double, 6> pid(o.pid);
  CHECK(pid.alpha(T) == Approx(0.5));
}

TEST_CASE("presets: Table 7 surface following in library units", "[control][presets]") {
  const auto o = surfaceFollowingPreset<double>();
  CHECK(diag(o.pid.kp).isApprox(v6(0, 0, 2, 2, 2, 0)));
  CHECK(diag(o.pid.ki).isApprox(v6(0, 0, 2, 2, 2, 0)));
  CHECK(diag(o.pid.kd).isApprox(v6(0, 0, 0.0025, 0.0025, 0.0025, 0)));
  // [−25, 25] per step: mm·step → 1.25 mm·s; deg·step → 1.25·π/180 rad·s
  CHECK(o.pid.integral_max.head<3>().isApprox(V6::Constant(1.25).head<3>()));
  CHECK(o.pid.integral_max.tail<3>().isApprox(V6::Constant(1.25 * kDeg).tail<3>()));
  CHECK(o.pid.integral_min.isApprox(-o.pid.integral_max));
  CHECK(o.reference.isApprox(pose(0, 0, 3, 0, 0, 0), 1e-15));
  CHECK(o.feedforward.isApprox(v6(0, 10, 0, 0, 0, 0)));  // the curved ramp
  const V6 dome = surfaceFollowingFeedforward<double>(deg2rad(45.0));
  CHECK(dome.isApprox(v6(10 * std::cos(pi<double>() / 4), 10 * std::sin(pi<double>() / 4), 0, 0, 0, 0)));
}

TEST_CASE("presets: Table 8 pushing (PID 1 and PID 2) in library units", "[control][presets]") {
  const auto single = pushingPreset<double>(PushingConfiguration::single_arm);
  const auto dual = pushingPreset<double>(PushingConfiguration::dual_arm_leader);
  const auto tall = pushingPreset<double>(PushingConfiguration::dual_arm_leader_tall_object);
  CHECK(diag(single.servo.pid.kp).isApprox(v6(1, 0, 0, 1, 0, 0)));
  CHECK(diag(single.servo.pid.ki).isApprox(v6(2, 0, 0, 2, 0, 0)));
  CHECK(diag(single.servo.pid.kd).isApprox(v6(0.005, 0, 0, 0.005, 0, 0)));
  CHECK(single.servo.pid.integral_max[0] == Approx(1.25));
  CHECK(single.servo.pid.integral_max[3] == Approx(1.25 * kDeg));
  CHECK(single.servo.reference.isApprox(G::identity(), 1e-15));
  CHECK(single.servo.feedforward.isApprox(v6(0, 0, 10, 0, 0, 0)));
  // PID 2: bearing error in rad → u_y in mm/s: gains × 180/π
  const double per_rad = 180.0 / pi<double>();
  CHECK(single.alignment.kp == Approx(0.9 * per_rad));               // 51.57 mm/s per rad
  CHECK(single.alignment.ki == Approx(0.3 * per_rad / T));           // 343.8
  CHECK(dual.alignment.ki == Approx(0.5 * per_rad / T));             // 573.0
  CHECK(single.alignment.kd == Approx(0.9 * per_rad * T));           // 2.578
  CHECK(single.alignment.integral_max == Approx(10 * kDeg * T));     // deg·step → rad·s
  CHECK(single.alignment.integral_min == Approx(-10 * kDeg * T));
  CHECK(single.alignment.output_max == Approx(15));                  // mm/s unchanged
  CHECK(single.alignment.output_min == Approx(-15));
  CHECK(single.reference_bearing == 0);
  CHECK(single.alignment_cutoff == 120);
  CHECK(single.termination_radius == 20);
  CHECK(tall.servo.reference.isApprox(pose(0.5, 0, 0, 0, 0, 0), 1e-15));
  CHECK(tall.alignment.ki == dual.alignment.ki);
}

TEST_CASE("presets: Table 9 stabiliser in library units, tall-object offset", "[control][presets]") {
  const auto o = stabiliserPreset<double>();
  CHECK(diag(o.pid.kp).isApprox(v6(5, 0, 5, 1, 0, 0)));
  CHECK(diag(o.pid.ki).isApprox(v6(10, 0, 10, 2, 0, 0)));
  CHECK(diag(o.pid.kd).isApprox(v6(0.025, 0, 0.025, 0.005, 0, 0)));
  CHECK(o.pid.integral_max[0] == Approx(10.0));          // 200 mm·step
  CHECK(o.pid.integral_max[5] == Approx(10.0 * kDeg));   // 200 deg·step
  CHECK(o.reference.isApprox(pose(0, 0, 3, 0, 0, 0), 1e-15));
  const auto tall = stabiliserPreset<double>(true);
  CHECK(tall.reference.isApprox(pose(-0.5, 0, 3, 0, 0, 0), 1e-15));
}

TEST_CASE("presets: other conventions (period, per-second gains)", "[control][presets]") {
  PaperGainConvention c;
  c.control_period = 1.0 / 30.0;
  const auto o30 = objectTrackingPreset<double>(c);
  CHECK(o30.pid.ki(0, 0) == Approx(0.5 * 30));
  CHECK(o30.pid.kd(0, 0) == Approx(0.5 / 30));
  c.per_step = false;
  c.smoothing_as_time_constant = false;
  const auto raw = surfaceFollowingPreset<double>(c);
  CHECK(raw.pid.ki(2, 2) == Approx(0.1));
  CHECK(raw.pid.kd(2, 2) == Approx(0.05));
  CHECK(raw.pid.integral_max[2] == Approx(25));
  CHECK(raw.pid.integral_max[4] == Approx(25 * kDeg));
  CHECK(raw.pid.smoothing == 0.5);
  CHECK(raw.pid.smoothing_time_constant == 0);
  const auto a = paperAlignmentPid<double>(false, c);
  CHECK(a.ki == Approx(0.3 * 180 / pi<double>()));
  CHECK(a.integral_max == Approx(10 * kDeg));
}

TEST_CASE("presets: converted bearing PID equals the paper's per-step PID in degrees",
          "[control][presets]") {
  for (bool dual : {false, true}) {
    const auto& t = paper::kPushingAlignment;
    PaperStepPid ref{t.kp, dual ? t.ki_dual_arm : t.ki_single_arm, t.kd, t.integral_clip, t.output_clip};
    SisoPid<double> lib(paperAlignmentPid<double>(dual));
    for (int k = 0; k < 300; ++k) {
      const double e_deg = 12 * std::sin(0.04 * k) + 4 * std::cos(0.31 * k);  // bearing error
      double u = 0;
      REQUIRE(lib.step(deg2rad(e_deg), 0, T, u) == Status::ok);
      CHECK(u == Approx(ref.step(e_deg)).epsilon(1e-9).margin(1e-9));  // both mm/s
    }
  }
}

TEST_CASE("presets: converted MIMO PID equals the paper's per-step PID in mm and degrees",
          "[control][presets]") {
  for (const paper::MimoTable* t : {&paper::kObjectTracking, &paper::kSurfaceFollowing,
                                    &paper::kPushingServo, &paper::kStabiliser}) {
    PaperStepPid ref[6];
    for (int i = 0; i < 6; ++i) ref[i] = PaperStepPid{t->kp[i], t->ki[i], t->kd[i], t->integral_clip, kInf};
    MimoPid<double, 6> lib(paperMimoPid<double>(*t));
    for (int k = 0; k < 300; ++k) {
      V6 e_paper;  // mm and degrees
      for (int i = 0; i < 6; ++i) e_paper[i] = 3 * std::sin(0.05 * k + i) + 1.5;
      V6 e_lib = e_paper;
      e_lib.tail<3>() *= kDeg;
      V6 u = V6::Zero();
      REQUIRE(lib.step(e_lib, V6::Zero(), T, u) == Status::ok);
      for (int i = 0; i < 6; ++i) {
        const double expect = ref[i].step(e_paper[i]);       // mm/s or deg/s
        const double got = i < 3 ? u[i] : rad2deg(u[i]);       // library: mm/s or rad/s
        CHECK(got == Approx(expect).epsilon(1e-9).margin(1e-9));
      }
    }
  }
}
