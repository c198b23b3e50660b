// Compile-time unit 2 (benchmarks/compile_time.py): the pushing controller in its single-arm
// loop, and the dual-arm and centralised dual-arm pushers, each stepped once on SE(3) double.
#include <lieservo/lieservo.hpp>

namespace ls = lieservo;
using SE3d = ls::SE3<double>;

int main() {
  ls::ConcentratedGaussian<SE3d> obs;
  obs.covariance = SE3d::Jacobian::Identity();
  const double dt = 0.05;
  SE3d::Tangent u;
  ls::TactileLoop<ls::PushingController<SE3d>> single;
  int failures = single.step(SE3d(), obs, dt, u) != ls::Status::ok;

  ls::DualArmPushing<SE3d> dual;
  ls::DualArmPushing<SE3d>::ArmInput in;
  in.observation = obs;
  ls::DualArmPushing<SE3d>::ArmOutput lo, fo;
  failures += dual.step(in, in, dt, lo, fo) != ls::Status::ok;

  ls::CentralisedDualArmPushing<SE3d> central;
  ls::CentralisedDualArmPushing<SE3d>::ArmOutput clo, cfo;
  failures += central.step(in, in, dt, clo, cfo) != ls::Status::ok;
  return failures;
}
