// examples/franka/franka_servo_example.cpp — pose-and-shear tactile servoing on a real Franka
// arm with a TacTip: surface following (paper Section 5.5 (sec:surface_follow_exp)) or single-arm pushing
// (Section 5.6, sec:single_arm_object_pushing_exp). See docs/hardware.md before running it.
//
//   franka_servo_example --robot 172.16.0.2 --task follow --camera 0
//       --model-card examples/gdn/models/train_val/model_card.json --preprocess processed_image_params.json
//       --mount 0,0,120,0,0,0 --start 450,0,150,180,0,0 --heading 90 --duration 30
//   (one command line)
//
// Threads: this program's TACTILE thread runs at camera rate (capture → pre-processing →
// GDN → SE(3) Bayes filter → controller → FrankaAdapter::commandVelocity); the adapter's
// 1 kHz thread (libfranka) smooths and sends the commands. The main thread waits, prints
// status once a second and handles Ctrl-C (ramped stop). The hardware emergency stop /
// enabling device is the real safety layer; this program is not a safety system.
//
// The tactile front end sits behind one seam, `TactileFrontEnd`: replace
// `OpenCvGdnFrontEnd` to use a different sensor or model.
#include "franka_adapter.hpp"
#include "franka_example_options.hpp"
#include "tactile_run.hpp"

#include <lieservo/control/presets.hpp>
#include <lieservo/control/tactile_loop.hpp>
#include <lieservo/units.hpp>

#include <lieservo_adapters/camera.hpp>
#include <lieservo_adapters/gdn_observation.hpp>
#include <lieservo_adapters/onnx_pose_model.hpp>
#include <lieservo_adapters/preprocessing.hpp>

#include <opencv2/core.hpp>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace {

using lieservo::Status;
using lieservo::franka_example::TactileFrontEnd;
using lieservo::franka_example::TactileSample;
using lieservo::franka_adapter::FrankaAdapter;
using lieservo::franka_adapter::FrankaAdapterOptions;
using SE3d = lieservo::SE3<double>;
using Twist = SE3d::Tangent;

std::atomic<bool> g_interrupted{false};
extern "C" void onSignal(int) { g_interrupted.store(true); }

// ---- Command line: franka_example_options.hpp ---------------------------------------
using Args = lieservo::franka_example::Options;

SE3d poseFromMmDeg(const std::vector<double>& v) {
  Eigen::Matrix<double, 6, 1> x;
  for (int i = 0; i < 6; ++i) x[i] = v[static_cast<std::size_t>(i)];
  return SE3d::fromEulerXYZ6Degrees(x);
}

// ---- The tactile seam (tactile_run.hpp): the OpenCV + ONNX GDN front end ---------------
/// TacTip camera → pre-processing → ONNX GDN (examples/adapters) → SE(3) observation; contact
/// by the mean absolute difference of the processed image from a no-contact reference frame
/// (with hysteresis: on above T, off below T/2).
class OpenCvGdnFrontEnd final : public TactileFrontEnd {
 public:
  OpenCvGdnFrontEnd(const Args& a)
      : camera_(a.camera,
                lieservo::adapters::Preprocessor(a.preprocess.empty()
                                                     ? lieservo::adapters::PreprocessParams{}
                                                     : lieservo::adapters::PreprocessParams::fromJsonFile(a.preprocess))),
        model_(lieservo::adapters::OnnxPoseModel::fromCard(a.model_card, lieservo::adapters::ModelKind::gdn)) {
    if (!model_.hasUncertainty()) throw std::runtime_error("the model card's GDN has no uncertainty outputs");
    // Reference frame and noise level: the sensor must be OUT of contact now.
    std::vector<cv::Mat> frames;
    for (int i = 0; i < 30; ++i) {
      lieservo::adapters::CameraFrame f;
      if (camera_.next(f) != Status::ok) throw std::runtime_error("camera: " + camera_.lastError());
      frames.push_back(f.image.clone());
    }
    reference_ = cv::Mat::zeros(frames[0].size(), frames[0].type());
    for (const auto& f : frames) reference_ += f / static_cast<double>(frames.size());
    double noise = 0;
    for (const auto& f : frames) noise = std::max(noise, statistic(f));
    threshold_ = a.contact_threshold > 0 ? a.contact_threshold : std::max(4 * noise, 1e-3);
    std::printf("tactile: no-contact noise %.5f, contact threshold %.5f\n", noise, threshold_);
  }

  bool next(TactileSample& out, std::string& error) override {
    lieservo::adapters::CameraFrame f;
    if (camera_.next(f) != Status::ok) {
      error = "camera: " + camera_.lastError();
      return false;
    }
    lieservo::adapters::Prediction p;
    if (model_.predict(f.image, p) != Status::ok) {
      error = "model: " + model_.lastError();
      return false;
    }
    const Status s = lieservo::adapters::toObservation(p, out.observation);
    if (s != Status::ok) {
      error = std::string("observation: ") + lieservo::describe(s);
      return false;
    }
    out.contact_statistic = statistic(f.image);
    contact_ = contact_ ? out.contact_statistic > 0.5 * threshold_ : out.contact_statistic > threshold_;
    out.in_contact = contact_;
    out.stamp = f.stamp;
    return true;
  }

