// examples/collection/kinematic_arm.hpp — a minimal kinematic stand-in arm for CI.
//
// moveTo sets the pose exactly, readPose returns it, commandVelocity integrates the body
// twist (X ← X·exp(ξ dt)). No dynamics, no limits. Optionally records every moveTo target so
// tests can check the collection motion sequence (Algorithm 1, alg:data_collection).
#pragma once

#include <robot/robot_interface.hpp>

#include <lieservo/groups/se3.hpp>
#include <lieservo/status.hpp>

#include <cmath>
#include <vector>

namespace lieservo::collection {

class KinematicArm final : public robot::RobotInterface {
 public:
  using SE3d = robot::SE3d;

  explicit KinematicArm(const SE3d& initial = SE3d(), bool record_moves = false)
      : pose_(initial), record_(record_moves) {}

  Status readPose(SE3d& X_ws) override {
    X_ws = pose_;
    return Status::ok;
  }
  Status commandVelocity(const robot::Twist& twist_s, double dt) override {
    if (!(dt > 0) || !std::isfinite(dt)) return Status::invalid_time_step;
    if (!twist_s.allFinite()) return Status::non_finite_input;
    pose_ = pose_ * SE3d::exp(twist_s * dt);
    return Status::ok;
  }
  Status moveTo(const SE3d& X_ws) override {
    if (!X_ws.allFinite()) return Status::non_finite_input;
    pose_ = X_ws;
    if (record_) moves_.push_back(X_ws);
    return Status::ok;
  }
  void stop() override {}

  const std::vector<SE3d>& moves() const { return moves_; }
  void clearMoves() { moves_.clear(); }

 private:
  SE3d pose_;
  bool record_;
  std::vector<SE3d> moves_;
};

}  // namespace lieservo::collection
