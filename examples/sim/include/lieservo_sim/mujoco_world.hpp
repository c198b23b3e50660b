// lieservo_sim/mujoco_world.hpp — the physical world of the simulated tasks, on MuJoCo.
//
// A scene (support, free objects, fixtures, TacTip sensors) is written as MJCF and loaded
// into MuJoCo, which integrates the rigid-body dynamics and resolves the contacts: objects
// slide, turn and topple on the support under gravity and the sensors' pushes; fixtures (a
// dome, a curved ramp, a plate carried by a leader arm) do not move under contact. What MuJoCo
// does not give, the tactile features (contact frame, depth, shear with stick/slip), is
// derived from its contact geometry: World::tipGeometry gives the nearest surface point, its
// normal and the depth from MuJoCo's own collision functions.
//
// Units at this interface are the paper's: mm, kg, s, radians; MuJoCo works in metres inside.
//
// Sensors. The arm holding each sensor is position-stiff: the sensor's pose is what the
// commanded twist makes it (sensor_arm.hpp), and MuJoCo is told its velocity too, so the
// friction on a sliding tip acts. Its tip is a sphere of radius
// 20 mm (the 40 mm TacTip's hemisphere; the back half never touches in these tasks). The
// compliant gel is a spring between the arm's nominal tip and the touching tip: the tip is a
// light body on three slide joints with stiffness k_gel along z_s and ρ_t k_gel across
// (SensorSpec), so a contact depth d (the surface inside the nominal tip sphere) presses with
// ≈ k_gel d, whatever the object's mass, and a sticking contact shears the gel sideways. Tip
// contacts are stiff, with elliptic friction cones and condim 4 (torsional friction, the
// twist γ); MuJoCo's noslip pass, not a hard friction impedance (impratio stays at MuJoCo's
// default 1), holds a stuck gel.
//
// Objects touch the support at their base points only (basePoints: two rings of equally
// loaded points whose mean radius is the uniform-pressure one), each a spring of a Winkler
// foundation (SupportSpec::foundation_modulus) with sliding friction μ_s.
#pragma once

#include <array>
#include <string>
#include <vector>

#include <lieservo/status.hpp>

#include "common.hpp"

struct mjModel_;
struct mjData_;

