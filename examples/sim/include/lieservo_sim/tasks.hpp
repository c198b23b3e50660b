// lieservo_sim/tasks.hpp — the paper's four tasks in simulation (sec:obj_pose_tracking_exp …
// sec:dual_arm_tall_object_pushing), each closing the loop of the paper's Figure 1:
//
//   true contact (ContactModel) → GDN-like (μ, σ) (GdnObservationModel)
//   → fromTangentGaussian (eq:se3_inverse_transform) → DiscriminativeBayesFilter (alg:se3_bayes_filter)
//   → controller (TactileServoController / PushingController / DualArmPushing, paper presets)
//   → sensor body twist → SimulatedArm (X_ws ← X_ws exp(u Δt), sub-stepped) → world update.
//
// Every task takes TaskOptions (rate, seed, output folder, duration scale) and returns a result
// with the metrics, the success flag and a list of reasons when it failed.  With a non-empty
// TaskOptions::out_dir the task writes SVG plots and CSV logs there.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "common.hpp"
#include "contact_model.hpp"
#include "observation_model.hpp"
#include "simulated_arm.hpp"

namespace lieservo::sim {

struct TaskOptions {
  double control_rate = 20.0;   ///< Hz, tactile loop (camera rate); the presets assume 20 Hz
  int substeps = 8;             ///< arm/world sub-steps per control period
  std::uint64_t seed = 1;
  /// Scales the durations of long tasks (tracking sequence, periodic periods, dome paths) and
  /// the number of pushing trials; 1 = the paper's set-up.  Tests use < 1.
  double duration_scale = 1.0;
  std::string out_dir;          ///< empty: no files
  GdnCalibration calibration = GdnCalibration::paperTable1();
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

// ---- (c, d) pushing ------------------------------------------------------------------------
struct SupportSurface {
  std::string name;
  double object_friction;      ///< μ_s object–support: f_max = μ_s m g
  double pressure_factor;      ///< limit-surface ratio c = factor · c_uniform(footprint)
  double pusher_friction;      ///< μ_c sensor skin–object, sliding (motion cone)
  double holding_friction;     ///< μ_h: static hold of the opposite (stabilising) sensor
};
SupportSurface foamSurface();
SupportSurface mdfSurface();

struct PushObject {
  std::string name;
  std::string shape;   ///< "square", "circle", "hexagon"
  double size;         ///< side (square), radius (circle), circumradius (hexagon), mm
  double height;       ///< mm
  double mass;         ///< kg (paper Figures 8–9)
};
std::vector<PushObject> shortObjects();  ///< the four prisms of sec:single_arm_object_pushing_exp
std::vector<PushObject> tallObjects();   ///< their double-height versions

struct PushingSetup {
  PushObject object;
  SupportSurface surface;
  bool dual_arm = false;
  bool tall = false;               ///< tall-object reference offsets (sec:dual_arm_tall_object_pushing)
  double tip_stiffness = 0.8;      ///< N/mm: tip force per mm of depth
  Vec2 start{-250, 100};           ///< sensor (y, z) in the work frame (mm)
  Vec2 target{0, 375};             ///< (y, z)
  double sensor_height = 45;       ///< x of the sensor axis above the support (mm)
  double initial_depth = 1.0;      ///< leader contact depth at the start (mm)
  double follower_depth = 3.0;     ///< follower contact depth at the start (mm)
  double timeout = 120;            ///< s
  void validate() const;           ///< throws SceneError
};
struct PushTrial {
  double target_error = 0;      ///< perpendicular distance target ↔ contact normal (mm)
  double final_distance = 0;    ///< sensor centre ↔ target at the end (mm)
  double duration = 0;          ///< s
  bool terminated = false;      ///< reached the termination radius
  bool contact_kept = true;     ///< the pusher (leader) kept contact throughout
  bool follower_contact_kept = true;     ///< dual arm: the follower kept contact throughout
  double follower_contact_fraction = 1;  ///< dual arm: fraction of control steps in contact
  double max_leader_depth = 0, max_follower_depth = 0, min_follower_depth = 1e9;
  double sliding_fraction = 0;  ///< fraction of pushing sub-steps on a motion-cone edge
  std::vector<Vec3> sensor_path, follower_path;  ///< (x, y, z) per control step
  std::vector<Vec3> object_path;                 ///< (y, z, θ) per control step
  std::vector<double> bearing, alignment_velocity;  ///< θ_s' (deg), alignment u_y (mm/s) per step
  std::vector<double> leader_depth, leader_tilt, follower_depth;  ///< true depth (mm), α (deg)
};
struct PushingCase {
  PushingSetup setup;
  std::vector<PushTrial> trials;
  double mean_error = 0, sd_error = 0;  ///< over the trials that reached the target
  int reached_trials = 0;          ///< trials that met the termination rule within the timeout
  int follower_kept_trials = 0;    ///< dual arm: trials in which the follower never lost contact
  bool success = false;
  std::vector<std::string> failures;
  std::vector<std::string> notes;  ///< reported, not failures (follower contact, see docs)
};
/// One trial (seeded: object placement jitter, friction ±10 %, GDN noise).
PushTrial runPushTrial(const PushingSetup& setup, const TaskOptions& opt, std::uint64_t trial_seed);
/// `trials` seeded trials of one set-up (the paper: 5).
PushingCase runPushingCase(const PushingSetup& setup, const TaskOptions& opt, int trials);

struct PushingResult {
  std::vector<PushingCase> cases;
  bool success = false;
  std::vector<std::string> failures;
  std::vector<std::string> notes;
};
/// (c) the four short prisms on foam and MDF, single arm.
PushingResult runSingleArmPushing(const TaskOptions& opt, int trials = 5);
/// (d) dual arm: the short prisms on foam and MDF, then the tall prisms on MDF.
PushingResult runDualArmPushing(const TaskOptions& opt, int trials = 5);

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
  // pushing
  static constexpr double pushing_error_max = 20.0;     ///< mm, any trial: one tip radius
  /// A pushing case passes if at most trials/5 trials (1 of the paper's 5) miss the target
  /// (the push passes beside it and the 120 s timeout expires); misses are reported.
};

}  // namespace lieservo::sim
