// Toppling: whether a pushed object tips before it slides, by statics (w/2 against μ_s h) and
// by the engine (a slowly ramped push), and the critical push height and support friction of
// each (docs/simulation.md, "Toppling").
#include <cmath>
#include <functional>
#include <limits>

#include "task_common.hpp"

namespace lieservo::sim {

using mujoco::World;

bool tipsBeforeSliding(const ObjectSpec& object, double support_friction, double push_height) {
  mujoco::SceneSpec scene;
  scene.support = SupportSpec::rigid(support_friction);
  ObjectSpec o = object;
  o.x = o.y = o.yaw = 0;
  scene.objects = {o};
  World w(scene);
  const double m = o.mass, g = 9.81, a = mujoco::halfExtentX(o);
  const double F_max = 2 * support_friction * m * g + m * g * a / push_height;  // past both thresholds
  const double ramp = 4.0, dt = 0.01;  // s: slow, so the object is quasi-static when it gives
  // Statics asks which threshold the rising force meets first, so the first motion decides:
  // the base centre sliding 1 mm, or the object turning 3° about its leading edge (which moves
  // the base centre up, not along). Past that the ramped force would keep rising over a sliding
  // object's friction and tip it in motion, a dynamic threshold statics does not describe.
  const double slide = 1.0, tilt = deg2rad(3);
  for (double t = 0; t < ramp; t += dt) {
    const SE3d X = w.objectPose(0);
    const Vec3 face = X * Vec3(-a, 0, push_height);
    w.applyObjectForce(0, X.rotationMatrix() * Vec3(F_max * t / ramp, 0, 0), face);
    if (w.step(dt) != Status::ok) return false;
    if (w.objectTilt(0) > tilt) return true;
    if (w.objectPose(0).translation().head<2>().norm() > slide) return false;
  }
  return w.objectTilt(0) > tilt;
}

ToppleRow toppleAnalysis(const ObjectSpec& object, double support_friction, double push_height, double tolerance) {
  ToppleRow row;
  row.object = object;
  row.support_friction = support_friction;
  row.push_height = push_height;
  const double a = mujoco::halfExtentX(object);  // w / 2 along the push
  row.statics_height = a / support_friction;
  row.statics_friction = a / push_height;
  // Bisection: below the critical height (or friction) the object slides, above it tips.
  auto bisect = [&](double lo, double hi, const std::function<bool(double)>& tips) {
    while (hi - lo > tolerance * lo) {
      const double mid = 0.5 * (lo + hi);
      (tips(mid) ? hi : lo) = mid;
    }
    return 0.5 * (lo + hi);
  };
  // Pushed at its top, does it tip at all? If not, neither critical height is on the object.
  const double top = 0.98 * object.height;
  if (row.statics_height >= top && !tipsBeforeSliding(object, support_friction, top)) {
    row.engine_height = row.statics_height = std::numeric_limits<double>::infinity();
  } else {
    row.engine_height = bisect(0.5 * std::min(row.statics_height, top), std::min(top, 2 * row.statics_height),
                               [&](double h) { return tipsBeforeSliding(object, support_friction, h); });
  }
  row.engine_friction = bisect(0.5 * row.statics_friction, 2 * row.statics_friction,
                               [&](double mu) { return tipsBeforeSliding(object, mu, push_height); });
  return row;
}

std::vector<ToppleRow> toppleTable(const std::vector<ObjectSpec>& objects) {
  std::vector<ToppleRow> rows(objects.size());
  detail::parallelFor(int(objects.size()), [&](int i) { rows[std::size_t(i)] = toppleAnalysis(objects[std::size_t(i)]); });
  return rows;
}

}  // namespace lieservo::sim
