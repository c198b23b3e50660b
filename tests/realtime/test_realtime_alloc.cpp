// Zero heap allocations per real-time step, counted with tests/support/allocation_counter.hpp
// (in every build, the sanitizer builds included).
#include <catch2/catch.hpp>

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
  po.mount.p_es = Vector3(0, 0, 0.12);
  REQUIRE(pipe.configure(po) == Status::ok);
  const Matrix4 T_OE = Matrix4::Identity();
  std::array<double, 6> out{};
  Eigen::Matrix<double, 6, 1> target;
  target << 0.3, -0.2, 0.1, 1.0, -0.5, 0.2;
  Vector6 base;
  TwistCommand cmd;
  cmd.twist_s = {5, 0, 2, 0.1, 0, 0};
  cmd.in_contact = true;
  ChannelStamp stamp;

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
      (void)sensorTwistToBaseChecked(T_OE, po.mount, target, 1e-3, base);
      (void)pipe.step(T_OE, *channel, steadyNowNs(), out);
      if (k == 2500) pipe.requestStop();
      (void)pipe.stepStopping(out);
      (void)smoother.stoppingTimeBound(1e-3);
    }
    n = c.count();
  }
  CHECK(n == 0);
}
