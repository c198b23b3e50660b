// libFuzzer target: the real-time layer (CartesianVelocityPipeline with its CommandWatchdog and
// VelocitySmoother) driven by arbitrary configure/step/stepStopping/rearm/resync sequences:
// arbitrary poses, twists, stamps and clocks (int64 extremes and stamps from the future
// included), arbitrary limits. Properties (abort on violation):
//   * no crash, no UB (ASan+UBSan): the command's age never overflows;
//   * Status::ok ⇒ the output is finite and inside the smoother's velocity limits;
//   * any other Status ⇒ the output array and the smoother's velocity are unchanged;
//   * a command older than the timeout, or stamped further ahead, never moves the robot
//     away from what the smoother was already doing: the watchdog does not pass it.
#include <lieservo/realtime/velocity_pipeline.hpp>

#include <array>
#include <cstring>

#include "fuzz_common.hpp"

using namespace lieservo;
using namespace lieservo::realtime;
using lieservo::fuzz::Bytes;

namespace {

using Matrix4 = Eigen::Matrix<double, 4, 4>;
using Vector6 = Eigen::Matrix<double, 6, 1>;

std::int64_t anyTime(Bytes& b) {
  switch (b.u8() % 4) {
    case 0: return std::numeric_limits<std::int64_t>::max() - std::int64_t(b.u8());
    case 1: return std::numeric_limits<std::int64_t>::min() + std::int64_t(b.u8());
    case 2: {
      std::int64_t t = 0;
      for (int i = 0; i < 8; ++i) t = std::int64_t(std::uint64_t(t) << 8 | b.u8());
      return t;
    }
    default: return std::int64_t(b.i16()) * 1000000;  // ms around 0
  }
}

Matrix4 pose(Bytes& b) {
  if (b.u8() & 1) return SE3<double>::exp(b.vector<SE3<double>::Tangent>()).matrix();
  return b.vector<Matrix4>();
}

bool withinVelocity(const std::array<double, 6>& v, const SmootherLimits<double>& L) {
  const Eigen::Map<const Eigen::Vector3d> lin(v.data()), ang(v.data() + 3);
  const double slack = 1 + 1e-9;
  return lin.norm() <= L.translation.velocity * slack && ang.norm() <= L.rotation.velocity * slack;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Bytes b(data, size);
  CartesianVelocityPipeline p;
  std::array<double, 6> out{};
  for (int op = 0; op < 256 && !b.empty(); ++op) {
    const std::array<double, 6> out_before = out;
    const Vector6 v_before = p.smoother().velocity();
    Status s = Status::ok;
    switch (b.u8() % 6) {
      case 0: {
        PipelineOptions o;
        if (b.u8() & 1) o.limits.translation = {b.value(), b.value(), b.value()};
        if (b.u8() & 1) o.watchdog.command_timeout_s = b.value();
        if (b.u8() & 1) o.twist_to_metres = b.value();
        if (b.u8() & 1) o.control_period_s = b.value();
        (void)p.configure(o);
        continue;
      }
      case 1:
      case 2: {
        TwistCommand cmd;
        for (double& x : cmd.twist_s) x = b.value();
        cmd.in_contact = b.u8() & 1;
        ChannelStamp stamp;
        stamp.sequence = b.u8();
        stamp.time_ns = anyTime(b);
        // Now: near the stamp (wrapping at the int64 ends, as a clock would not) or anywhere.
        const std::int64_t near =
            std::int64_t(std::uint64_t(stamp.time_ns) + std::uint64_t(std::int64_t(b.i16()) * 1000));
        const std::int64_t now = (b.u8() & 1) ? near : anyTime(b);
        // As an adapter: the one parse of the robot's pose, then the cycle (a refused pose
        // leaves the pipeline as it was: the adapter then calls stepStopping).
        SE3<double> T_OE;
        s = poseFromHomogeneous(pose(b), T_OE);
        if (s == Status::ok) s = p.step(T_OE, cmd, stamp, now, out);
        if (s == Status::ok && stamp.sequence != 0) {
          const double age = 1e-9 * std::abs(double(now) - double(stamp.time_ns));
          if (age > p.options().watchdog.command_timeout_s) LIESERVO_FUZZ_REQUIRE(!p.watchdog().passCommands());
        }
        break;
      }
      case 3: s = p.stepStopping(out); break;
      case 4: p.rearm(); continue;
      default: {
        const Vector6 v = b.vector<Vector6>(), a = b.vector<Vector6>();
        s = p.resync(v, a);
        if (s != Status::ok) LIESERVO_FUZZ_REQUIRE(p.smoother().velocity() == v_before);
        continue;
      }
    }
    if (s == Status::ok) {
      for (double x : out) LIESERVO_FUZZ_REQUIRE(std::isfinite(x));
      LIESERVO_FUZZ_REQUIRE(withinVelocity(out, p.options().limits));
    } else {
      LIESERVO_FUZZ_REQUIRE(std::memcmp(out.data(), out_before.data(), sizeof out) == 0);
      LIESERVO_FUZZ_REQUIRE(p.smoother().velocity() == v_before);
    }
  }
  return 0;
}
