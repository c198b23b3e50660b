// Task options, statistics, objects, surfaces and the paper's reference values.
#include <algorithm>
#include <cmath>
#include <limits>

#include "task_common.hpp"

namespace lieservo::sim {

void TaskOptions::validate() const {
  requirePositive(control_rate, "TaskOptions.control_rate");
  if (control_rate > 1000) throw SceneError("TaskOptions.control_rate must be <= 1000 Hz");
  if (substeps < 1 || substeps > 100) throw SceneError("TaskOptions.substeps must be in [1, 100]");
  requirePositive(duration_scale, "TaskOptions.duration_scale");
  if (duration_scale > 10) throw SceneError("TaskOptions.duration_scale must be <= 10");
  calibration.validate();
  arm.validate();
  contact.validate();
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

// Foam: higher support friction, pressure spread evenly (the object beds into the foam).
// MDF: lower support friction, pressure towards the rim of a hard, slightly uneven base.
// Pusher-object friction is that of the same skin on the same prisms in both settings.
SupportSurface foamSurface() { return {"foam", 0.6, 1.0, 0.25, 0.75}; }
SupportSurface mdfSurface() { return {"MDF", 0.35, 1.25, 0.25, 0.75}; }

std::vector<PushObject> shortObjects() {
  return {{"blue square", "square", 100, 60, 0.479},
          {"blue circle", "circle", 50, 60, 0.363},
          {"red square", "square", 75, 60, 0.264},
          {"yellow hexagon", "hexagon", 50, 60, 0.310}};
}
std::vector<PushObject> tallObjects() {
  return {{"tall blue square", "square", 100, 120, 0.566},
          {"tall blue circle", "circle", 50, 120, 0.436},
          {"tall red square", "square", 75, 120, 0.324},
          {"tall yellow hexagon", "hexagon", 50, 120, 0.373}};
}

void PushingSetup::validate() const {
  requirePositive(object.size, "PushObject.size");
  requirePositive(object.height, "PushObject.height");
  requirePositive(object.mass, "PushObject.mass");
  if (object.shape != "square" && object.shape != "circle" && object.shape != "hexagon")
    throw SceneError("PushObject.shape must be square, circle or hexagon (got '" + object.shape + "')");
  requirePositive(surface.object_friction, "SupportSurface.object_friction");
  requirePositive(surface.pressure_factor, "SupportSurface.pressure_factor");
  requireNonNegative(surface.pusher_friction, "SupportSurface.pusher_friction");
  requireNonNegative(surface.holding_friction, "SupportSurface.holding_friction");
  requirePositive(tip_stiffness, "PushingSetup.tip_stiffness");
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
  if (o == "blue square") return foam ? PaperValue{0.50, 0.56} : PaperValue{4.45, 0.78};
  if (o == "blue circle") return foam ? PaperValue{6.93, 0.06} : PaperValue{9.45, 0.13};
  if (o == "red square") return foam ? PaperValue{1.88, 0.71} : PaperValue{4.38, 0.77};
  if (o == "yellow hexagon") return foam ? PaperValue{0.33, 1.32} : PaperValue{2.87, 0.68};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  return {nan, nan};
}
PaperValue paperDualArm(const std::string& o, const std::string& s, bool tall) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (tall) {
    if (s != "MDF") return {nan, nan};
    if (o == "tall blue square") return {3.62, 0.31};
    if (o == "tall blue circle") return {7.11, 2.18};
    if (o == "tall red square") return {4.94, 0.19};
    if (o == "tall yellow hexagon") return {4.73, 0.38};
    return {nan, nan};
  }
  const bool foam = s == "foam";
  if (o == "blue square") return foam ? PaperValue{4.43, 0.25} : PaperValue{5.24, 0.24};
  if (o == "blue circle") return foam ? PaperValue{4.46, 3.35} : PaperValue{3.58, 2.04};
  if (o == "red square") return foam ? PaperValue{4.97, 0.18} : PaperValue{4.28, 0.15};
  if (o == "yellow hexagon") return foam ? PaperValue{4.43, 0.31} : PaperValue{4.44, 0.62};
  return {nan, nan};
}

}  // namespace lieservo::sim
