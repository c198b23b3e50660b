// lieservo_sim/mujoco_world.cpp — the MuJoCo model and data of a scene (its MJCF: scene_mjcf.cpp),
// stepped with the arms driving the sensors, and the tips' geometry.
#include "lieservo_sim/mujoco_world.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <mutex>
#include <set>
#include <sstream>

#include <mujoco/mujoco.h>

#include <lieservo/groups/perturbation.hpp>

#include "mujoco_model.hpp"

namespace lieservo::sim::mujoco {

using namespace model;

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
