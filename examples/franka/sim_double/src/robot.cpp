// lieservo's libfranka test double: franka::Robot on franka_sim::Arm (see franka_sim/arm.h).
#include <franka/robot.h>
#include <franka_sim/arm.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <stdexcept>
#include <thread>

#include <Eigen/Core>

namespace franka_sim {

namespace {

std::mutex& registryMutex() {
  static std::mutex m;
  return m;
}
std::map<std::string, std::shared_ptr<Arm>>& registry() {
  static std::map<std::string, std::shared_ptr<Arm>> r;
  return r;
}

// libfranka's documented Cartesian limits of the end effector (translation, rotation), written
// out here rather than taken from the adapter's franka_frames.hpp: the double checks the
// adapter, so it must not share the adapter's constants.
constexpr double kMaxSpeed = 1.7, kMaxAccel = 13.0, kMaxJerk = 6500.0;
constexpr double kMaxAngularSpeed = 2.5, kMaxAngularAccel = 25.0, kMaxAngularJerk = 12500.0;
constexpr double kDt = 1e-3;

}  // namespace

void KinematicServo::step(const panda::Joints& dq_cmd, const Eigen::Vector3d&, const Eigen::Vector3d&,
                          panda::Joints& q, panda::Joints& dq) {
  q += kDt * dq_cmd;
  dq = dq_cmd;
}

std::shared_ptr<Arm> Arm::create(const std::string& address, const panda::Joints& q0,
                                 std::shared_ptr<JointServo> servo) {
  auto arm = std::make_shared<Arm>(q0, std::move(servo));
  std::lock_guard<std::mutex> g(registryMutex());
  registry()[address] = arm;
  return arm;
}

void Arm::remove(const std::string& address) {
  std::lock_guard<std::mutex> g(registryMutex());
  registry().erase(address);
}

std::shared_ptr<Arm> Arm::find(const std::string& address) {
  std::lock_guard<std::mutex> g(registryMutex());
  const auto it = registry().find(address);
  return it == registry().end() ? nullptr : it->second;
}

Arm::Arm(const panda::Joints& q0, std::shared_ptr<JointServo> servo)
    : q_(q0), servo_(servo ? std::move(servo) : std::make_shared<KinematicServo>()) {
  if (!q0.allFinite() || panda::jointLimitMargin(q0) < 0)
    throw std::invalid_argument("franka_sim::Arm: the start configuration is outside the joint limits");
}

void Arm::setLoad(const Eigen::Vector3d& f, const Eigen::Vector3d& p) {
  if (!f.allFinite() || !p.allFinite()) throw std::invalid_argument("franka_sim::Arm::setLoad: non-finite force or point");
  std::lock_guard<std::mutex> g(mutex_);
  load_f_ = f;
  load_p_ = p;
}

void Arm::injectReflex(const std::string& what) {
  std::lock_guard<std::mutex> g(mutex_);
  reflex_ = what.empty() ? "injected reflex" : what;
}

void Arm::setLockstep(bool on) {
  std::lock_guard<std::mutex> g(mutex_);
  lockstep_ = on;
  permits_ = 0;
  cycle_cv_.notify_all();
}

int Arm::advance(int n) {
  std::unique_lock<std::mutex> lock(mutex_);
  if (!lockstep_ || !in_control_ || n <= 0) return 0;
  ran_ = 0;
  permits_ = n;
  cycle_cv_.notify_all();
  cycle_cv_.wait(lock, [&] { return permits_ == 0 || !in_control_; });
  permits_ = 0;
  return ran_;
}

bool Arm::inControl() const {
  std::lock_guard<std::mutex> g(mutex_);
  return in_control_;
}

panda::Joints Arm::joints() const {
  std::lock_guard<std::mutex> g(mutex_);
  return q_;
}

panda::Joints Arm::jointVelocities() const {
  std::lock_guard<std::mutex> g(mutex_);
  return dq_;
}

bool Arm::faulted() const {
  std::lock_guard<std::mutex> g(mutex_);
  return faulted_;
}

ArmReport Arm::report() const {
  std::lock_guard<std::mutex> g(mutex_);
  return report_;
}

franka::RobotState Arm::stateLocked() const {
  franka::RobotState s;
  const Eigen::Matrix4d T = panda::flange(q_);
  Eigen::Map<Eigen::Matrix4d>(s.O_T_EE.data()) = T;  // column-major, as libfranka's
  for (int i = 0; i < panda::kJoints; ++i) {
    s.q[std::size_t(i)] = q_[i];
    s.dq[std::size_t(i)] = dq_[i];
  }
  s.time = franka::Duration(time_ms_);
  return s;
}

franka::RobotState Arm::readOnce() const {
  std::lock_guard<std::mutex> g(mutex_);
  return stateLocked();
}

void Arm::fail(const std::string& what) {
  faulted_ = true;
  servo_->brake(q_, dq_);
  ++report_.errors;
  report_.last_error = what;
  throw franka::ControlException("libfranka: Move command aborted: motion aborted by reflex! [\"" + what + "\"]");
}

void Arm::recover() {
  std::lock_guard<std::mutex> g(mutex_);
  faulted_ = false;
  reflex_.clear();
}

void Arm::checkMotionLimits(const Twist& v, Twist& v_prev, Twist& a_prev) {
  // The motion generator's limits, on differences over one 1 ms cycle (the first command
  // continues from rest, so a jump from zero is a discontinuity).
  const Twist a = (v - v_prev) / kDt, j = (a - a_prev) / kDt;
  const double s = v.head<3>().norm(), w = v.tail<3>().norm();
  const double acc = a.head<3>().norm(), aacc = a.tail<3>().norm();
  const double jerk = j.head<3>().norm(), ajerk = j.tail<3>().norm();
  report_.max_speed = std::max(report_.max_speed, s);
  report_.max_angular_speed = std::max(report_.max_angular_speed, w);
  report_.max_accel = std::max(report_.max_accel, acc);
  report_.max_angular_accel = std::max(report_.max_angular_accel, aacc);
  report_.max_jerk = std::max(report_.max_jerk, jerk);
  report_.max_angular_jerk = std::max(report_.max_angular_jerk, ajerk);
  if (s > kMaxSpeed || w > kMaxAngularSpeed) fail("cartesian_motion_generator_velocity_limits_violation");
  // libfranka's names: a velocity step too large for the acceleration limit is a velocity
  // discontinuity, an acceleration step too large for the jerk limit an acceleration one.
  if (acc > kMaxAccel || aacc > kMaxAngularAccel) fail("cartesian_motion_generator_velocity_discontinuity");
  if (jerk > kMaxJerk || ajerk > kMaxAngularJerk) fail("cartesian_motion_generator_acceleration_discontinuity");
  v_prev = v;
  a_prev = a;
}

void Arm::stepJoints(const Twist& v) {
  // Resolved rate, then one 1 ms step of the joints.
  const panda::ResolvedRate r = panda::resolvedRate(q_, v);
  // The robot follows the twist exactly (no damping): where that needs a joint faster than its
  // limit, near a singularity or where the twist leaves the workspace, it stops on a reflex.
  if (r.scale < 1.0 || r.exact_speed_ratio > 1.0) fail("cartesian_motion_generator_joint_velocity_limits_violation");
  const panda::Jacobian J = panda::jacobian(q_);
  const double twist_error = (J * r.dq - v).norm();
  if (r.lambda > 0) ++report_.damped_cycles;
  else report_.max_twist_error = std::max(report_.max_twist_error, twist_error);
  report_.min_manipulability = std::min(report_.min_manipulability, panda::manipulability(J));
  // libfranka judges the commanded motion, and a real joint past its limit stops it too.
  if (panda::jointLimitMargin(q_ + kDt * r.dq) < 0) fail("cartesian_motion_generator_joint_position_limits_violation");
  servo_->step(r.dq, load_f_, load_p_, q_, dq_);
  if (panda::jointLimitMargin(q_) < 0) fail("cartesian_motion_generator_joint_position_limits_violation");
  report_.max_achieved_error = std::max(report_.max_achieved_error, ((J * dq_).head<3>() - v.head<3>()).norm());
}

void Arm::control(const std::function<franka::CartesianVelocities(const franka::RobotState&, franka::Duration)>& cb) {
  {
    std::lock_guard<std::mutex> g(mutex_);
    if (faulted_)
      throw franka::CommandException("libfranka: Move command rejected: the robot is in reflex mode (automaticErrorRecovery)");
  }
  struct InControl {  // in_control_ for advance(), cleared however control() ends
    Arm& a;
    explicit InControl(Arm& arm) : a(arm) {
      std::lock_guard<std::mutex> g(a.mutex_);
      a.in_control_ = true;
    }
    ~InControl() {
      std::lock_guard<std::mutex> g(a.mutex_);
      a.in_control_ = false;
      a.cycle_cv_.notify_all();
    }
  } in_control(*this);
  using Clock = std::chrono::steady_clock;
  Twist v_prev = Twist::Zero(), a_prev = v_prev;
  auto next = Clock::now();
  for (std::uint64_t k = 0;; ++k) {
    franka::RobotState state;
    bool paced;  // at 1 kHz of wall-clock time, unless the cycles are released by advance()
    {
      std::unique_lock<std::mutex> g(mutex_);
      cycle_cv_.wait(g, [&] { return !lockstep_ || permits_ > 0; });
      state = stateLocked();
      paced = !lockstep_;
    }
    const franka::CartesianVelocities c = cb(state, franka::Duration(k == 0 ? 0 : 1));
    const Twist v = Eigen::Map<const Twist>(c.O_dP_EE.data());
    if (!v.allFinite()) throw std::invalid_argument("libfranka: Invalid command: commanded values must be finite");

    std::unique_lock<std::mutex> lock(mutex_);
    ++report_.cycles;
    if (!reflex_.empty()) {
      const std::string what = reflex_;
      reflex_.clear();
      fail(what);
    }
    checkMotionLimits(v, v_prev, a_prev);
    stepJoints(v);
    time_ms_ += 1;
    report_.min_joint_margin = std::min(report_.min_joint_margin, panda::jointLimitMargin(q_));
    if (lockstep_ && permits_ > 0) {
      --permits_;
      ++ran_;
      cycle_cv_.notify_all();
    }
    if (c.motion_finished) {
      servo_->brake(q_, dq_);
      ++report_.motions;
      return;
    }
    lock.unlock();
    if (!paced) continue;
    next += std::chrono::milliseconds(1);
    const auto now = Clock::now();
    if (now > next + std::chrono::milliseconds(20)) next = now;  // far behind (a loaded machine): no burst
    std::this_thread::sleep_until(next);
  }
}

}  // namespace franka_sim

namespace franka {

Robot::Robot(const std::string& franka_address, RealtimeConfig, size_t) : arm_(franka_sim::Arm::find(franka_address)) {
  if (!arm_) throw NetworkException("libfranka: Connection error: no simulated arm at " + franka_address);
}

Robot::~Robot() noexcept = default;

void Robot::control(std::function<CartesianVelocities(const RobotState&, franka::Duration)> motion_generator_callback,
                    ControllerMode, bool, double cutoff_frequency) {
  if (!(cutoff_frequency > 0) || cutoff_frequency > kMaxCutoffFrequency)
    throw std::invalid_argument("libfranka: cutoff_frequency out of range");
  arm_->control(motion_generator_callback);
}

RobotState Robot::readOnce() { return arm_->readOnce(); }

void Robot::setCollisionBehavior(const std::array<double, 7>&, const std::array<double, 7>&,
                                 const std::array<double, 6>&, const std::array<double, 6>&) {}

void Robot::automaticErrorRecovery() { arm_->recover(); }

}  // namespace franka
