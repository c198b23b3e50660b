// lieservo_sim/panda_dynamics.cpp — see panda_dynamics.hpp.
#include <lieservo_sim/panda_dynamics.hpp>

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include <mujoco/mujoco.h>

#include <lieservo_sim/mujoco_world.hpp>

namespace lieservo::sim::panda {

namespace {

/// Gaz et al.'s identified link masses (kg), links 1–7, and the sensor with its mount on the
/// flange.
constexpr double kLinkMass[kJoints] = {4.970684, 0.646926, 3.228604, 3.587895, 1.225946, 1.666555, 0.735522};
constexpr double kToolMass = 0.5;
/// The rotors' inertia reflected through the gears (kg·m²), an assumed plausible value.
constexpr double kArmature[kJoints] = {0.1, 0.1, 0.1, 0.1, 0.05, 0.05, 0.05};

std::string fmt(const char* format, double a, double b = 0, double c = 0, double d = 0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, format, a, b, c, d);
  return buf;
}

/// Where frame i + 1's origin lies in frame i (Craig's step without the joint angle).
Eigen::Vector3d childOrigin(const Link& l) { return {l.a, -std::sin(l.alpha) * l.d, std::cos(l.alpha) * l.d}; }

}  // namespace

std::string pandaMjcf(const JointServoGains& g) {
  std::string x =
      "<mujoco model=\"panda\">\n"
      "  <compiler angle=\"radian\"/>\n"
      "  <!-- 1 kHz; the robot compensates gravity itself; the links touch nothing -->\n"
      "  <option timestep=\"0.001\" gravity=\"0 0 0\" integrator=\"implicit\"/>\n"
      "  <default><geom contype=\"0\" conaffinity=\"0\"/></default>\n"
      "  <worldbody>\n";
  std::string close;
  for (int i = 0; i <= kJoints; ++i) {
    const Link& l = kLinks[std::size_t(i)];
    const Eigen::Vector3d p = childOrigin(l);
    const std::string indent(std::size_t(4 + 2 * i), ' ');
    if (i == kJoints) {  // the flange, with the sensor and its mount
      x += indent + "<body name=\"flange\"" + fmt(" pos=\"%.17g %.17g %.17g\">\n", p.x(), p.y(), p.z());
      x += indent + fmt("  <geom type=\"capsule\" fromto=\"0 0 0 0 0 0.08\" size=\"0.025\" mass=\"%.17g\"/>\n", kToolMass);
      x += indent + "</body>\n";
      break;
    }
    x += indent + "<body name=\"link" + std::to_string(i + 1) + "\"" +
         fmt(" pos=\"%.17g %.17g %.17g\" quat=\"%.17g", p.x(), p.y(), p.z(), std::cos(l.alpha / 2)) +
         fmt(" %.17g 0 0\">\n", std::sin(l.alpha / 2));
    x += indent + "  <joint name=\"joint" + std::to_string(i + 1) + "\" type=\"hinge\" axis=\"0 0 1\" limited=\"true\"" +
         fmt(" range=\"%.17g %.17g\" armature=\"%.17g\"/>\n", lowerLimits()[i], upperLimits()[i], kArmature[i]);
    // The link: a capsule from this joint's origin to the next one's (a ball where they meet).
    const Eigen::Vector3d c = childOrigin(kLinks[std::size_t(i + 1)]);
    const double r = i < 4 ? 0.06 : 0.05;
    if (c.norm() > 1e-9)
      x += indent + fmt("  <geom type=\"capsule\" fromto=\"0 0 0 %.17g %.17g %.17g\"", c.x(), c.y(), c.z()) +
           fmt(" size=\"%.17g\" mass=\"%.17g\"/>\n", r, kLinkMass[i]);
    else
      x += indent + fmt("  <geom type=\"sphere\" size=\"%.17g\" mass=\"%.17g\"/>\n", r, kLinkMass[i]);
    close = indent + "</body>\n" + close;
  }
  x += close + "  </worldbody>\n  <actuator>\n";
  // τ = kp (ctrl − q) − kd q̇ with ctrl = q_d + (kd / kp) q̇_d: the PD law with velocity
  // feedforward as one actuator, so that the torque limit bounds the sum.
  for (int i = 0; i < kJoints; ++i)
    x += "    <general name=\"servo" + std::to_string(i + 1) + "\" joint=\"joint" + std::to_string(i + 1) +
         "\" gaintype=\"fixed\" biastype=\"affine\"" + fmt(" gainprm=\"%.17g\" biasprm=\"0 %.17g %.17g\"", g.kp[i], -g.kp[i], -g.kd[i]) +
         fmt(" forcelimited=\"true\" forcerange=\"%.17g %.17g\"/>\n", -torqueLimits()[i], torqueLimits()[i]);
  return x + "  </actuator>\n</mujoco>\n";
}

