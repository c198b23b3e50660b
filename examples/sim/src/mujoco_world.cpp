// lieservo_sim/mujoco_world.cpp — scene → MJCF, the MuJoCo model and data, tip geometry.
#include "lieservo_sim/mujoco_world.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <mutex>
#include <set>
#include <sstream>

#include <mujoco/mujoco.h>

#include <lieservo/groups/perturbation.hpp>

namespace lieservo::sim::mujoco {
namespace {

constexpr double kMm = 1e-3;  // mm → m
// The body that carries a sensor: heavy, so that a contact force of 3 N changes its velocity by
// 0.25 mm/s within a step before the arm sets it again (World::step). The reset takes that
// change from the tip as well, a creep of the gel against what it holds: lighter arms let a
// stuck gel creep (10 kg: 16 % of a 1 mm/s drag), heavier ones slow the solver's convergence.
constexpr double kArmMass = 30;        // kg
constexpr double kArmInertia = 0.05;   // kg m²
constexpr double kGravity = 9.81;
// The gel: the tip is a light body on three slide joints (the sensor frame's axes), springs
// k_gel along z_s and ρ_t k_gel across, behind the arm's nominal tip (the sensor body). A push
// of F on the tip deflects it by F/k whatever the object's mass or inertia; the tip–object
// contact itself is stiff (penetration ≈ 0.03 mm per N: kContactSolref, kContactSolimp). The
// tip's mass sets the gel's natural frequency sqrt(k/m) (283 rad/s at 0.8 N/mm: ω dt = 0.7 at
// the 2.5 ms step, stable under MuJoCo's semi-implicit Euler); its weight is the arm's.
constexpr double kTipMass = 0.01;  // kg
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

std::string sceneMjcf(const SceneSpec& spec) {
  spec.validate();
  std::ostringstream x;
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
  x << "<mujoco model=\"lieservo_scene\">\n"
    << "  <option timestep=\"" << num(spec.timestep) << "\" gravity=\"0 0 " << num(-kGravity)
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
  // The support touches the objects' base points only, through explicit pairs (below); no
  // geom collides by type and affinity.
  // A light from above for rendering (render.hpp); lights and colours do not enter the dynamics.
  x << "  <worldbody>\n"
    << "    <light name=\"sun\" directional=\"true\" pos=\"0 0 2\" dir=\"0.3 -0.2 -1\" diffuse=\"0.7 0.7 0.7\"/>\n"
    << "    <geom name=\"support\" type=\"plane\" size=\"2 2 0.01\" contype=\"0\" conaffinity=\"0\" rgba=\""
    << rgbaOf(spec.support.rgba) << "\"/>\n";
  for (const ObjectSpec& o : spec.objects) {
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
  for (const FixtureSpec& f : spec.fixtures) {
    const Vec3 p = f.pose.translation() * kMm;
    x << "    <body name=\"" << f.name << "\" pos=\"" << num(p.x()) << " " << num(p.y()) << " " << num(p.z())
      << "\" quat=\"" << quatOf(f.pose.rotationMatrix()) << "\">\n";
    if (f.carried) x << drivenJoint(f.name);  // moved by its leader arm (World::setFixturePose)
    x << fixtureGeoms(f) << "    </body>\n";
  }
  for (const SensorSpec& s : spec.sensors) {
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
  x << "  </worldbody>\n";
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
  x << "</mujoco>\n";
  return x.str();
}

std::vector<Vec2> footprint(const ObjectSpec& o) {
  std::vector<Vec2> v;
  if (o.shape == "square" || o.shape == "rectangle") {
    const double a = o.size / 2, b = (o.shape == "square" ? o.size : o.size2) / 2;
    return {{a, b}, {-a, b}, {-a, -b}, {a, -b}};
  }
  const int n = o.shape == "circle" ? 48 : 6;
  const double a0 = o.shape == "hexagon" ? kPi / 6 : 0.0;  // as hexagonMesh
  for (int k = 0; k < n; ++k) v.emplace_back(o.size * std::cos(a0 + 2 * kPi * k / n), o.size * std::sin(a0 + 2 * kPi * k / n));
  return v;
}

double baseArea(const ObjectSpec& o) {
  if (o.shape == "circle") return kPi * o.size * o.size;
  const std::vector<Vec2> v = footprint(o);
  double a = 0;
  for (std::size_t i = 0; i < v.size(); ++i) a += 0.5 * (v[i].x() * v[(i + 1) % v.size()].y() - v[(i + 1) % v.size()].x() * v[i].y());
  return a;
}

double uniformPressureRadius(const ObjectSpec& o) {
  if (o.shape == "circle") return 2 * o.size / 3;
  // Over the triangle (axis, v_i, v_(i+1)) in polar coordinates about the axis, ∫∫ r dA =
  // ∫ ρ(θ)³/3 dθ with ρ = d / cos(θ − θ_n) (d, θ_n: the edge line's distance and normal), and
  // ∫ sec³ φ dφ = (sec φ tan φ + ln(sec φ + tan φ)) / 2.
  const std::vector<Vec2> v = footprint(o);
  auto F = [](double phi) {
    const double sec = 1 / std::cos(phi), tan = std::tan(phi);
    return 0.5 * (sec * tan + std::log(sec + tan));
  };
  double integral = 0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const Vec2 a = v[i], b = v[(i + 1) % v.size()];
    const Vec2 e = (b - a).normalized();
    const Vec2 n(e.y(), -e.x());  // outward for a counter-clockwise outline
    const double d = n.dot(a), theta_n = std::atan2(n.y(), n.x());
    const double phi_a = std::remainder(std::atan2(a.y(), a.x()) - theta_n, 2 * kPi);
    const double phi_b = std::remainder(std::atan2(b.y(), b.x()) - theta_n, 2 * kPi);
    integral += d * d * d / 3 * (F(phi_b) - F(phi_a));
  }
  return integral / baseArea(o);
}

std::vector<Vec2> basePoints(const ObjectSpec& o) {
  // The outline: a polygon's vertices, six points on a circle's rim (one on +x). The inner
  // ring: the outline again, for a rectangle with its edge midpoints (eight points, so that the
  // base's second moment stays near the area's: its four corners alone would put it 50 %
  // above), scaled so that all points' mean distance from the axis is the uniform-pressure
  // radius. Every base point costs three constraint rows in each step.
  std::vector<Vec2> outline, inner;
  if (o.shape == "circle") {
    for (int k = 0; k < 6; ++k) outline.emplace_back(o.size * std::cos(kPi * k / 3), o.size * std::sin(kPi * k / 3));
    inner = outline;
  } else {
    outline = footprint(o);
    for (std::size_t i = 0; i < outline.size(); ++i) {
      inner.push_back(outline[i]);
      if (outline.size() == 4) inner.push_back(0.5 * (outline[i] + outline[(i + 1) % outline.size()]));
    }
  }
  double sum_outline = 0, sum_inner = 0;
  for (const Vec2& p : outline) sum_outline += p.norm();
  for (const Vec2& p : inner) sum_inner += p.norm();
  const double n = double(outline.size() + inner.size());
  const double lambda = (n * uniformPressureRadius(o) - sum_outline) / sum_inner;
  std::vector<Vec2> points = outline;
  for (const Vec2& p : inner) points.push_back(lambda * p);
  return points;
}

double halfExtentX(const ObjectSpec& o) {
  if (o.shape == "hexagon") return o.size * std::cos(kPi / 6);  // apothem: a face is normal to +x
  return o.shape == "circle" ? o.size : o.size / 2;
}

mjModel_* loadMjcf(const std::string& mjcf) {
  mjVFS vfs;
  mj_defaultVFS(&vfs);
  const char* file = "lieservo_model.xml";
  if (mj_makeEmptyFileVFS(&vfs, file, int(mjcf.size())) != 0) throw SceneError("MuJoCo: cannot hold the model");
  std::memcpy(vfs.filedata[mj_findFileVFS(&vfs, file)], mjcf.data(), mjcf.size());
  char error[1024] = "";
  mjModel* m = nullptr;
  {
    static std::mutex parser;  // MuJoCo's XML parser is not documented as thread-safe
    const std::lock_guard<std::mutex> lock(parser);
    m = mj_loadXML(file, &vfs, error, sizeof error);
  }
  mj_deleteVFS(&vfs);
  if (!m) throw SceneError(std::string("MuJoCo could not load the model: ") + error);
  return m;
}

mjModel_* loadScene(const SceneSpec& spec) { return loadMjcf(sceneMjcf(spec)); }

World::World(const SceneSpec& spec) : spec_(spec) {
  m_ = loadScene(spec);
  d_ = mj_makeData(m_);
  if (!d_) {
    mj_deleteModel(m_);
    throw SceneError("MuJoCo: out of memory for the scene's data");
  }
  for (const ObjectSpec& o : spec_.objects) {
    const int b = mj_name2id(m_, mjOBJ_BODY, o.name.c_str());
    object_body_.push_back(b);
    object_geoms_.emplace_back(m_->body_geomadr[b], m_->body_geomadr[b] + m_->body_geomnum[b]);
    object_qpos_.push_back(m_->jnt_qposadr[m_->body_jntadr[b]]);
    object_dof_.push_back(m_->jnt_dofadr[m_->body_jntadr[b]]);
  }
  for (const FixtureSpec& f : spec_.fixtures) {
    const int b = mj_name2id(m_, mjOBJ_BODY, f.name.c_str());
    fixture_body_.push_back(b);
    fixture_driven_.push_back(f.carried ? int(driven_.size()) : -1);
    if (f.carried) driven_.push_back(drivenBody(b, f.pose));
    fixture_geoms_.emplace_back(m_->body_geomadr[b], m_->body_geomadr[b] + m_->body_geomnum[b]);
  }
  for (const SensorSpec& s : spec_.sensors) {
    const int b = mj_name2id(m_, mjOBJ_BODY, s.name.c_str());
    sensor_driven_.push_back(int(driven_.size()));
    driven_.push_back(drivenBody(b, s.initial_pose));
    sensor_geom_.push_back(mj_name2id(m_, mjOBJ_GEOM, s.name.c_str()));
    sensor_probe_.push_back(mj_name2id(m_, mjOBJ_GEOM, (s.name + "_probe").c_str()));
    const int tip_body = mj_name2id(m_, mjOBJ_BODY, (s.name + "_tip").c_str());
    sensor_tip_body_.push_back(tip_body);
    sensor_gel_qpos_.push_back(m_->jnt_qposadr[m_->body_jntadr[tip_body]]);
  }
  mj_forward(m_, d_);
}

World::~World() {
  mj_deleteData(d_);
  mj_deleteModel(m_);
}

void World::reset() noexcept {
  mj_resetData(m_, d_);
  for (Driven& b : driven_) {
    b.pose = b.initial_pose;
    b.twist.setZero();
  }
  mj_forward(m_, d_);
}

World::Driven World::drivenBody(int body, const SE3d& X0) const {
  Driven b;
  b.qpos = m_->jnt_qposadr[m_->body_jntadr[body]];
  b.dof = m_->jnt_dofadr[m_->body_jntadr[body]];
  b.body = body;
  b.initial_pose = b.pose = X0;
  return b;
}

void World::writeState(const Driven& b) noexcept {
  const SE3d& X = b.pose;
  const Vec6& u = b.twist;
  double* q = d_->qpos + b.qpos;
  const Vec3 p = X.translation() * kMm;
  const Eigen::Quaterniond quat(X.rotationMatrix());
  std::copy(p.data(), p.data() + 3, q);
  q[3] = quat.w(), q[4] = quat.x(), q[5] = quat.y(), q[6] = quat.z();
  // A free joint's velocity: the origin's linear velocity in the world frame, the angular
  // velocity in the body frame; u is the body twist [v; ω] (mm/s, rad/s).
  double* v = d_->qvel + b.dof;
  const Vec3 lin = X.rotationMatrix() * u.head<3>() * kMm;
  std::copy(lin.data(), lin.data() + 3, v);
  std::copy(u.data() + 3, u.data() + 6, v + 3);
}

Status World::step(double dt) noexcept {
  if (!(dt > 0) || !std::isfinite(dt)) return Status::invalid_time_step;
  const int n = std::max(1, int(std::lround(dt / m_->opt.timestep)));
  for (int k = 0; k < n; ++k) {
    // The arms are position-stiff: each driven body starts the step where its arm holds it,
    // moving at its twist, with gravity on it cancelled. After the step a sensor is exactly
    // where its twist takes it, X_ws · exp(u^ h); a carried fixture stays where it was put
    // (setFixturePose) and rests until moved again.
    for (const Driven& d : driven_) {
      mjtNum* xf = d_->xfrc_applied + 6 * d.body;
      std::fill(xf, xf + 6, 0.0);
      xf[2] = kArmMass * kGravity;
      writeState(d);
    }
    // The touching tip's weight is carried by the arm too: only the gel's springs act on it.
    for (const int b : sensor_tip_body_) {
      mjtNum* xf = d_->xfrc_applied + 6 * b;
      std::fill(xf, xf + 6, 0.0);
      xf[2] = kTipMass * kGravity;
    }
    mj_step(m_, d_);
    for (int s = 0; s < sensorCount(); ++s) {
      Driven& d = driven_[size_t(sensor_driven_[size_t(s)])];
      d.pose = d.pose * SE3d::exp(d.twist * m_->opt.timestep);
      d.pose.normalize();
    }
    for (int j = 0; j < fixtureCount(); ++j)
      if (fixture_driven_[size_t(j)] >= 0) driven_[size_t(fixture_driven_[size_t(j)])].twist.setZero();
    for (const Driven& d : driven_) writeState(d);
  }
  for (int i = 0; i < m_->nq; ++i)
    if (!std::isfinite(d_->qpos[i])) return Status::numerical_failure;
  mj_kinematics(m_, d_);  // geom poses at the new state, for tipGeometry
  return Status::ok;
}

SE3d World::objectPose(int i) const noexcept {
  const double* q = d_->qpos + object_qpos_[size_t(i)];
  const Eigen::Quaterniond quat(q[3], q[4], q[5], q[6]);
  return makePose(quat.normalized().toRotationMatrix(), Vec3(q[0], q[1], q[2]) / kMm);
}

double World::objectTilt(int i) const noexcept {
  const Vec3 z = objectPose(i).rotationMatrix().col(2);
  return std::acos(std::max(-1.0, std::min(1.0, z[2])));
}

void World::applyObjectForce(int i, const Vec3& force_w, const Vec3& point_w) noexcept {
  const int b = object_body_[size_t(i)];
  const Vec3 p = point_w * kMm;
  mjtNum* xf = d_->xfrc_applied + 6 * b;
  std::fill(xf, xf + 6, 0.0);
  // xfrc_applied is a force and a torque about the body's centre of mass (world frame).
  const Vec3 com(d_->xipos[3 * b], d_->xipos[3 * b + 1], d_->xipos[3 * b + 2]);
  const Vec3 torque = (p - com).cross(force_w);
  std::copy(force_w.data(), force_w.data() + 3, xf);
  std::copy(torque.data(), torque.data() + 3, xf + 3);
}

void World::applyObjectWrench(int i, const Vec3& force_w, const Vec3& torque_w) noexcept {
  mjtNum* xf = d_->xfrc_applied + 6 * object_body_[size_t(i)];
  std::copy(force_w.data(), force_w.data() + 3, xf);
  std::copy(torque_w.data(), torque_w.data() + 3, xf + 3);
}

void World::clearForces() noexcept { std::fill(d_->xfrc_applied, d_->xfrc_applied + 6 * m_->nbody, 0.0); }

SE3d World::fixturePose(int j) const noexcept {
  if (fixture_driven_[size_t(j)] >= 0) return driven_[size_t(fixture_driven_[size_t(j)])].pose;
  return spec_.fixtures[size_t(j)].pose;
}

Status World::setFixturePose(int j, const SE3d& X_wo) noexcept {
  if (j < 0 || j >= fixtureCount() || fixture_driven_[size_t(j)] < 0) return Status::invalid_argument;
  const Status v = validateElement(X_wo);
  if (v != Status::ok) return v;
  // There now, and moving during the next step with the body twist that took it there.
  Driven& d = driven_[size_t(fixture_driven_[size_t(j)])];
  d.twist = (d.pose.inverse() * X_wo).log() / m_->opt.timestep;
  d.pose = X_wo;
  writeState(d);
  mj_kinematics(m_, d_);
  return Status::ok;
}

std::vector<double> World::positions() const { return std::vector<double>(d_->qpos, d_->qpos + m_->nq); }

SE3d World::sensorPose(int s) const noexcept { return driven_[size_t(sensor_driven_[size_t(s)])].pose; }

Status World::setSensorPose(int s, const SE3d& X_ws) noexcept {
  const Status v = validateElement(X_ws);
  if (v != Status::ok) return v;
  Driven& d = driven_[size_t(sensor_driven_[size_t(s)])];
  d.pose = X_ws;
  d.twist.setZero();
  writeState(d);
  mj_kinematics(m_, d_);
  return Status::ok;
}

Status World::setSensorTwist(int s, const Vec6& twist_s) noexcept {
  if (!twist_s.allFinite()) return Status::non_finite_input;
  driven_[size_t(sensor_driven_[size_t(s)])].twist = twist_s;
  return Status::ok;
}

TipGeometry World::tipGeometry(int s, double range) const noexcept {
  TipGeometry best;
  const int tip = sensor_probe_[size_t(s)];  // the nominal tip: depth = the gel's deformation
  const Vec3 c(d_->geom_xpos[3 * tip], d_->geom_xpos[3 * tip + 1], d_->geom_xpos[3 * tip + 2]);
  const double R = m_->geom_size[3 * tip];
  double best_dist = range * kMm;
  auto consider = [&](int g, int object, int fixture) {
    // Bounding spheres first: most of a ramp's boxes are far from the tip.
    const Vec3 gc(d_->geom_xpos[3 * g], d_->geom_xpos[3 * g + 1], d_->geom_xpos[3 * g + 2]);
    if ((gc - c).norm() - m_->geom_rbound[g] - R > best_dist) return;
    // MuJoCo's collision table is filled for type(g1) ≤ type(g2); its normal points from g1
    // to g2, so it is the surface's outward normal when the object is g1.
    const bool object_first = m_->geom_type[g] <= m_->geom_type[tip];
    const int g1 = object_first ? g : tip, g2 = object_first ? tip : g;
    mjfCollision f = mjCOLLISIONFUNC[m_->geom_type[g1]][m_->geom_type[g2]];
    if (!f) return;
    mjContact con[mjMAXCONPAIR];
    const int n = f(m_, d_, con, g1, g2, best_dist);
    for (int k = 0; k < n; ++k) {
      if (con[k].dist >= best_dist) continue;
      best_dist = con[k].dist;
      Vec3 normal(con[k].frame[0], con[k].frame[1], con[k].frame[2]);
      if (!object_first) normal = -normal;
      // The surface point: from the tip centre c, back along the normal by the distance
      // R − depth (con.pos is not reliably midway for the general convex collider).
      best.valid = true;
      best.object = object;
      best.fixture = fixture;
      best.normal_w = normal;
      best.point_w = (c - (R + con[k].dist) * normal) / kMm;
      best.depth = -con[k].dist / kMm;
    }
  };
  for (int i = 0; i < objectCount(); ++i)
    for (int g = object_geoms_[size_t(i)].first; g < object_geoms_[size_t(i)].second; ++g) consider(g, i, -1);
  for (int j = 0; j < fixtureCount(); ++j)
    for (int g = fixture_geoms_[size_t(j)].first; g < fixture_geoms_[size_t(j)].second; ++g) consider(g, -1, j);
  return best;
}

double World::tipNormalForce(int s) const noexcept {
  const int tip = sensor_geom_[size_t(s)];
  double f = 0;
  for (int k = 0; k < d_->ncon; ++k) {
    if (d_->contact[k].geom1 != tip && d_->contact[k].geom2 != tip) continue;
    mjtNum r[6];
    mj_contactForce(m_, d_, k, r);
    f += r[0];
  }
  return f;
}

Vec3 World::tipContactForce(int s) const noexcept {
  const int tip = sensor_geom_[size_t(s)];
  Vec3 total = Vec3::Zero();
  for (int k = 0; k < d_->ncon; ++k) {
    const mjContact& c = d_->contact[k];
    if (c.geom1 != tip && c.geom2 != tip) continue;
    mjtNum r[6];
    mj_contactForce(m_, d_, k, r);  // in the contact frame, on geom2 from geom1
    Vec3 f = Vec3::Zero();
    for (int i = 0; i < 3; ++i) f += r[i] * Vec3(c.frame[3 * i], c.frame[3 * i + 1], c.frame[3 * i + 2]);
    total += c.geom1 == tip ? f : Vec3(-f);
  }
  return total;
}

Vec3 World::gelDeflection(int s) const noexcept {
  const double* q = d_->qpos + sensor_gel_qpos_[size_t(s)];
  return Vec3(q[0], q[1], q[2]) / kMm;
}

}  // namespace lieservo::sim::mujoco
