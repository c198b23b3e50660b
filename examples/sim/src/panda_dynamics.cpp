// lieservo_sim/panda_dynamics.cpp — see panda_dynamics.hpp.
#include <lieservo_sim/panda_dynamics.hpp>

#include <cmath>
#include <sstream>
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

/// Where frame i + 1's origin lies in frame i.
Eigen::Vector3d childOrigin(const Link& l) { return linkTransform(l, 0.0).topRightCorner<3, 1>(); }

}  // namespace

std::string pandaMjcf(const JointServoGains& g) {
  std::ostringstream x;
  x.precision(17);  // MuJoCo's flange must equal the chain's to rounding (test_panda_dynamics)
  x << "<mujoco model=\"panda\">\n"
    << "  <compiler angle=\"radian\"/>\n"
    << "  <!-- 1 kHz; the robot compensates gravity itself; the links touch nothing -->\n"
    << "  <option timestep=\"" << PandaDynamics::kStep << "\" gravity=\"0 0 0\" integrator=\"implicit\"/>\n"
    << "  <default><geom contype=\"0\" conaffinity=\"0\"/></default>\n"
    << "  <worldbody>\n";
  for (int i = 0; i < kJoints; ++i) {
    const Link& l = kLinks[std::size_t(i)];
    const Eigen::Vector3d p = childOrigin(l), c = childOrigin(kLinks[std::size_t(i + 1)]);
    const std::string in(std::size_t(4 + 2 * i), ' ');
    x << in << "<body name=\"link" << i + 1 << "\" pos=\"" << p.x() << ' ' << p.y() << ' ' << p.z() << "\" quat=\""
      << std::cos(l.alpha / 2) << ' ' << std::sin(l.alpha / 2) << " 0 0\">\n"
      << in << "  <joint name=\"joint" << i + 1 << "\" type=\"hinge\" axis=\"0 0 1\" limited=\"true\" range=\""
      << lowerLimits()[i] << ' ' << upperLimits()[i] << "\" armature=\"" << kArmature[i] << "\"/>\n";
    // The link: a capsule from this joint's origin to the next one's (a ball where they meet).
    const double r = i < 4 ? 0.06 : 0.05;
    if (c.norm() > 1e-9)
      x << in << "  <geom type=\"capsule\" fromto=\"0 0 0 " << c.x() << ' ' << c.y() << ' ' << c.z() << "\" size=\""
        << r << "\" mass=\"" << kLinkMass[i] << "\"/>\n";
    else
      x << in << "  <geom type=\"sphere\" size=\"" << r << "\" mass=\"" << kLinkMass[i] << "\"/>\n";
  }
  // The flange in link 7, with the sensor and its mount.
  const Eigen::Vector3d f = childOrigin(kLinks[kJoints]);
  const std::string in(std::size_t(4 + 2 * kJoints), ' ');
  x << in << "<body name=\"flange\" pos=\"" << f.x() << ' ' << f.y() << ' ' << f.z() << "\">\n"
    << in << "  <geom type=\"capsule\" fromto=\"0 0 0 0 0 0.08\" size=\"0.025\" mass=\"" << kToolMass << "\"/>\n"
    << in << "</body>\n";
  for (int i = kJoints - 1; i >= 0; --i) x << std::string(std::size_t(4 + 2 * i), ' ') << "</body>\n";
  x << "  </worldbody>\n  <actuator>\n";
  // τ = kp (ctrl − q) − kd q̇ with ctrl = q_d + (kd / kp) q̇_d: the PD law with velocity
  // feedforward as one actuator, so that the torque limit bounds the sum.
  for (int i = 0; i < kJoints; ++i)
    x << "    <general name=\"servo" << i + 1 << "\" joint=\"joint" << i + 1
      << "\" gaintype=\"fixed\" biastype=\"affine\" gainprm=\"" << g.kp[i] << "\" biasprm=\"0 " << -g.kp[i] << ' '
      << -g.kd[i] << "\" forcelimited=\"true\" forcerange=\"" << -torqueLimits()[i] << ' ' << torqueLimits()[i]
      << "\"/>\n";
  x << "  </actuator>\n</mujoco>\n";
  return x.str();
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