namespace lieservo::sim::mujoco {

/// The surface the objects stand on, with its friction against them (sliding μ_s) and its
/// compliance.
struct SupportSpec {
  std::string name = "MDF";
  double friction = 0.35;  ///< μ_s, object–support sliding friction
  /// k_w (N/mm³): pressure per mm of sink (a Winkler foundation: E / t for a sheet of
  /// compressive modulus E and thickness t), so an object of mass m on base area A beds in by
  /// m g / (k_w A) and its base's load shifts linearly under a tipping moment.
  double foundation_modulus = 0.05;
  /// The paper's two supports: foam (μ_s 0.6; a 10 mm sheet of E ≈ 100 kPa, k_w = 0.01
  /// N/mm³: the objects bed in by 0.02–0.15 mm) and a hard MDF board (μ_s 0.35; k_w = 0.05
  /// N/mm³: 2–30 µm, the compliance of the objects' printed bases on it). All are assumed
  /// plausible values (docs/simulation.md, "What is assumed").
  /// Colour (RGBA, 0–1) for rendering only.
  std::array<double, 4> rgba{{0.6, 0.6, 0.6, 1}};
  static SupportSpec foam() { return {"foam", 0.6, 0.01, {{0.16, 0.16, 0.17, 1}}}; }
  static SupportSpec mdf() { return {"MDF", 0.35, 0.05, {{0.72, 0.58, 0.42, 1}}}; }
  /// The rigid support of the statics checks (toppleAnalysis): k_w = 1 N/mm³ (sinks < 2 µm).
  static SupportSpec rigid(double friction) { return {"rigid", friction, 1.0, {{0.6, 0.6, 0.6, 1}}}; }
};

/// A rigid object standing on the support: a vertical prism.
struct ObjectSpec {
  std::string name = "object";
  /// "square" (side), "rectangle" (side along x_o, size2 along y_o), "circle" (radius),
  /// "hexagon" (circumradius)
  std::string shape = "square";
  double size = 100;             ///< mm: side, radius or circumradius
  double size2 = 0;              ///< mm: the rectangle's side along y_o (other shapes: unused)
  double height = 60;            ///< mm
  double mass = 0.5;             ///< kg
  double x = 0, y = 0;           ///< mm, centre of the base on the support
  double yaw = 0;                ///< rad about the support normal
  double friction = 0.8;         ///< μ_c, skin–object sliding friction at the sensor (ContactParams)
  /// mm: the height at which the sensors touch it (0: unknown). A circle or hexagon taller
  /// than twice this is split for collision into a segment centred there and one above:
  /// MuJoCo's convex collider misjudges a sphere low on a tall cylinder (docs/simulation.md,
  /// "Tall cylinders and hexagons").
  double contact_height = 0;
  /// Colour (RGBA, 0–1) for rendering only.
  std::array<double, 4> rgba{{0.55, 0.55, 0.6, 1}};
};

/// A surface that is not pushed: fixed in the work frame (the following tasks' dome and ramp)
/// or carried by a leader arm (the tracking task's plate, moved with World::setFixturePose).
/// Shapes, in the fixture's frame {o}:
///   "plate" a square plate, side `size`, thickness `size2`; its touched face is the plane
///           z_o = 0 (solid below), centred on the origin;
///   "dome"  a sphere of radius `size` centred on the origin (its upper half is the dome);
///   "ramp"  the curved ramp: height h(y) = H for y < 0, H (1 + cos(π y / L)) / 2 on [0, L] and
///           0 beyond (convex, then concave), with H = `size`, L = `size2`, `width` along x_o,
///           flat for 80 mm before and after. MuJoCo collides convex shapes, so the curved part
///           is `segments` boxes whose top faces are the profile's chords (L / segments long;
///           the chords leave the arc by H π² L / (16 segments²) at most: 12 µm for the paper's
///           40 mm by 200 mm ramp in 100 segments).
struct FixtureSpec {
  std::string name = "fixture";
  std::string shape = "plate";  ///< "plate", "dome" or "ramp"
  double size = 120;            ///< mm: plate side, dome radius or ramp height H
  double size2 = 10;            ///< mm: plate thickness or ramp length L (dome: unused)
  double width = 80;            ///< mm: the ramp's width (others: unused)
  int segments = 100;           ///< the ramp's chords (others: unused)
  SE3d pose = SE3d::identity(); ///< X_wo (mm)
  bool carried = false;         ///< moved by a leader arm (World::setFixturePose), else fixed
  double friction = 0.8;        ///< μ_c, skin–surface sliding friction at the sensor
};

/// A TacTip sensor carried by an arm.
struct SensorSpec {
  std::string name = "sensor";
  double tip_radius = 20;  ///< mm: hemispherical tip of the 40 mm TacTip
  /// N/mm: normal force per mm of contact depth (the spring along z_s). A soft silicone-gel
  /// tip of radius R pressed to depth d gives F = (4/3) E* sqrt(R) d^(3/2) (Hertz); with an
  /// assumed E* ≈ 0.1 MPa and R = 20 mm that is 0.6 N at 1 mm and 2.6 N at 3 mm; the linear
  /// 0.8 N/mm is its secant at the 1.5–2.5 N of a push.
  double gel_stiffness = 0.8;
  /// k_t / k_gel: the gel's stiffness across the sensor axis (x_s, y_s) over k_gel; 2/3 is
  /// Mindlin's ratio for an incompressible elastic contact.
  double gel_tangential_ratio = 2.0 / 3.0;
  /// ζ of the gel spring: damping 2ζ sqrt(k m_tip) on each slide joint (k its stiffness).
  double gel_damping_ratio = 1.0;
  SE3d initial_pose = SE3d::identity();  ///< X_ws (mm)
};

struct SceneSpec {
  SupportSpec support{};
  std::vector<ObjectSpec> objects;
  std::vector<FixtureSpec> fixtures;
  std::vector<SensorSpec> sensors;
  double timestep = 0.002;  ///< s, MuJoCo's integration step
  double impratio = 1;      ///< elliptic-cone friction-to-normal impedance ratio (MuJoCo's default)

