// Task options, statistics, objects, surfaces and the paper's reference values.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "task_common.hpp"

namespace lieservo::sim {

mujoco::SensorSpec taskSensor(const std::string& name, const ContactParams& contact, const SE3d& X_ws) {
  mujoco::SensorSpec s;
  s.name = name;
  s.tip_radius = contact.tip_radius;
  s.gel_stiffness = contact.gel_stiffness;
  s.gel_tangential_ratio = contact.gel_tangential_ratio;
  s.initial_pose = X_ws;
  return s;
}

void PhysicalRanges::validate() const {
  auto range = [](const double (&r)[2], const char* name) {
    requirePositive(r[0], name);
    requirePositive(r[1], name);
    if (r[0] > r[1]) throw SceneError(std::string(name) + " must be an interval [low, high] with low <= high");
  };
  range(support_friction_scale, "PhysicalRanges.support_friction_scale");
  range(skin_friction, "PhysicalRanges.skin_friction");
  range(gel_stiffness, "PhysicalRanges.gel_stiffness");
}

void TaskOptions::validate() const {
  requirePositive(control_rate, "TaskOptions.control_rate");
  if (control_rate > 1000) throw SceneError("TaskOptions.control_rate must be <= 1000 Hz");
  requirePositive(duration_scale, "TaskOptions.duration_scale");
  if (duration_scale > 10) throw SceneError("TaskOptions.duration_scale must be <= 10");
  calibration.validate();
  arm.validate();
  contact.validate();
  ranges.validate();
  // NaN: drawn per trial; anything else must be a placement a person could set up.
  auto fixedIn = [](double v, double bound, const char* name) {
    if (!std::isnan(v) && !(std::abs(v) <= bound))
      throw SceneError(std::string("TaskOptions.") + name + " must be NaN (drawn) or within ±" + std::to_string(bound));
  };
  fixedIn(start_offset, 50, "start_offset (mm)");
  fixedIn(start_yaw, kPi / 4, "start_yaw (rad)");
  if (!std::isnan(support_friction_scale) && !(support_friction_scale > 0 && support_friction_scale <= 3))
    throw SceneError("TaskOptions.support_friction_scale must be NaN (drawn) or in (0, 3]");
}

void Stat::add(double v) {
  v = std::abs(v);
  mean += v;
  rms += v * v;
  max = std::max(max, v);
  ++n;
}
void Stat::finish() {
  if (n == 0) return;
  mean /= double(n);
  rms = std::sqrt(rms / double(n));
}

// The paper's prisms (Figures 8–9: masses; sizes: side, radius, circumradius) and its five
// tall everyday objects (Section 4.3, sec:test_objects) built from primitives with uniform
// density. The everyday objects' masses are the paper's (Figure 9); their sizes are
// approximate: the YCB object set's (Calli et al. 2015) mustard bottle, cream cleanser ("Soft
// Scrub") and Windex bottles as boxes of their base and height, its large coffee tin as a
// cylinder, the glass bottle a wine bottle's (no YCB object).
std::vector<ObjectSpec> shortObjects() {
  // Colours (rendering only): the paper's printed blue, red and yellow.
  auto prism = [](const char* name, const char* shape, double size, double mass, std::array<double, 4> rgba) {
    ObjectSpec o;
    o.name = name, o.shape = shape, o.size = size, o.height = 60, o.mass = mass, o.rgba = rgba;
    return o;
  };
  const std::array<double, 4> blue{{0.12, 0.32, 0.85, 1}}, red{{0.85, 0.15, 0.12, 1}}, yellow{{0.95, 0.8, 0.1, 1}};
  return {prism("blue_square", "square", 100, 0.479, blue), prism("blue_circle", "circle", 50, 0.363, blue),
          prism("red_square", "square", 75, 0.264, red), prism("yellow_hexagon", "hexagon", 50, 0.310, yellow)};
}
std::vector<ObjectSpec> tallObjects() {
  std::vector<ObjectSpec> v = shortObjects();
  const double mass[] = {0.566, 0.436, 0.324, 0.373};
  for (std::size_t i = 0; i < v.size(); ++i) {
    v[i].name = "tall_" + v[i].name;
    v[i].height = 120;
    v[i].mass = mass[i];
  }
  return v;
}
std::vector<ObjectSpec> everydayObjects() {
  auto object = [](const char* name, const char* shape, double size, double size2, double height, double mass,
                   std::array<double, 4> rgba) {
    ObjectSpec o;
    o.name = name, o.shape = shape, o.size = size, o.size2 = size2, o.height = height, o.mass = mass, o.rgba = rgba;
    return o;
  };
  // Rectangles: `size` along the push, `size2` across it (the pushed face). Colours (rendering
  // only) roughly the products', each told apart from the others, the supports and the
  // sensors by tests/sim/check_results_page.py.
  return {object("mustard_bottle", "rectangle", 58, 95, 190, 0.237, {{0.98, 0.8, 0.1, 1}}),
          object("cleaner_bottle", "rectangle", 65, 98, 250, 0.161, {{0.6, 0.85, 0.9, 1}}),
          object("windex_spray", "rectangle", 80, 105, 270, 0.339, {{0.2, 0.55, 0.9, 1}}),
          object("glass_bottle", "circle", 37, 0, 290, 0.641, {{0.3, 0.6, 0.35, 0.8}}),
          object("coffee_tin", "circle", 55, 0, 160, 0.214, {{0.55, 0.1, 0.1, 1}})};
}
std::string displayName(const ObjectSpec& o) {
  std::string n = o.name;
  std::replace(n.begin(), n.end(), '_', ' ');
  return n;
}

void PushingSetup::validate() const {
  mujoco::SceneSpec scene;
  scene.support = surface;
  scene.objects = {object};
  scene.validate();  // names the object's bad parameter
  requirePositive(sensor_height, "PushingSetup.sensor_height");
  if (sensor_height >= object.height)
    throw SceneError("PushingSetup.sensor_height must be below the object's top (the tip must touch a side face)");
  requirePositive(initial_depth, "PushingSetup.initial_depth");
  requirePositive(follower_depth, "PushingSetup.follower_depth");
  if (initial_depth >= 20 || follower_depth >= 20) throw SceneError("PushingSetup depths must be < tip radius");
  requirePositive(timeout, "PushingSetup.timeout");
  if (!start.allFinite() || !target.allFinite()) throw SceneError("PushingSetup start/target must be finite");
  if ((target - start).norm() < 100) throw SceneError("PushingSetup target must be >= 100 mm from the start");
}

PaperValue paperSingleArm(const std::string& o, const std::string& s) {
  const bool foam = s == "foam";
  if (o == "blue_square") return foam ? PaperValue{0.50, 0.56} : PaperValue{4.45, 0.78};
  if (o == "blue_circle") return foam ? PaperValue{6.93, 0.06} : PaperValue{9.45, 0.13};
  if (o == "red_square") return foam ? PaperValue{1.88, 0.71} : PaperValue{4.38, 0.77};
  if (o == "yellow_hexagon") return foam ? PaperValue{0.33, 1.32} : PaperValue{2.87, 0.68};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  return {nan, nan};
}
PaperValue paperDualArm(const std::string& o, const std::string& s, bool tall) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (tall) {
    if (s != "MDF") return {nan, nan};
    if (o == "tall_blue_square") return {3.62, 0.31};
    if (o == "tall_blue_circle") return {7.11, 2.18};
    if (o == "tall_red_square") return {4.94, 0.19};
    if (o == "tall_yellow_hexagon") return {4.73, 0.38};
    if (o == "mustard_bottle") return {6.24, 2.33};
    if (o == "cleaner_bottle") return {7.02, 0.95};
    if (o == "windex_spray") return {4.59, 1.36};
    if (o == "glass_bottle") return {6.42, 0.39};
    if (o == "coffee_tin") return {4.81, 2.09};
    return {nan, nan};
  }
  const bool foam = s == "foam";
  if (o == "blue_square") return foam ? PaperValue{4.43, 0.25} : PaperValue{5.24, 0.24};
  if (o == "blue_circle") return foam ? PaperValue{4.46, 3.35} : PaperValue{3.58, 2.04};
  if (o == "red_square") return foam ? PaperValue{4.97, 0.18} : PaperValue{4.28, 0.15};
  if (o == "yellow_hexagon") return foam ? PaperValue{4.43, 0.31} : PaperValue{4.44, 0.62};
  return {nan, nan};
}

PaperValue paperValue(const PushingCase& c) {
  return c.setup.dual_arm ? paperDualArm(c.setup.object.name, c.setup.surface.name, c.setup.tall)
                          : paperSingleArm(c.setup.object.name, c.setup.surface.name);
}

}  // namespace lieservo::sim
