// Zero heap allocations per real-time step, counted with tests/support/allocation_counter.hpp
// (in every build, the sanitizer builds included).
#include <catch2/catch.hpp>

#include <cmath>

#include <lieservo/realtime.hpp>

#include "allocation_counter.hpp"

#include <memory>
#include <new>

using Counting = lieservo::test::AllocationCounter;

using namespace lieservo::realtime;
using lieservo::Status;

TEST_CASE("alloc: the counter sees allocations (self-check)", "[realtime][alloc]") {
  long n = 0;
  {
    Counting c;
    void* volatile p = ::operator new(16);  // an explicit call: a new-expression may be elided
    n = c.count();
    ::operator delete(p);
  }
  CHECK(n == 1);
}

TEST_CASE("alloc: smoother, watchdog, latest-value hand-over, frames and pipeline steps allocate nothing", "[realtime][alloc]") {
  // Everything constructed before counting starts.
  VelocitySmoother<double> smoother;
  CommandWatchdog watchdog;
  REQUIRE(watchdog.configure(WatchdogOptions{}) == Status::ok);
  auto channel = std::make_unique<LatestValueChannel<TwistCommand>>();
  CartesianVelocityPipeline pipe;
  PipelineOptions po;
  po.mount.X_es = lieservo::SE3<double>(lieservo::SO3<double>(), Vector3(0, 0, 0.12));
  REQUIRE(pipe.configure(po) == Status::ok);
  const lieservo::SE3<double> T_OE;
  std::array<double, 6> out{};
  Eigen::Matrix<double, 6, 1> target;
  target << 0.3, -0.2, 0.1, 1.0, -0.5, 0.2;
  Vector6 base;
  TwistCommand cmd;
  cmd.twist_s = {5, 0, 2, 0.1, 0, 0};
  cmd.in_contact = true;
  ChannelStamp stamp;
  double sink = 0;  // keeps the sensor poses computed

  long n = -1;
  {
    Counting c;
    for (int k = 0; k < 3000; ++k) {
      const double sgn = (k / 500) % 2 ? -1.0 : 1.0;
      (void)smoother.step(sgn * target, 1e-3);
      (void)smoother.step(target, 0.0);  // error path too
      (void)watchdog.step(static_cast<std::uint64_t>(k / 30 + 1), 0.01, true);
      channel->write(cmd);
      TwistCommand got;
      (void)channel->read(got, stamp);
      lieservo::SE3<double> parsed;
      (void)poseFromHomogeneous(Matrix4::Identity(), parsed);
      base = sensorTwistToBase(parsed, po.mount, target, 1e-3);
      sink += sensorPose(parsed, po.mount, 1e3).translation().x();
      (void)pipe.step(T_OE, *channel, steadyNowNs(), out);
      if (k == 2500) pipe.requestStop();
      (void)pipe.stepStopping(out);
      (void)smoother.stoppingTimeBound(1e-3);
    }
    n = c.count();
  }
  CHECK(n == 0);
  CHECK(std::isfinite(sink));
}
