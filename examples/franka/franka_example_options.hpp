// examples/franka/franka_example_options.hpp — franka_servo_example's command line: CLI11 with
// the programs' shared validators and exit statuses (lieservo_cli/cli.hpp). libfranka-free, so
// CI tests it (tests/franka) although it never builds the example itself.
#pragma once

#include <string>
#include <vector>

#include <lieservo_cli/cli.hpp>

namespace lieservo::franka_example {

/// What the example runs. Poses are x, y, z (mm) and α, β, γ (degrees, extrinsic xyz).
struct Options {
  std::string robot_ip;
  std::string task = "follow";  ///< follow | push
  int camera = 0;
  std::string model_card;
  std::string preprocess;  ///< processed_image_params.json ("" = PreprocessParams{}, the data set's)
  std::vector<double> mount{0, 0, 0, 0, 0, 0};  ///< X_ES: the sensor frame in libfranka's EE frame
  std::vector<double> start;                    ///< optional X_ws to move to first
  double heading_deg = 90;  ///< follow: feedforward direction in the reference xy-plane
  double speed = 10;        ///< follow: feedforward speed (mm/s), paper 10
  std::vector<double> target{0, 0, 375};  ///< push: target position in {w} (mm); paper (y, z) = (0, 375)
  double approach_speed = 5;     ///< mm/s along the sensor z until contact
  double approach_max_mm = 30;   ///< give up if no contact after this far
  double contact_threshold = -1; ///< mean |I − I_ref| of the processed image; < 0: 4× the no-contact noise
  double duration = 60;          ///< s
  double max_speed = 50;         ///< mm/s: translational velocity limit of the smoother
};

/// Parses argv into `out`. Returns -1 when the program should go on, otherwise the status to
/// exit with (lieservo::cli::parse): a malformed, missing or out-of-range option is named on
/// stderr and `out` is left as it was.
inline int parseOptions(int argc, char** argv, Options& out) {
  Options o = out;
  CLI::App app(
      "Pose-and-shear tactile servoing on a Franka arm with a TacTip: surface following or single-arm "
      "pushing (docs/hardware.md). Poses: x,y,z (mm),a,b,g (degrees, extrinsic xyz). Exit status: 0 the run\n"
      "ended (its outcome printed), 2 bad usage or set-up (a malformed option, a robot or camera that cannot be\n"
      "reached, a failed move to the start).",
      "franka_servo_example");
  const CLI::Validator length = cli::finiteIn(-5000, 5000);  // mm or degrees: a coordinate or an angle
  app.add_option("--robot", o.robot_ip, "the robot's IP address")->required();
  app.add_option("--model-card", o.model_card, "the GDN's model card (examples/gdn)")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--task", o.task, "follow | push")->capture_default_str()->check(CLI::IsMember({"follow", "push"}));
  app.add_option("--camera", o.camera, "the camera's index")->capture_default_str()->check(cli::integerIn(0, 63));
  app.add_option("--preprocess", o.preprocess,
                 "processed_image_params.json (default: the shared data set's, as the card describes: bbox [105,20,550,460], "
                 "threshold [61,5], mask r=230)")
      ->check(CLI::ExistingFile);
  app.add_option("--mount", o.mount, "X_ES, the sensor frame in libfranka's EE frame: x,y,z,a,b,g")
      ->expected(6)
      ->delimiter(',')
      ->check(length);
  app.add_option("--start", o.start, "a pose X_ws to move to first: x,y,z,a,b,g")
      ->expected(6)
      ->delimiter(',')
      ->check(length);
  app.add_option("--heading", o.heading_deg, "follow: the feedforward direction (degrees)")
      ->capture_default_str()
      ->check(cli::finiteIn(-360, 360));
  app.add_option("--speed", o.speed, "follow: the feedforward speed (mm/s)")
      ->capture_default_str()
      ->check(cli::finiteIn(0.1, 100));
  app.add_option("--target", o.target, "push: the target in {w}: x,y,z (mm)")
      ->expected(3)
      ->delimiter(',')
      ->check(length);
  app.add_option("--approach-speed", o.approach_speed, "mm/s along the sensor z until contact")
      ->capture_default_str()
      ->check(cli::finiteIn(0.1, 50));
  app.add_option("--approach-max", o.approach_max_mm, "give up without contact after this far (mm)")
      ->capture_default_str()
      ->check(cli::finiteIn(0.1, 200));
  app.add_option("--contact-threshold", o.contact_threshold,
                 "contact when the mean |I - I_ref| exceeds it; < 0: 4x the no-contact noise")
      ->capture_default_str()
      ->check(cli::finiteIn(-1, 255));
  app.add_option("--duration", o.duration, "s")->capture_default_str()->check(cli::finiteIn(0.1, 86400));
  app.add_option("--max-speed", o.max_speed, "the smoother's translational velocity limit (mm/s; libfranka's 1700)")
      ->capture_default_str()
      ->check(cli::finiteIn(0.1, 1700));
  const int status = cli::parse(app, argc, argv);
  if (status < 0) out = o;
  return status;
}

}  // namespace lieservo::franka_example