  /// Throws SceneError naming the parameter: non-positive size, height, mass or timestep,
  /// negative friction, an unknown shape, a non-finite or non-orthonormal pose, duplicate
  /// names.
  void validate() const;
};

/// The nearest point of an object or fixture to a sensor's tip centre, from MuJoCo's
/// collision geometry.
struct TipGeometry {
  bool valid = false;            ///< an object or fixture within the query range of the tip
  int object = -1;               ///< index into SceneSpec::objects, or −1
  int fixture = -1;              ///< index into SceneSpec::fixtures, or −1
  Vec3 point_w = Vec3::Zero();   ///< nearest object surface point (mm, work frame)
  Vec3 normal_w = Vec3::UnitZ(); ///< outward object normal there
  double depth = 0;              ///< mm: tip radius − distance of the tip centre (> 0 in contact)
};

class World {
 public:
  /// Builds and loads the scene; throws SceneError (bad spec, or MuJoCo's own load error).
  explicit World(const SceneSpec& spec);
  ~World();
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  /// Back to the scene as built: objects, fixtures and sensors at their initial poses, at rest,
  /// no applied forces.
  void reset() noexcept;

  /// Advances the physics by dt (a whole number of MuJoCo steps, at least one). Never throws;
  /// dt ≤ 0 or non-finite → invalid_time_step; a non-finite state → numerical_failure.
  Status step(double dt) noexcept;

  /// X_wo of object i (mm): the frame at the centre of its base, z up.
  SE3d objectPose(int i) const noexcept;
  /// Tilt of object i's axis from the support normal (rad): toppling shows here.
  double objectTilt(int i) const noexcept;
  /// An external force F (N, work frame) on object i at point p (mm, work frame), held until
  /// changed (clearForces): a disturbance, or a known push for checks against hand calculations.
  void applyObjectForce(int i, const Vec3& force_w, const Vec3& point_w) noexcept;
  /// A force at the centre of mass and a torque (N, N·m, work frame) on object i, held until
  /// changed (clearForces).
  void applyObjectWrench(int i, const Vec3& force_w, const Vec3& torque_w) noexcept;
  void clearForces() noexcept;

  /// X_wo of fixture j (mm).
  SE3d fixturePose(int j) const noexcept;
  /// Moves a carried fixture (the leader's plate) to X_wo: it is there at once, and MuJoCo sees
  /// it moving, during the next step, with the twist that took it there from its last pose.
  /// Refuses a fixed fixture (invalid_argument) and a non-finite or non-orthonormal pose.
  Status setFixturePose(int j, const SE3d& X_wo) noexcept;

  SE3d sensorPose(int s) const noexcept;
  /// Puts sensor s at X_ws, at rest (a teleport: a finished move); refuses a non-finite or
  /// non-orthonormal pose.
  Status setSensorPose(int s, const SE3d& X_ws) noexcept;
  /// The body twist [v (mm/s); ω (rad/s)] sensor s moves with from now on: each MuJoCo step
  /// moves it by X_ws ← X_ws · exp(u^ h), with MuJoCo seeing that velocity (so friction acts
  /// on a tip that slides); refuses a non-finite twist.
  Status setSensorTwist(int s, const Vec6& twist_s) noexcept;

  /// Nearest object or fixture to sensor s's tip centre within `range` mm of its surface.
  TipGeometry tipGeometry(int s, double range = 30) const noexcept;
  /// Total normal force (N) of sensor s's tip on the objects, from MuJoCo's contact forces.
  /// tipGeometry's depth is measured from the arm's nominal tip, so it includes the gel's
  /// deflection.
  double tipNormalForce(int s) const noexcept;
  /// The total force (N, work frame) that sensor s's tip exerts on what it touches, from
  /// MuJoCo's contact forces (normal and friction).
  Vec3 tipContactForce(int s) const noexcept;
  /// The tip's gel deflection (mm, sensor frame): where the touching tip sits relative to the
  /// arm's nominal tip (the three slide joints).
  Vec3 gelDeflection(int s) const noexcept;

  /// MuJoCo's generalised positions now (qpos: metres, unit quaternions), for a StateLog.
  std::vector<double> positions() const;