 private:
  double statistic(const cv::Mat& img) const {
    return cv::norm(img, reference_, cv::NORM_L1) / static_cast<double>(img.total());
  }

  lieservo::adapters::TactileCamera camera_;
  lieservo::adapters::OnnxPoseModel model_;
  cv::Mat reference_;
  double threshold_ = 0;
  bool contact_ = false;
};

// ---- The tactile loop (its own thread): tactile_run.hpp -----------------------------------
lieservo::franka_example::RunSettings runSettings(const Args& a) {
  lieservo::franka_example::RunSettings r;
  r.duration_s = a.duration;
  r.approach_speed = a.approach_speed;
  r.approach_max_mm = a.approach_max_mm;
  return r;
}

// The task's loop from the options: surface following (Table 7, the feedforward along
// --heading) or single-arm pushing (Table 8, towards --target at the sensor's height).
std::string tactileLoop(const Args& a, FrankaAdapter& robot, TactileFrontEnd& sensor, const std::atomic<bool>& quit) {
  if (a.task == "push") {
    SE3d X_ws;
    if (robot.readPose(X_ws) != Status::ok) return "cannot read the robot pose: " + robot.lastError();
    lieservo::TactileLoop<lieservo::PushingController<lieservo::SE3d>>::Options o;
    o.controller = lieservo::pushingPreset<double>(lieservo::PushingConfiguration::single_arm);
    // Target at the sensor's current height (work x), paper (y, z) = (0, 375) mm.
    Eigen::Vector3d p(X_ws.translation().x(), a.target[1], a.target[2]);
    if (a.target[0] != 0) p.x() = a.target[0];
    o.controller.target = SE3d(lieservo::SO3<double>::identity(), p);
    lieservo::TactileLoop<lieservo::PushingController<lieservo::SE3d>> loop(o);
    if (loop.configurationStatus() != Status::ok) return std::string("pushing: ") + lieservo::describe(loop.configurationStatus());
    return lieservo::franka_example::runTactileLoop(runSettings(a), robot, sensor, loop, quit);
  }
  lieservo::TactileLoop<lieservo::TactileServoController<SE3d>>::Options o;
  o.controller = lieservo::surfaceFollowingPreset<double>();
  o.controller.feedforward = lieservo::surfaceFollowingFeedforward<double>(lieservo::deg2rad(a.heading_deg), a.speed);
  lieservo::TactileLoop<lieservo::TactileServoController<SE3d>> loop(o);
  if (loop.configurationStatus() != Status::ok) return std::string("following: ") + lieservo::describe(loop.configurationStatus());
  return lieservo::franka_example::runTactileLoop(runSettings(a), robot, sensor, loop, quit);
}

}  // namespace

static int run(int argc, char** argv) {
  namespace cli = lieservo::cli;
  Args args;
  if (const int status = lieservo::franka_example::parseOptions(argc, argv, args); status >= 0) return status;
  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);

  try {
    FrankaAdapterOptions ro;
    ro.robot_ip = args.robot_ip;
    ro.X_ee_s = poseFromMmDeg(args.mount);
    ro.limits.translation.velocity = args.max_speed * 1e-3;
    ro.watchdog.command_timeout_s = 0.2;
    FrankaAdapter robot(ro);

    if (!args.start.empty()) {
      std::puts("moving to the start pose");
      const Status s = robot.moveTo(poseFromMmDeg(args.start));
      if (s != Status::ok) {
        std::fprintf(stderr, "set-up: moveTo failed: %s %s\n", lieservo::describe(s), robot.lastError().c_str());
        return cli::kUsageOrSetup;
      }
    }

    OpenCvGdnFrontEnd sensor(args);  // captures the no-contact reference: keep the tip free
    std::atomic<bool> quit{false};
    std::string outcome = "running";
    std::thread tactile([&] { outcome = tactileLoop(args, robot, sensor, quit); });
    std::atomic<bool> tactile_done{false};
    std::thread waiter([&] {
      tactile.join();
      tactile_done.store(true);
    });
    for (int tick = 0; !tactile_done.load(); ++tick) {
      if (g_interrupted.load()) {
        quit.store(true);
        robot.stop();  // ramp down now; the tactile thread ends after its current frame
      }
      if (tick % 10 == 0) {
        const auto st = robot.stats();
        std::printf("loop %s, watchdog: %s, callbacks %llu, lost cycles %llu\n", st.running ? "running" : "idle",
                    lieservo::realtime::describe(st.watchdog), static_cast<unsigned long long>(st.callbacks),
                    static_cast<unsigned long long>(st.lost_cycles));
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    waiter.join();
    robot.stop();  // ramp to zero inside the limits and end the libfranka motion
    std::printf("finished: %s\n", outcome.c_str());
    if (!robot.lastError().empty()) std::printf("last libfranka error: %s\n", robot.lastError().c_str());
  } catch (const std::exception& e) {  // the robot or the camera cannot be reached or set up
    std::fprintf(stderr, "set-up error: %s\n", e.what());
    return cli::kUsageOrSetup;
  }
  return cli::kOk;
}

int main(int argc, char** argv) {
  return lieservo::cli::runProgram("franka_servo_example", [&] { return run(argc, argv); });
}
