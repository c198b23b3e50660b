// lieservo_sim/mujoco_world.hpp — the physical world of the simulated tasks, on MuJoCo.
//
// A scene (support, objects, TacTip sensors) is written as MJCF and loaded into MuJoCo, which
// integrates the rigid-body dynamics and resolves the contacts: objects slide, turn and topple
// on the support under gravity and the sensors' pushes. What MuJoCo does not give, the tactile
// features (contact frame, depth, shear with stick/slip), is derived from its contact geometry:
// World::tipGeometry gives the nearest object point, its normal and the depth from MuJoCo's
// own collision functions.
//
// Units at this interface are the paper's: mm, kg, s, radians; MuJoCo works in metres inside.
//
// Sensors. Each sensor is a mocap body: the arm holding it is position-stiff, so the sensor
// pose is what the commanded twist makes it (MujocoSensorArm integrates X_ws ← X_ws exp(u dt)
// under velocity and acceleration limits). Its tip is a sphere of radius 20 mm (the 40 mm
// TacTip's hemisphere; the back half never touches in these tasks). The compliant gel is a
// spring between the arm's nominal tip and the touching tip: the tip is a light body on three
// slide joints with stiffness k_gel (SensorSpec::gel_stiffness), so a contact depth d (the
// object's surface inside the nominal tip sphere) presses the object with ≈ k_gel d, whatever
// its mass, and a sticking contact shears the gel sideways. Tip–object contacts are stiff,
// with elliptic friction cones, a high impratio (no creeping slip) and condim 4 (torsional
// friction, the twist γ).
#pragma once

#include <string>
#include <vector>

#include <lieservo/status.hpp>

#include "common.hpp"
#include "robot_interface.hpp"
#include "simulated_arm.hpp"

struct mjModel_;
struct mjData_;

namespace lieservo::sim::mujoco {

/// The surface the objects stand on, with its friction against them (sliding μ_s).
struct SupportSpec {
  std::string name = "MDF";
  double friction = 0.35;  ///< μ_s, object–support sliding friction
  /// The paper's two supports: soft foam (μ_s 0.6, the object beds in) and a hard MDF board
  /// (μ_s 0.35). Both are assumptions of plausible friction coefficients (docs/simulation.md).
  static SupportSpec foam() { return {"foam", 0.6}; }
  static SupportSpec mdf() { return {"MDF", 0.35}; }
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
};

/// A TacTip sensor carried by an arm.
struct SensorSpec {
  std::string name = "sensor";
  double tip_radius = 20;  ///< mm: hemispherical tip of the 40 mm TacTip
  /// N/mm: normal force per mm of contact depth. A soft silicone-gel tip of radius R pressed
  /// to depth d gives F = (4/3) E* sqrt(R) d^(3/2) (Hertz); with an assumed E* ≈ 0.1 MPa (a
  /// soft silicone gel) and R = 20 mm that is ≈ 0.6 N/mm at 1 mm and 1.5 N/mm at 6 mm; the
  /// linear 1 N/mm used here sits between them (0–6 N over the 0–6 mm depth range).
  double gel_stiffness = 1.0;
  /// ζ of the gel spring: damping 2ζ sqrt(k_gel m_tip) on each slide joint.
  double gel_damping_ratio = 1.0;
  SE3d initial_pose = SE3d::identity();  ///< X_ws (mm)
};

struct SceneSpec {
  SupportSpec support{};
  std::vector<ObjectSpec> objects;
  std::vector<SensorSpec> sensors;
  double timestep = 0.002;  ///< s, MuJoCo's integration step
  double impratio = 10;     ///< elliptic-cone friction-to-normal impedance ratio

  /// Throws SceneError naming the parameter: non-positive size, height, mass or timestep,
  /// negative friction, an unknown shape, a non-finite or non-orthonormal initial pose,
  /// duplicate names.
  void validate() const;
};

/// The nearest point of an object to a sensor's tip centre, from MuJoCo's collision geometry.
struct TipGeometry {
  bool valid = false;            ///< an object within the query range of the tip
  int object = -1;               ///< index into SceneSpec::objects
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
  void clearForces() noexcept;

  SE3d sensorPose(int s) const noexcept;
  /// Moves sensor s (a mocap body) to X_ws; refuses a non-finite or non-orthonormal pose.
  Status setSensorPose(int s, const SE3d& X_ws) noexcept;

  /// Nearest object to sensor s's tip centre within `range` mm of its surface.
  TipGeometry tipGeometry(int s, double range = 30) const noexcept;
  /// Total normal force (N) of sensor s's tip on the objects, from MuJoCo's contact forces.
  /// tipGeometry's depth is measured from the arm's nominal tip, so it includes the gel's
  /// deflection.
  double tipNormalForce(int s) const noexcept;

  int objectCount() const noexcept { return int(spec_.objects.size()); }
  int sensorCount() const noexcept { return int(spec_.sensors.size()); }
  const SceneSpec& spec() const noexcept { return spec_; }

 private:
  SceneSpec spec_;
  mjModel_* m_ = nullptr;
  mjData_* d_ = nullptr;
  std::vector<int> object_body_, object_geom_, object_qpos_, object_dof_;
  std::vector<int> sensor_mocap_, sensor_geom_, sensor_probe_;
};

/// The MJCF text of a scene (metres inside). Validates first.
std::string sceneMjcf(const SceneSpec& spec);

/// The object's base outline in its own frame (mm, counter-clockwise; a circle as a 48-gon),
/// for plots.
std::vector<Vec2> footprint(const ObjectSpec& object);
/// Distance from the object's axis to its side face along +x_o (mm): where a push along −x_o
/// meets it.
double halfExtentX(const ObjectSpec& object);

/// A sensor of a World driven as a robot: RobotInterface's commanded body twist in {s} moves
/// the sensor's mocap body, X_ws ← X_ws exp(u dt), within speed and acceleration limits.
/// The limits are the kinematic arm's (ArmLimits, limitTwist); its `substeps` is not used here.
class MujocoSensorArm final : public lieservo::robot::RobotInterface {
 public:
  MujocoSensorArm(World& world, int sensor, const ArmLimits& limits = {});

  Status readPose(SE3d& X_ws) override;
  /// Moves the sensor for dt under the limits (the world is stepped by the caller).
  Status commandVelocity(const SE3d::Tangent& twist_s, double dt) override;
  Status moveTo(const SE3d& X_ws) override;
  void stop() override { applied_.setZero(); }
  const SE3d::Tangent& appliedTwist() const { return applied_; }

 private:
  World* world_;
  int sensor_;
  ArmLimits limits_;
  SE3d::Tangent applied_ = SE3d::Tangent::Zero();
};

}  // namespace lieservo::sim::mujoco