  int objectCount() const noexcept { return int(spec_.objects.size()); }
  int fixtureCount() const noexcept { return int(spec_.fixtures.size()); }
  int sensorCount() const noexcept { return int(spec_.sensors.size()); }
  const SceneSpec& spec() const noexcept { return spec_; }

 private:
  // A body an arm moves (a sensor, a carried fixture): a free joint whose pose and velocity
  // are set at every step, so that MuJoCo's friction sees its motion.
  struct Driven {
    int body = -1, qpos = -1, dof = -1;
    SE3d initial_pose = SE3d::identity(), pose = SE3d::identity();
    Vec6 twist = Vec6::Zero();  // body twist [v (mm/s); ω (rad/s)]
  };
  Driven drivenBody(int body, const SE3d& X0) const;
  void writeState(const Driven& b) noexcept;  // pose, twist → the free joint's qpos, qvel

  SceneSpec spec_;
  mjModel_* m_ = nullptr;
  mjData_* d_ = nullptr;
  std::vector<int> object_body_, object_qpos_, object_dof_;
  std::vector<std::pair<int, int>> object_geoms_;   // [first, last) geom ids
  std::vector<int> fixture_body_, fixture_driven_;  // fixture_driven_: index in driven_, or −1 (fixed)
  std::vector<std::pair<int, int>> fixture_geoms_;  // [first, last) geom ids
  std::vector<int> sensor_driven_, sensor_geom_, sensor_probe_, sensor_gel_qpos_, sensor_tip_body_;
  std::vector<Driven> driven_;
};

/// The MJCF text of a scene (metres inside). Validates first. Colours, a light and each
/// sensor's body (a black cylinder behind the tip, touching nothing, massless) are for
/// rendering only: they do not change the dynamics.
std::string sceneMjcf(const SceneSpec& spec);
/// The scene compiled by MuJoCo (validates first; throws SceneError). The caller owns it
/// (mj_deleteModel).
mjModel_* loadScene(const SceneSpec& spec);
/// Any MJCF text compiled by MuJoCo from memory (throws SceneError with MuJoCo's message). The
/// caller owns it (mj_deleteModel).
mjModel_* loadMjcf(const std::string& mjcf);

/// A run's world states, kept so that it can be shown afterwards (render.hpp) without
/// touching the run: the scene as built and MuJoCo's generalised positions (qpos: metres,
/// unit quaternions) at the logged times.
struct StateLog {
  SceneSpec scene;
  std::vector<double> times;              ///< s from the start of the run
  std::vector<std::vector<double>> qpos;  ///< one per time
  void add(double t, std::vector<double> q) {
    times.push_back(t);
    qpos.push_back(std::move(q));
  }
  bool empty() const { return qpos.empty(); }
};

/// The ramp fixture's height h(y) (mm) at y (mm, along y_o): the profile of FixtureSpec.
double rampHeight(const FixtureSpec& ramp, double y);

/// The object's base outline in its own frame (mm, counter-clockwise; a circle as a 48-gon),
/// for plots.
std::vector<Vec2> footprint(const ObjectSpec& object);
/// Base area (mm²).
double baseArea(const ObjectSpec& object);
/// Mean distance from the axis over the base under uniform pressure (mm): the breakaway
/// torque over the breakaway force of a flat base sliding on a plane (0.383 a for a square of
/// side a, 2R/3 for a disc; exact for the polygons).
double uniformPressureRadius(const ObjectSpec& object);
/// The points (object frame, mm, on the base plane) at which the object touches the support:
/// 12 equally loaded points in two rings, the outline (a polygon's vertices; 6 points on a
/// circle's rim, one on +x) and an inner ring (the outline again; a rectangle's with its edge
/// midpoints) scaled by λ, with λ chosen so that the points' mean distance from the axis is
/// uniformPressureRadius(): the base turns and slides as a uniformly pressed flat base does,
/// and tips about its true outline.
std::vector<Vec2> basePoints(const ObjectSpec& object);
/// Distance from the object's axis to its side face along +x_o (mm): where a push along −x_o
/// meets it.
double halfExtentX(const ObjectSpec& object);

}  // namespace lieservo::sim::mujoco
