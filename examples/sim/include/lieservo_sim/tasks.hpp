// lieservo_sim/tasks.hpp — the paper's four tasks in simulation (Section 5.4, sec:obj_pose_tracking_exp …
// Section 5.7.2 (sec:dual_arm_tall_object_pushing)), each closing the loop of the paper's Figure 1:
//
//   true contact (ContactModel) → GDN-like (μ, σ) (GdnObservationModel)
//   → fromTangentGaussian (eq. 14, eq:se3_inverse_transform) → DiscriminativeBayesFilter (Algorithm 2, alg:se3_bayes_filter)
//   → controller (TactileServoController / PushingController / DualArmPushing, paper presets)
//   → sensor body twist → the arm (X_ws ← X_ws exp(u Δt) per MuJoCo step) → the engine steps.
//
// All four run on MuJoCo (mujoco_world.hpp): each sensor is a MujocoSensorArm (sensor_arm.hpp),
// its contact state comes from the engine's tip geometry. The world steps at 2.5 ms
// (kTimestep), 20 steps per 20 Hz control period.
//
// Every task takes TaskOptions (rate, seed, output folder, duration scale) and returns a result
// with the metrics, the success flag and a list of reasons when it failed.  With a non-empty
// TaskOptions::out_dir the task writes SVG plots and CSV logs there.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "common.hpp"
#include "contact_model.hpp"
#include "observation_model.hpp"
#include "mujoco_world.hpp"
#include "sensor_arm.hpp"