PandaDynamics::PandaDynamics(const Joints& q0, const JointServoGains& gains) : gains_(gains), q_d_(q0) {
  if (!q0.allFinite() || jointLimitMargin(q0) < 0)
    throw std::invalid_argument("PandaDynamics: the start configuration is outside the joint limits");
  if (!gains.kp.allFinite() || !gains.kd.allFinite() || (gains.kp.array() <= 0).any() || (gains.kd.array() < 0).any())
    throw std::invalid_argument("PandaDynamics: the gains must be finite, kp > 0 and kd >= 0");
  try {
    m_ = mujoco::loadMjcf(pandaMjcf(gains));
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string("PandaDynamics: ") + e.what());
  }
  d_ = mj_makeData(m_);
  if (!d_) {
    mj_deleteModel(m_);
    throw std::runtime_error("PandaDynamics: out of memory for MuJoCo's data");
  }
  flange_body_ = mj_name2id(m_, mjOBJ_BODY, "flange");
  for (int i = 0; i < kJoints; ++i) d_->qpos[i] = q0[i];
  brake();
}

PandaDynamics::~PandaDynamics() {
  mj_deleteData(d_);
  mj_deleteModel(m_);
}

void PandaDynamics::applyLoad() {
  // xfrc_applied is a force and a torque about the body's centre of mass (world frame).
  mjtNum* xf = d_->xfrc_applied + 6 * flange_body_;
  const Eigen::Map<const Eigen::Vector3d> com(d_->xipos + 3 * flange_body_);
  const Eigen::Vector3d torque = (load_p_ - com).cross(load_f_);
  for (int k = 0; k < 3; ++k) {
    xf[k] = load_f_[k];
    xf[3 + k] = torque[k];
  }
}

void PandaDynamics::step(const Joints& dq_d) {
  q_d_ += kStep * dq_d;
  for (int i = 0; i < kJoints; ++i) d_->ctrl[i] = q_d_[i] + gains_.kd[i] / gains_.kp[i] * dq_d[i];
  applyLoad();
  mj_step(m_, d_);
  // mj_step leaves the positions it derived from the state before the step: bring them to now.
  mj_kinematics(m_, d_);
  mj_comPos(m_, d_);
}

void PandaDynamics::brake() {
  for (int i = 0; i < kJoints; ++i) {
    d_->qvel[i] = 0;
    d_->qacc_warmstart[i] = 0;
    q_d_[i] = d_->qpos[i];
    d_->ctrl[i] = q_d_[i];
  }
  mj_forward(m_, d_);
}

void PandaDynamics::setLoad(const Eigen::Vector3d& f, const Eigen::Vector3d& p) {
  if (!f.allFinite() || !p.allFinite()) throw std::invalid_argument("PandaDynamics::setLoad: non-finite force or point");
  load_f_ = f;
  load_p_ = p;
}

Joints PandaDynamics::q() const { return Eigen::Map<const Joints>(d_->qpos); }
Joints PandaDynamics::dq() const { return Eigen::Map<const Joints>(d_->qvel); }
Joints PandaDynamics::trackingError() const { return q_d_ - q(); }
Joints PandaDynamics::torques() const { return Eigen::Map<const Joints>(d_->actuator_force); }

Eigen::Matrix4d PandaDynamics::flangePose() const {
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  T.topLeftCorner<3, 3>() = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(d_->xmat + 9 * flange_body_);
  T.topRightCorner<3, 1>() = Eigen::Map<const Eigen::Vector3d>(d_->xpos + 3 * flange_body_);
  return T;
}

}  // namespace lieservo::sim::panda
