// lieservo_sim/scene_mjcf.cpp — a scene (SceneSpec) as MuJoCo's MJCF: the support, the
// objects with their base points, the fixtures, the sensors on their gel, the contact pairs.
#include "lieservo_sim/mujoco_world.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

#include "mujoco_model.hpp"

namespace lieservo::sim::mujoco {
namespace {

using namespace model;

// The tip–object contact is overdamped (damping ratio 2): at a time constant of two steps, the
// least MuJoCo resolves, a critically damped contact rings against a moving object (its normal
// force ripples at the step rate), and each ripple lets a stuck gel slide back, so that a gel
// dragged along a pushed face held a fraction of μ_c N. The stick tests in tests/sim hold it.
constexpr const char* kContactSolref = "0.005 2";  // s, damping ratio
constexpr const char* kContactSolimp = "0.99 0.99 0.001";  // constant impedance near 1: stiff
// MuJoCo's soft friction is a damper below its limit: a force f makes it creep at a speed
// proportional to f. Its noslip pass (a few projected Gauss–Seidel sweeps over the friction
// directions after the main solver) removes that creep, so a gel stuck to a face holds its
// shear up to μ_c N (tests/sim: the stick tests).
constexpr int kNoslipIterations = 5;

// The objects' base points (basePoints) are spheres of this radius (mm) resting on the support:
// small, so that a tilted base still touches near its outline.
constexpr double kBaseSphere = 1.0;
// Base–support contact: constant impedance d and critical damping, τ set per object so that
// it sinks by its Winkler depth (supportSolref).
constexpr double kCompliantImpedance = 0.9;
constexpr const char* kSupportSolimp = "0.9 0.9 0.001";

const char* const kShapes[] = {"square", "rectangle", "circle", "hexagon"};
const char* const kFixtureShapes[] = {"plate", "dome", "ramp"};
constexpr double kRampFlat = 80;   // mm of flat ramp before and after the curved part
constexpr double kRampSlab = 20;   // mm: thickness of the ramp's boxes (deeper than any contact)

std::string num(double v);

// RGBA for MJCF, each clamped to [0, 1].
std::string rgbaOf(const std::array<double, 4>& c) {
  std::string out;
  for (double v : c) out += (out.empty() ? "" : " ") + num(std::isfinite(v) ? std::clamp(v, 0.0, 1.0) : 1.0);
  return out;
}

std::string num(double v) {
  std::ostringstream s;
  s.precision(9);
  s << v;
  return s.str();
}

// MuJoCo's quaternion (w, x, y, z) of a rotation matrix.
std::string quatOf(const Mat3& R) {
  const Eigen::Quaterniond q(R);
  return num(q.w()) + " " + num(q.x()) + " " + num(q.y()) + " " + num(q.z());
}

void requireName(const std::string& n, const char* what) {
  if (n.empty()) throw SceneError(std::string(what) + " name must not be empty");
  for (char c : n)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_'))
      throw SceneError(std::string(what) + " name '" + n + "' may hold letters, digits and '_' only");
}

// The regular hexagon as a convex mesh (circumradius r, from z0 to z1, metres), with a face
// normal to +x (vertices at 30° + k 60°), as the square's.
std::string hexagonMesh(const std::string& name, double r, double z0, double z1) {
  std::string v;
  for (const double z : {z0, z1})
    for (int k = 0; k < 6; ++k) {
      const double a = kPi / 6 + k * kPi / 3;
      v += num(r * std::cos(a)) + " " + num(r * std::sin(a)) + " " + num(z) + " ";
    }
  return "    <mesh name=\"" + name + "\" vertex=\"" + v + "\"/>\n";
}

// The object's collision segments along its height (mm) and their geom names. MuJoCo 2.2.2
// collides a sphere with a cylinder or a mesh by MPR, which measures the penetration along the
// line between the two centres: when that line leaves a tall cylinder through its cap (a tip
// low on a tall object), the depth comes out wrong (31.8 mm instead of 1 mm, measured, for
// the 290 mm glass bottle touched at 45 mm). So a cylinder or hexagon touched at
// contact_height is split into a segment centred there and one above it; boxes collide
// analytically and stay whole.
std::vector<std::pair<double, double>> segmentsOf(const ObjectSpec& o) {
  const bool convex = o.shape == "circle" || o.shape == "hexagon";
  if (convex && o.contact_height > 0 && 2 * o.contact_height < o.height)
    return {{0.0, 2 * o.contact_height}, {2 * o.contact_height, o.height}};
  return {{0.0, o.height}};
}
std::string segmentName(const ObjectSpec& o, std::size_t k) { return k == 0 ? o.name : o.name + "_" + std::to_string(k); }

// The support as a Winkler foundation: each of the n base points carries k_i = k_w A / n
// (N/m). MuJoCo's soft contact settles where R f = k r (v = 0), with R = (1 − d)/d · Â the
// regulariser (Â ≈ 1/m: the object's inverse weight), k = 1/(d τ² ζ²) (constant impedance
// d): a point force f sinks by (1 − d) Â f τ², so τ = sqrt(n m / ((1 − d) k_w A)), ζ = 1.
std::string supportSolref(const SupportSpec& support, const ObjectSpec& o) {
  const double n = double(basePoints(o).size()), A = baseArea(o) * kMm * kMm;  // m²
  const double kw = support.foundation_modulus / (kMm * kMm * kMm);              // N/m³
  return num(std::sqrt(n * o.mass / ((1 - kCompliantImpedance) * kw * A))) + " 1";
}

}  // namespace

void SceneSpec::validate() const {
  requirePositive(timestep, "timestep");
  requirePositive(impratio, "impratio");
  requireNonNegative(support.friction, "support friction");
  requirePositive(support.foundation_modulus, "support foundation_modulus");
  std::set<std::string> names;
  for (const ObjectSpec& o : objects) {
    requireName(o.name, "object");
    if (!names.insert(o.name).second) throw SceneError("duplicate name '" + o.name + "'");
    if (std::find(std::begin(kShapes), std::end(kShapes), o.shape) == std::end(kShapes))
      throw SceneError("object '" + o.name + "': unknown shape '" + o.shape +
                       "' (square, rectangle, circle or hexagon)");
    const std::string p = "object '" + o.name + "' ";
    requirePositive(o.size, (p + "size").c_str());
    if (o.shape == "rectangle") requirePositive(o.size2, (p + "size2").c_str());
    requirePositive(o.height, (p + "height").c_str());
    requirePositive(o.mass, (p + "mass").c_str());
    requireNonNegative(o.friction, (p + "friction").c_str());
    requireNonNegative(o.contact_height, (p + "contact_height").c_str());
    if (!std::isfinite(o.x) || !std::isfinite(o.y) || !std::isfinite(o.yaw))
      throw SceneError(p + "position and yaw must be finite");
  }
  for (const FixtureSpec& f : fixtures) {
    requireName(f.name, "fixture");
    if (!names.insert(f.name).second) throw SceneError("duplicate name '" + f.name + "'");
    if (std::find(std::begin(kFixtureShapes), std::end(kFixtureShapes), f.shape) == std::end(kFixtureShapes))
      throw SceneError("fixture '" + f.name + "': unknown shape '" + f.shape + "' (plate, dome or ramp)");
    const std::string p = "fixture '" + f.name + "' ";
    requirePositive(f.size, (p + "size").c_str());
    if (f.shape != "dome") requirePositive(f.size2, (p + "size2").c_str());
    if (f.shape == "ramp") {
      requirePositive(f.width, (p + "width").c_str());
      if (f.segments < 1 || f.segments > 1000) throw SceneError(p + "segments must be in [1, 1000]");
    }
    requireNonNegative(f.friction, (p + "friction").c_str());
    requireValidPose(f.pose, (p + "pose").c_str());
  }
  for (const SensorSpec& s : sensors) {
    requireName(s.name, "sensor");
    if (!names.insert(s.name).second) throw SceneError("duplicate name '" + s.name + "'");
    const std::string p = "sensor '" + s.name + "' ";
    requirePositive(s.tip_radius, (p + "tip_radius").c_str());
    requirePositive(s.gel_stiffness, (p + "gel_stiffness").c_str());
    requirePositive(s.gel_tangential_ratio, (p + "gel_tangential_ratio").c_str());
    requirePositive(s.gel_damping_ratio, (p + "gel_damping_ratio").c_str());
    requireValidPose(s.initial_pose, (p + "initial_pose").c_str());
  }
}

double rampHeight(const FixtureSpec& f, double y) {
  if (y <= 0) return f.size;
  if (y >= f.size2) return 0;
  return 0.5 * f.size * (1 + std::cos(kPi * y / f.size2));
}

namespace {

// A box geom (half sizes hx, hy, hz in mm) centred at c (mm), rotated by α about x.
std::string boxGeom(const std::string& name, double hx, double hy, double hz, const Vec3& c, double alpha,
                    const std::string& extra) {
  return "      <geom name=\"" + name + "\" type=\"box\" size=\"" + num(hx * kMm) + " " + num(hy * kMm) + " " +
         num(hz * kMm) + "\" pos=\"" + num(c.x() * kMm) + " " + num(c.y() * kMm) + " " + num(c.z() * kMm) +
         "\" quat=\"" + quatOf(rotX(alpha)) + "\" " + extra + "/>\n";
}

// The geoms of a fixture in its body frame. They touch nothing but the sensor tips (explicit
// pairs), so they neither rest on the support nor collide with each other.
std::string fixtureGeoms(const FixtureSpec& f) {
  const std::string extra = "contype=\"0\" conaffinity=\"0\" rgba=\"0.85 0.78 0.62 1\"";  // light wood
  if (f.shape == "plate") return boxGeom(f.name, f.size / 2, f.size / 2, f.size2 / 2, Vec3(0, 0, -f.size2 / 2), 0, extra);
  if (f.shape == "dome")
    return "      <geom name=\"" + f.name + "\" type=\"sphere\" size=\"" + num(f.size * kMm) + "\" " + extra + "/>\n";
  // Ramp: the flat top, the chords of the curved part, the flat bottom; each box's top face
  // is the surface, its thickness kRampSlab below it.
  const double hw = f.width / 2, t = kRampSlab / 2;
  std::string g = boxGeom(f.name + "_top", hw, kRampFlat / 2, t, Vec3(0, -kRampFlat / 2, f.size - t), 0, extra);
  for (int i = 0; i < f.segments; ++i) {
    const double y0 = f.size2 * i / f.segments, y1 = f.size2 * (i + 1) / f.segments;
    const double z0 = rampHeight(f, y0), z1 = rampHeight(f, y1);
    const double a = std::atan2(z1 - z0, y1 - y0), len = std::hypot(y1 - y0, z1 - z0);
    const Vec3 n(0, -std::sin(a), std::cos(a));  // the chord's upward normal
    const Vec3 c = Vec3(0, (y0 + y1) / 2, (z0 + z1) / 2) - t * n;
    g += boxGeom(f.name + "_" + std::to_string(i), hw, len / 2, t, c, a, extra);
  }
  return g + boxGeom(f.name + "_bottom", hw, kRampFlat / 2, t, Vec3(0, f.size2 + kRampFlat / 2, -t), 0, extra);
}

// A body moved by an arm (a sensor, a carried fixture): heavy, on a free joint whose pose and
// velocity World sets at every step. MuJoCo's friction acts on velocities, so it must see how
// the body moves: a mocap body is teleported, its velocity is zero to the solver, and a tip
// carried by one slides along a surface with next to no friction.
std::string drivenJoint(const std::string& name) {
  return "      <freejoint name=\"" + name + "_arm\"/>\n      <inertial pos=\"0 0 0\" mass=\"" + num(kArmMass) +
         "\" diaginertia=\"" + num(kArmInertia) + " " + num(kArmInertia) + " " + num(kArmInertia) + "\"/>\n";
}

}  // namespace

namespace {

// <option> (the solver) and, for hexagonal objects, their meshes in <asset>.
void writeOptions(std::ostream& x, const SceneSpec& spec) {
  // MPR (the convex collider: cylinders, meshes) to 0.1 nm. The conjugate-gradient solver to a
  // relative tolerance of 1e-5: on these scenes (24 DoF, 20–30 friction cones) it costs half of
  // the Newton solver's time per step (whose Hessian updates dominate), with the same pass
  // rates over 30 seeded pushes per case (both at 1e-6, docs/simulation.md); 1e-5 is 6 %
  // cheaper than 1e-6 with every engine test passing, and at 1e-4 a stuck gel slips (the stick
  // test fails).
  // Then MuJoCo's noslip pass (kNoslipIterations) removes the soft model's creep in the
  // friction directions. With the noslip pass holding the stick, impratio stays at MuJoCo's
  // default 1 (SceneSpec): a harder friction impedance (10) ill-conditions the solve (24 CG
  // iterations a step against 13).
  x << "  <option timestep=\"" << num(spec.timestep) << "\" gravity=\"0 0 " << num(-kGravity)
    << "\" cone=\"elliptic\" impratio=\"" << num(spec.impratio)
    << "\" mpr_tolerance=\"1e-10\" mpr_iterations=\"100\" solver=\"CG\" tolerance=\"1e-5\" noslip_iterations=\""
    << kNoslipIterations << "\"/>\n";
  bool any_mesh = false;
  for (const ObjectSpec& o : spec.objects) any_mesh = any_mesh || o.shape == "hexagon";
  if (any_mesh) {
    x << "  <asset>\n";
    for (const ObjectSpec& o : spec.objects) {
      if (o.shape != "hexagon") continue;
      const auto seg = segmentsOf(o);
      for (std::size_t k = 0; k < seg.size(); ++k)
        x << hexagonMesh(segmentName(o, k) + "_mesh", o.size * kMm, seg[k].first * kMm, seg[k].second * kMm);
    }
    x << "  </asset>\n";
  }
}

// An object's body: its segments' geoms (box, cylinder or mesh) and its base points.
void writeObject(std::ostream& x, const ObjectSpec& o) {
  const double h = o.height * kMm, s = o.size * kMm;
  x << "    <body name=\"" << o.name << "\" pos=\"" << num(o.x * kMm) << " " << num(o.y * kMm)
    << " 0\" quat=\"" << quatOf(rotZ(o.yaw)) << "\">\n      <freejoint name=\"" << o.name << "_free\"/>\n";
  const auto seg = segmentsOf(o);
  for (std::size_t k = 0; k < seg.size(); ++k) {
    const double z0 = seg[k].first * kMm, z1 = seg[k].second * kMm, hs = z1 - z0;
    std::string geom;
    if (o.shape == "square" || o.shape == "rectangle")
      geom = "type=\"box\" size=\"" + num(s / 2) + " " + num((o.shape == "square" ? s : o.size2 * kMm) / 2) + " " +
             num(hs / 2) + "\" pos=\"0 0 " + num(z0 + hs / 2) + "\"";
    else if (o.shape == "circle")
      geom = "type=\"cylinder\" size=\"" + num(s) + " " + num(hs / 2) + "\" pos=\"0 0 " + num(z0 + hs / 2) + "\"";
    else
      geom = "type=\"mesh\" mesh=\"" + segmentName(o, k) + "_mesh\"";
    // The mass split by height: the same density, so the same centre of mass and inertia.
    // The body touches the sensors (pairs below), never the support.
    x << "      <geom name=\"" << segmentName(o, k) << "\" " << geom << " mass=\"" << num(o.mass * hs / h)
      << "\" contype=\"0\" conaffinity=\"0\" rgba=\"" << rgbaOf(o.rgba) << "\"/>\n";
  }
  // The base: small massless spheres whose lowest points are the base points on z_o = 0.
  const std::vector<Vec2> base = basePoints(o);
  for (std::size_t k = 0; k < base.size(); ++k)
    x << "      <geom name=\"" << o.name << "_base" << k << "\" type=\"sphere\" size=\"" << num(kBaseSphere * kMm)
      << "\" pos=\"" << num(base[k].x() * kMm) << " " << num(base[k].y() * kMm) << " " << num(kBaseSphere * kMm)
      << "\" mass=\"0\" contype=\"0\" conaffinity=\"0\" group=\"3\"/>\n";
  x << "    </body>\n";

}

// A fixture's body (carried by its leader arm when f.carried) and its geoms.
void writeFixture(std::ostream& x, const FixtureSpec& f) {
  const Vec3 p = f.pose.translation() * kMm;
  x << "    <body name=\"" << f.name << "\" pos=\"" << num(p.x()) << " " << num(p.y()) << " " << num(p.z())
    << "\" quat=\"" << quatOf(f.pose.rotationMatrix()) << "\">\n";
  if (f.carried) x << drivenJoint(f.name);  // moved by its leader arm (World::setFixturePose)
  x << fixtureGeoms(f) << "    </body>\n";

}

// A sensor: the arm's driven body, the probe, the TacTip's body and the tip on its gel.
void writeSensor(std::ostream& x, const SensorSpec& s) {
  // The arm's nominal tip: a driven body (drivenJoint). Its "probe" sphere
  // touches nothing (contype/conaffinity 0, no pairs) and gives the tactile depth
  // (tipGeometry). The gel carries the tip body (see kTipMass); the tip touches the objects
  // through the explicit pairs below only, never the support.
  const double k = s.gel_stiffness / kMm;  // N/m, along z_s
  const double b = 2 * s.gel_damping_ratio * std::sqrt(k * kTipMass);
  x << "    <body name=\"" << s.name << "\" pos=\"" << num(s.initial_pose.translation()[0] * kMm) << " "
    << num(s.initial_pose.translation()[1] * kMm) << " " << num(s.initial_pose.translation()[2] * kMm)
    << "\" quat=\"" << quatOf(s.initial_pose.rotationMatrix()) << "\">\n"
    << drivenJoint(s.name) << "      <geom name=\"" << s.name << "_probe\" type=\"sphere\" size=\"" << num(s.tip_radius * kMm)
    << "\" contype=\"0\" conaffinity=\"0\" rgba=\"0 0 0 0\"/>\n"
    // The TacTip's body behind its tip, for rendering: the explicit inertial ignores it.
    << "      <geom name=\"" << s.name << "_body\" type=\"cylinder\" size=\"" << num(s.tip_radius * kMm) << " "
    << num(s.tip_radius * kMm) << "\" pos=\"0 0 " << num(-s.tip_radius * kMm)
    << "\" contype=\"0\" conaffinity=\"0\" group=\"1\" rgba=\"0.08 0.08 0.08 1\"/>\n"
    << "      <body name=\"" << s.name << "_tip\">\n";
  const double kt = k * s.gel_tangential_ratio, bt = 2 * s.gel_damping_ratio * std::sqrt(kt * kTipMass);
  for (const char* axis : {"1 0 0", "0 1 0"})
    x << "        <joint type=\"slide\" axis=\"" << axis << "\" stiffness=\"" << num(kt) << "\" damping=\"" << num(bt)
      << "\"/>\n";
  x << "        <joint type=\"slide\" axis=\"0 0 1\" stiffness=\"" << num(k) << "\" damping=\"" << num(b) << "\"/>\n";
  x << "        <geom name=\"" << s.name << "\" type=\"sphere\" size=\"" << num(s.tip_radius * kMm) << "\" mass=\""
    << num(kTipMass) << "\" contype=\"0\" conaffinity=\"0\" rgba=\"0.9 0.9 0.9 1\"/>\n      </body>\n    </body>\n";

}

// <contact>: each object's base points on the support, each sensor's tip on every surface it
// can touch.
void writeContacts(std::ostream& x, const SceneSpec& spec) {
  std::vector<std::pair<std::string, double>> touchable;  // geom name, μ_c
  for (const ObjectSpec& o : spec.objects)
    for (std::size_t k = 0; k < segmentsOf(o).size(); ++k) touchable.emplace_back(segmentName(o, k), o.friction);
  for (const FixtureSpec& f : spec.fixtures) {
    if (f.shape != "ramp") {
      touchable.emplace_back(f.name, f.friction);
      continue;
    }
    touchable.emplace_back(f.name + "_top", f.friction);
    for (int i = 0; i < f.segments; ++i) touchable.emplace_back(f.name + "_" + std::to_string(i), f.friction);
    touchable.emplace_back(f.name + "_bottom", f.friction);
  }
  x << "  <contact>\n";
  // Object–support: each base point on the support plane, sliding friction μ_s, no torsional
  // friction (turning is resisted by the spread of the points); the object sinks by its
  // Winkler depth (supportSolref).
  for (const ObjectSpec& o : spec.objects) {
    const std::string solref = supportSolref(spec.support, o);
    const std::size_t n = basePoints(o).size();
    for (std::size_t k = 0; k < n; ++k)
      x << "    <pair geom1=\"support\" geom2=\"" << o.name << "_base" << k << "\" condim=\"3\" friction=\""
        << num(spec.support.friction) << " " << num(spec.support.friction) << " 0 0 0\" solref=\"" << solref
        << "\" solimp=\"" << kSupportSolimp << "\"/>\n";
  }
  if (!spec.sensors.empty() && !touchable.empty()) {
    for (const SensorSpec& s : spec.sensors)
      for (const auto& [geom, mu] : touchable)
        x << "    <pair geom1=\"" << s.name << "\" geom2=\"" << geom << "\" condim=\"4\" friction=\"" << num(mu)
          << " " << num(mu) << " 0.005 0.0001 0.0001\" solref=\"" << kContactSolref << "\" solimp=\""
          << kContactSolimp << "\"/>\n";
  }
  x << "  </contact>\n";
}

}  // namespace

std::string sceneMjcf(const SceneSpec& spec) {
  spec.validate();
  std::ostringstream x;
  x << "<mujoco model=\"lieservo_scene\">\n";
  writeOptions(x, spec);
  // The support touches the objects' base points only, through explicit pairs (below); no
  // geom collides by type and affinity.
  // A light from above for rendering (render.hpp); lights and colours do not enter the dynamics.
  x << "  <worldbody>\n"
    << "    <light name=\"sun\" directional=\"true\" pos=\"0 0 2\" dir=\"0.3 -0.2 -1\" diffuse=\"0.7 0.7 0.7\"/>\n"
    << "    <geom name=\"support\" type=\"plane\" size=\"2 2 0.01\" contype=\"0\" conaffinity=\"0\" rgba=\""
    << rgbaOf(spec.support.rgba) << "\"/>\n";
  for (const ObjectSpec& o : spec.objects) writeObject(x, o);
  for (const FixtureSpec& f : spec.fixtures) writeFixture(x, f);
  for (const SensorSpec& s : spec.sensors) writeSensor(x, s);
  x << "  </worldbody>\n";
  writeContacts(x, spec);
  x << "</mujoco>\n";
  return x.str();
}

}  // namespace lieservo::sim::mujoco