namespace lieservo::sim {

/// The tasks' MuJoCo step (s), nominal; the arms move once per step. A control period dt is a
/// whole number of steps (stepsPerPeriod), so the step the tasks run is taskTimestep(dt): 2.5 ms
/// at 20 Hz. The engine's gel tests (tests/sim) run at that step.
inline constexpr double kTimestep = 0.0025;

/// The tasks keep their world's state (StateLog) every kStatePeriod s of simulated time and at
/// the end, for the time-lapses and videos (render.hpp): 0.25 s, 5 control periods at 20 Hz.
inline constexpr double kStatePeriod = 0.25;

/// MuJoCo steps per control period dt: the whole number nearest dt / kTimestep (at least 1).
inline int stepsPerPeriod(double dt) { return std::max(1, int(std::lround(dt / kTimestep))); }

/// The step the tasks run at control period dt: dt / stepsPerPeriod(dt).
inline double taskTimestep(double dt) { return dt / stepsPerPeriod(dt); }

/// A TacTip sensor of a task's scene, named `name`, at X_ws, with the gel of `contact` (one
/// contact truth: the engine's gel and the ContactModel's slip law share k_gel, ρ_t and μ_c).
mujoco::SensorSpec taskSensor(const std::string& name, const ContactParams& contact, const SE3d& X_ws);

/// The ranges (uniform draws, per pushing trial) of the physical parameters that are assumed
/// rather than measured (docs/simulation.md, "What is assumed").
struct PhysicalRanges {
  double support_friction_scale[2] = {0.7, 1.3};  ///< × the support's μ_s (foam 0.42–0.78, MDF 0.25–0.46)
  double skin_friction[2] = {0.5, 1.0};           ///< μ_c: rubber-like skin on smooth plastic
  double gel_stiffness[2] = {0.6, 1.5};           ///< k_gel (N/mm): Hertz secants of E* = 0.1 MPa at 1–6 mm
  void validate() const;                          ///< throws SceneError
};

struct TaskOptions {
  double control_rate = 20.0;   ///< Hz, tactile loop (camera rate); the presets assume 20 Hz
  std::uint64_t seed = 1;
  /// Scales the durations of long tasks (tracking sequence, periodic periods, dome paths) and
  /// the number of pushing trials; 1 = the paper's set-up.  Tests use < 1.
  double duration_scale = 1.0;
  std::string out_dir;          ///< empty: no files
  GdnCalibration calibration = GdnCalibration::paperTable1();
  /// The observations: null = the calibrated Gaussian model (`calibration`), one per arm,
  /// seeded; else this source for every arm (the `real` mode: RealGdnObservations). The tasks
  /// run one at a time on it (not thread-safe).
  std::shared_ptr<ObservationSource> observations;
  ArmLimits arm{};
  ContactParams contact{};
  /// Pushing trials draw the assumed physical parameters (μ_s, μ_c, k_gel) from `ranges`
  /// instead of using the defaults (μ_s still ±10 % around the support's).
  bool randomise = false;
  PhysicalRanges ranges{};
  /// Pushing: the object's start placement, the same for every trial instead of drawn (NaN:
  /// drawn, runPushTrial): its sideways offset along y (mm, |·| ≤ 50) and its yaw (rad,
  /// |·| ≤ π/4; round objects are never turned). lieservo_push_start_map sets them.
  double start_offset = std::numeric_limits<double>::quiet_NaN();
  double start_yaw = std::numeric_limits<double>::quiet_NaN();
  /// Pushing: the factor on the support's μ_s, the same for every trial instead of drawn
  /// (NaN: drawn, ±10 % or `ranges` with `randomise`); in (0, 3].
  double support_friction_scale = std::numeric_limits<double>::quiet_NaN();
  void validate() const;        ///< throws SceneError
};

/// Summary statistics of a signal (absolute values unless stated).
struct Stat {
  double mean = 0, max = 0, rms = 0;
  std::size_t n = 0;
  void add(double v);
  void finish();
};

// ---- (a) object tracking ------------------------------------------------------------------
struct TrackingSegment {
  std::string name;
  Stat depth_error;   ///< |true depth − 6 mm|
  Stat tilt;          ///< angle between sensor axis and surface normal (deg)
  Stat twist;         ///< |γ| relative to the stuck contact (deg)
  Stat lag;           ///< distance of the contact point from the leader's plate centre (mm)
  bool contact_kept = true;
};
struct TrackingResult {
  std::vector<TrackingSegment> segments;  ///< 12 single-axis legs (out/back) + "periodic"
  TrackingSegment single_axis, periodic;  ///< pooled
  mujoco::StateLog states;  ///< the world every kStatePeriod s (for render.hpp)
  bool success = false;
  std::vector<std::string> failures;
  double sim_time = 0;
};
TrackingResult runObjectTracking(const TaskOptions& opt);

// ---- (b) surface following ----------------------------------------------------------------
struct FollowingPath {
  std::string name;
  Stat depth_error;  ///< |true depth − 3 mm|
  Stat tilt;         ///< angle from the surface normal (deg)
  double distance = 0;  ///< distance travelled along the surface (mm)
  bool reached_end = false;
  bool contact_kept = true;
  mujoco::StateLog states;  ///< the world every kStatePeriod s (for render.hpp)
};
struct FollowingResult {
  FollowingPath ramp;
  std::vector<FollowingPath> dome;  ///< 8 radial paths, θ_i = 0, 45°, …, 315°
  FollowingPath dome_pooled;
  bool success = false;
  std::vector<std::string> failures;
  double sim_time = 0;
};
FollowingResult runSurfaceFollowing(const TaskOptions& opt);
/// The curved ramp of the following task (H = 40 mm, L = 200 mm, 80 mm wide); the path starts
/// 30 mm before it (y = −30) and ends when the contact passes y = L + 30.
mujoco::FixtureSpec followingRamp();

// ---- (c, d) pushing, on MuJoCo (mujoco_world.hpp) -------------------------------------------
using mujoco::ObjectSpec;
using mujoco::SupportSpec;

std::vector<ObjectSpec> shortObjects();    ///< the four prisms of Section 5.6 (sec:single_arm_object_pushing_exp)
std::vector<ObjectSpec> tallObjects();     ///< their double-height versions (Figure 9 masses)
std::vector<ObjectSpec> everydayObjects(); ///< the five tall everyday objects of Figure 9, from primitives
std::vector<ObjectSpec> tallAndEverydayObjects();  ///< tallObjects() then everydayObjects()
/// The object's name for tables and plots ("blue_square" → "blue square").
std::string displayName(const ObjectSpec& object);

struct PushingSetup {
  ObjectSpec object;
  SupportSpec surface = SupportSpec::mdf();
  bool dual_arm = false;
  bool tall = false;               ///< tall-object reference offsets (Section 5.7.2, sec:dual_arm_tall_object_pushing)
  /// Dual arm: false = the paper's decentralised follower (DualArmPushing, Table 9); true =
  /// the centralised follower (CentralisedDualArmPushing), not the paper's controller.
  bool centralised = false;
  Vec2 start{-250, 100};           ///< leader sensor (x, y) on the support (mm)
  Vec2 target{0, 375};             ///< (x, y)
  double sensor_height = 45;       ///< height of the sensor axis above the support (mm)
  double initial_depth = 1.0;      ///< leader contact depth at the start (mm)
  double follower_depth = 3.0;     ///< follower contact depth at the start (mm)
  double timeout = 120;            ///< s; a trial also stops after 1 s with the leader out of contact
  void validate() const;           ///< throws SceneError
};
/// Where a pushed object starts in front of the leader: sideways offset (mm), yaw (rad).
struct PushPlacement {
  double offset = 0;
  double yaw = 0;
};

/// The scene of a push, the one place it is built (the tasks, lesson 07, the libfranka-double
/// tests): `setup`'s support with its μ_s × `friction_scale`, its object (skin friction μ_c)
/// at `placement` in front of the leader's sensor, setup.initial_depth into contact; the leader
/// on the paper's right-angle mount (z_s along the push +x, x_s down) at setup.start and
/// setup.sensor_height and, for two arms, the follower opposite, normal to the far face at
/// setup.follower_depth; engine step h (s).
mujoco::SceneSpec pushingScene(const PushingSetup& setup, const ContactParams& contact, double h,
                               const PushPlacement& placement = {}, double friction_scale = 1.0);

struct PushTrial {
  double target_error = 0;      ///< perpendicular distance target ↔ contact normal (mm)
  double final_distance = 0;    ///< sensor centre ↔ target at the end (mm)
  double duration = 0;          ///< s (simulated)
  bool terminated = false;      ///< reached the termination radius
  /// Passed the target without reaching it: inside the alignment cut-off (ρ* = 120 mm, where
  /// only the servo acts and nothing steers any more) the sensor's distance to the target
  /// grew 20 mm beyond its closest approach; the trial stops there.
  bool passed_target = false;
  double closest_approach = 1e9;  ///< smallest sensor centre ↔ target distance (mm)
  bool contact_kept = true;     ///< the pusher (leader) was in contact at every control step
  bool follower_contact_kept = true;     ///< dual arm: the follower was in contact at every step
  double follower_contact_fraction = 1;  ///< dual arm: fraction of control steps in contact
  double max_leader_depth = 0, max_follower_depth = 0, min_follower_depth = 1e9;
  double max_tilt = 0;          ///< largest tilt of the object's axis from vertical (deg)
  bool toppled = false;         ///< the tilt passed Bounds::topple_tilt (the trial stops)
  /// Dual arm: the angle between the two contact normals (deg, 180 = opposite) per control
  /// step with both arms in contact (NaN otherwise), and its smallest value.
  std::vector<double> opposition;
  double min_opposition = 180;
  /// Mean vertical force (N, +z up) each tip exerted on the object over the steps in contact.
  double leader_vertical_force = 0, follower_vertical_force = 0;
  /// The physical parameters this trial ran with (drawn with TaskOptions::randomise).
  double support_friction = 0, skin_friction = 0, gel_stiffness = 0;
  /// The object's start placement: sideways offset (mm) and yaw (rad), drawn or fixed.
  double start_offset = 0, start_yaw = 0;
  std::vector<Vec3> sensor_path, follower_path;  ///< (x, y, z) per control step
  std::vector<Vec3> object_path;                 ///< (x, y, θ) per control step
  std::vector<double> bearing, alignment_velocity;  ///< θ_s' (deg), alignment u_y (mm/s) per step
  std::vector<double> leader_depth, leader_tilt, follower_depth;  ///< true depth (mm), α (deg)
  std::vector<double> object_tilt;                  ///< the object's tilt from vertical (deg) per step
  mujoco::StateLog states;  ///< the world every kStatePeriod s (for render.hpp)
};
struct PushingCase {
  PushingSetup setup;
  std::vector<PushTrial> trials;
  double mean_error = 0, sd_error = 0;  ///< over the trials that reached the target
  int reached_trials = 0;          ///< trials that met the termination rule within the timeout
  int follower_kept_trials = 0;    ///< dual arm: trials in which the follower never lost contact
  int toppled_trials = 0;
  double min_opposition = 180;     ///< dual arm: smallest opposition angle over the trials (deg)
  /// false: reported only (single-arm pushes of tall objects: how many topple; the paper's
  /// follower on round objects); its failures do not decide the result.
  bool judged = true;
  bool success = false;
  std::vector<std::string> failures;
  /// The case's figures: the group's plot is `<figure_stem>.svg`, its time-lapse
  /// `<figure_stem>/<object name>.png` (render.hpp); empty when the runner wrote no files.
  std::string figure_stem;
};
/// One trial (seeded: object placement jitter with sd 2 mm / 2° clipped at 2 sd, support
/// friction ±10 %, GDN noise; TaskOptions can fix the placement and the friction).
PushTrial runPushTrial(const PushingSetup& setup, const TaskOptions& opt, std::uint64_t trial_seed);
/// `trials` seeded trials of one set-up (the paper: 5), judged against Bounds unless `judged`
/// is false.
PushingCase runPushingCase(const PushingSetup& setup, const TaskOptions& opt, int trials, bool judged = true);

struct PushingResult {
  std::vector<PushingCase> cases;
  double sim_time = 0;  ///< s simulated, all trials
  bool success = false;             ///< every judged case met its criteria
  std::vector<std::string> failures;  ///< of the judged cases
  std::vector<std::string> reported;  ///< misses of the unjudged cases
};
/// (c) the four short prisms on foam and MDF, single arm.
PushingResult runSingleArmPushing(const TaskOptions& opt, int trials = 5);
/// (d) dual arm: the short prisms on foam and MDF, then the tall prisms and the everyday objects
/// on MDF, with the paper's decentralised follower or (`centralised`) the centralised one.
/// With the paper's follower the round objects are run and reported but not judged
/// (docs/simulation.md, "Task set-ups", (d)).
PushingResult runDualArmPushing(const TaskOptions& opt, int trials = 5, bool centralised = false);
/// The tall prisms and everyday objects pushed by one arm on the compliant foam: reported (how
/// many topple), not judged.
PushingResult runTallSingleArmPushing(const TaskOptions& opt, int trials = 5);
/// A pushing case as the runners above run it: `name` is its log's stem, `<group>_<object>`
/// ("pushing_single_foam_blue_square"), and `judged` whether its misses decide the result.
struct NamedPushingCase {
  std::string name;
  PushingSetup setup;
  bool judged = true;
};
/// Every case of runSingleArmPushing, runDualArmPushing (the paper's follower, then the
/// centralised one) and runTallSingleArmPushing, in that order (the studies, examples/studies).
std::vector<NamedPushingCase> pushingCases();

/// One trial against the pushing criteria (docs/simulation.md, "Success criteria"), a field
/// per criterion; the dual-arm ones hold for one arm. runPushingCase's verdicts come from it.
struct PushVerdict {
  bool reached = true;                ///< terminated within the timeout, neither toppled nor past the target
  bool within_error = true;           ///< reached, with target_error ≤ Bounds::pushing_error_max
  bool contact_kept = true;           ///< the pusher in contact at every control step
  bool follower_contact_kept = true;  ///< dual arm: the follower too
  bool upright = true;                ///< dual arm: max_tilt ≤ Bounds::upright_tilt_max
  bool opposed = true;                ///< dual arm: min_opposition ≥ Bounds::opposition_min
  bool passed() const { return reached && within_error && contact_kept && follower_contact_kept && upright && opposed; }
};
PushVerdict judgeTrial(const PushingSetup& setup, const PushTrial& trial);

/// Whether an object is round (circle: the glass bottle, the coffee tin, the circles).
bool isRound(const ObjectSpec& object);

// ---- toppling by statics and by the engine ---------------------------------------------------
/// A tall object pushed horizontally at height h on a rigid support with friction μ_s slides
/// (at F = μ_s m g) before it tips (at F = m g w / (2 h), w the base width along the push)
/// when μ_s h < w / 2. Critical values by statics and found in the engine (bisection on a
/// slowly ramped push at the middle of the face, along +x_o) on SupportSpec::rigid.
struct ToppleRow {
  ObjectSpec object;
  double push_height = 45;                 ///< mm, for the critical μ_s
  double support_friction = 0.35;          ///< μ_s, for the critical height
  /// h* (mm) at support_friction; +inf for both when the object, pushed at its top, slides
  /// (statics: w / (2 μ_s) is above it; engine: no tip there).
  double statics_height = 0, engine_height = 0;
  double statics_friction = 0, engine_friction = 0;  ///< μ_s* at push_height
};
/// Bisects in the engine to `tolerance` (relative).
ToppleRow toppleAnalysis(const ObjectSpec& object, double support_friction = 0.35, double push_height = 45,
                         double tolerance = 0.01);
/// toppleAnalysis of each object (at the defaults), on all cores.
std::vector<ToppleRow> toppleTable(const std::vector<ObjectSpec>& objects);
/// One engine trial: does a force ramped slowly to 2 μ_s m g at height h (mm) on the −x face
/// tip the object (tilt > 3°) before its base slides 1 mm? The first motion decides, as in
/// statics.
bool tipsBeforeSliding(const ObjectSpec& object, double support_friction, double push_height);
/// The paper-style 2-D plot of pushing cases (one panel each: the object at the start and the
/// end of the first trial, both sensors' paths, the target), as the runners write it.
void writePushingPlot(const std::vector<const PushingCase*>& cases, const std::string& path, const std::string& title);

/// The opposition angle over time (trial 1) of each round-object case, the paper's follower
/// (`paper`) beside the centralised one (`centralised`): one panel per case.
void writeOppositionPlot(const PushingResult& paper, const PushingResult& centralised, const std::string& path);

/// Paper values for the tables (mean, sd in mm); NaN when not reported.
struct PaperValue {
  double mean, sd;
};
PaperValue paperSingleArm(const std::string& object, const std::string& surface);
PaperValue paperDualArm(const std::string& object, const std::string& surface, bool tall);
/// The paper's final target error for a case: its single- or dual-arm table's entry.
PaperValue paperValue(const PushingCase& c);

/// Success bounds (docs/simulation.md justifies them).
struct Bounds {
  // tracking
  static constexpr double tracking_depth_mean = 1.0;    ///< mm
  static constexpr double tracking_depth_max = 5.0;     ///< mm (contact never lost at 6 mm ref)
  static constexpr double tracking_tilt_mean = 3.0;     ///< deg
  static constexpr double tracking_tilt_max = 20.0;     ///< deg
  // following
  static constexpr double following_depth_mean = 0.5;   ///< mm
  static constexpr double following_depth_max = 2.5;    ///< mm (< 3 mm ref: contact kept)
  static constexpr double following_tilt_mean = 3.0;    ///< deg
  static constexpr double following_tilt_max = 10.0;    ///< deg
  // pushing: every trial reaches the target within the timeout, every sensor keeps contact at
  // every control step, and
  static constexpr double pushing_error_max = 10.0;     ///< mm, any trial (paper worst mean 9.45)
  static constexpr double upright_tilt_max = 10.0;      ///< deg: dual-arm pushes keep objects upright
  static constexpr double opposition_min = 150.0;       ///< deg: dual-arm contact normals stay opposed
  static constexpr double topple_tilt = 45.0;           ///< deg: past this an object has toppled
};

}  // namespace lieservo::sim
