// lieservo_sim/tasks.hpp — the paper's four tasks in simulation (Section 5.4, sec:obj_pose_tracking_exp …
// Section 5.7.2 (sec:dual_arm_tall_object_pushing)), each closing the loop of the paper's Figure 1:
//
//   true contact (ContactModel) → GDN-like (μ, σ) (GdnObservationModel)
//   → fromTangentGaussian (eq. 14, eq:se3_inverse_transform) → DiscriminativeBayesFilter (Algorithm 2, alg:se3_bayes_filter)
//   → controller (TactileServoController / PushingController / DualArmPushing, paper presets)
//   → sensor body twist → the arm (X_ws ← X_ws exp(u Δt) per MuJoCo step) → the engine steps.
//
// All four run on MuJoCo (mujoco_world.hpp): each sensor is a MujocoSensorArm (sensor_arm.hpp),
// its contact state comes from the engine's tip geometry. The world steps at 2.5 ms, 20 steps
// per 20 Hz control period.
//
// Every task takes TaskOptions (rate, seed, output folder, duration scale) and returns a result
// with the metrics, the success flag and a list of reasons when it failed.  With a non-empty
// TaskOptions::out_dir the task writes SVG plots and CSV logs there.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "common.hpp"
#include "contact_model.hpp"
#include "observation_model.hpp"
#include "mujoco_world.hpp"
#include "sensor_arm.hpp"

namespace lieservo::sim {

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

// ---- (c, d) pushing, on MuJoCo (mujoco_world.hpp) -------------------------------------------
using mujoco::ObjectSpec;
using mujoco::SupportSpec;

std::vector<ObjectSpec> shortObjects();    ///< the four prisms of Section 5.6 (sec:single_arm_object_pushing_exp)
std::vector<ObjectSpec> tallObjects();     ///< their double-height versions (Figure 9 masses)
std::vector<ObjectSpec> everydayObjects(); ///< tall everyday-like objects from primitives
/// The object's name for tables and plots ("blue_square" → "blue square").
std::string displayName(const ObjectSpec& object);

struct PushingSetup {
  ObjectSpec object;
  SupportSpec surface = SupportSpec::mdf();
  bool dual_arm = false;
  bool tall = false;               ///< tall-object reference offsets (Section 5.7.2, sec:dual_arm_tall_object_pushing)
  double gel_stiffness = 1.0;      ///< N/mm (mujoco::SensorSpec::gel_stiffness)
  Vec2 start{-250, 100};           ///< leader sensor (x, y) on the support (mm)
  Vec2 target{0, 375};             ///< (x, y)
  double sensor_height = 45;       ///< height of the sensor axis above the support (mm)
  double initial_depth = 1.0;      ///< leader contact depth at the start (mm)
  double follower_depth = 3.0;     ///< follower contact depth at the start (mm)
  double timeout = 120;            ///< s; a trial also stops after 1 s with the leader out of contact
  /// 0: the paper's follower (Table 9: no gain on the tangential y). > 0: the named variant
  /// "follower + y": Kp on y (1/s), with z's Ki/Kp and Kd/Kp ratios (docs/simulation.md).
  double follower_y_gain = 0;
  void validate() const;           ///< throws SceneError
};
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
  std::vector<Vec3> sensor_path, follower_path;  ///< (x, y, z) per control step
  std::vector<Vec3> object_path;                 ///< (x, y, θ) per control step
  std::vector<double> bearing, alignment_velocity;  ///< θ_s' (deg), alignment u_y (mm/s) per step
  std::vector<double> leader_depth, leader_tilt, follower_depth;  ///< true depth (mm), α (deg)
};
struct PushingCase {
  PushingSetup setup;
  std::vector<PushTrial> trials;
  double mean_error = 0, sd_error = 0;  ///< over the trials that reached the target
  int reached_trials = 0;          ///< trials that met the termination rule within the timeout
  int follower_kept_trials = 0;    ///< dual arm: trials in which the follower never lost contact
  int toppled_trials = 0;
  /// false: reported only (single-arm pushes of tall objects: how many topple).
  bool judged = true;
  bool success = false;
  std::vector<std::string> failures;
};
/// One trial (seeded: object placement jitter with sd 2 mm / 2° clipped at 2 sd, support friction ±10 %, GDN noise).
PushTrial runPushTrial(const PushingSetup& setup, const TaskOptions& opt, std::uint64_t trial_seed);
/// `trials` seeded trials of one set-up (the paper: 5), judged against Bounds unless `judged`
/// is false.
PushingCase runPushingCase(const PushingSetup& setup, const TaskOptions& opt, int trials, bool judged = true);

struct PushingResult {
  std::vector<PushingCase> cases;
  double sim_time = 0;  ///< s simulated, all trials
  bool success = false;
  std::vector<std::string> failures;
};
/// (c) the four short prisms on foam and MDF, single arm.
PushingResult runSingleArmPushing(const TaskOptions& opt, int trials = 5);
/// (d) dual arm: the short prisms on foam and MDF, then the tall prisms and the everyday objects
/// on MDF. follower_y_gain > 0 runs the named variant "follower + y" (not the paper's Table 9);
/// round_only keeps the round objects (circle, glass bottle, coffee tin) only.
PushingResult runDualArmPushing(const TaskOptions& opt, int trials = 5, double follower_y_gain = 0,
                                bool round_only = false);
/// The tall prisms and everyday objects pushed by one arm on MDF: reported (how many topple),
/// not judged.
PushingResult runTallSingleArmPushing(const TaskOptions& opt, int trials = 5);
/// The paper-style 2-D plot of pushing cases (one panel each: the object at the start and the
/// end of the first trial, both sensors' paths, the target), as the runners write it.
void writePushingPlot(const std::vector<const PushingCase*>& cases, const std::string& path, const std::string& title);

/// Paper values for the tables (mean, sd in mm); NaN when not reported.
struct PaperValue {
  double mean, sd;
};
PaperValue paperSingleArm(const std::string& object, const std::string& surface);
PaperValue paperDualArm(const std::string& object, const std::string& surface, bool tall);

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
  static constexpr double topple_tilt = 45.0;           ///< deg: past this an object has toppled
};

}  // namespace lieservo::sim
