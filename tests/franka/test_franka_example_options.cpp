// franka_servo_example's command line (examples/franka/franka_example_options.hpp): the
// documented example parses, and each malformed, missing or out-of-range option is refused
// with exit status 2, the option named and the options left as they were.
#include <catch2/catch.hpp>

#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "franka_example_options.hpp"

using lieservo::franka_example::Options;
using lieservo::franka_example::parseOptions;

namespace {

const std::string kCard = std::string(LIESERVO_SOURCE_DIR) + "/examples/gdn/models/train_val/model_card.json";

// Runs parseOptions on {program, args...}; returns its status, and what it wrote to std::cerr
// (CLI11's messages) in `errors`.
int parse(const std::vector<std::string>& args, Options& o, std::string* errors = nullptr) {
  std::vector<std::string> words{"franka_servo_example"};
  words.insert(words.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& w : words) argv.push_back(w.data());
  std::stringstream captured;
  std::streambuf* old = std::cerr.rdbuf(captured.rdbuf());
  const int status = parseOptions(int(argv.size()), argv.data(), o);
  std::cerr.rdbuf(old);
  if (errors) *errors = captured.str();
  return status;
}

}  // namespace

TEST_CASE("franka example options: the documented command line parses", "[franka][cli]") {
  Options o;
  REQUIRE(parse({"--robot", "172.16.0.2", "--task", "follow", "--camera", "0", "--model-card", kCard, "--mount",
                 "0,0,120,0,0,0", "--start", "450,0,150,180,0,0", "--heading", "90", "--duration", "30"},
                o) == -1);
  CHECK(o.robot_ip == "172.16.0.2");
  CHECK(o.task == "follow");
  CHECK(o.mount == std::vector<double>{0, 0, 120, 0, 0, 0});
  CHECK(o.start == std::vector<double>{450, 0, 150, 180, 0, 0});
  CHECK(o.heading_deg == 90);
  CHECK(o.duration == 30);
  CHECK(o.max_speed == 50);  // default kept
  Options p;
  REQUIRE(parse({"--robot", "r", "--model-card", kCard, "--task", "push", "--target", "0,10,375"}, p) == -1);
  CHECK(p.target == std::vector<double>{0, 10, 375});
}

TEST_CASE("franka example options: bad input is refused, named, and changes nothing", "[franka][cli]") {
  const std::vector<std::pair<std::vector<std::string>, std::string>> bad = {
      {{"--model-card", kCard}, "--robot"},                                   // required
      {{"--robot", "r"}, "--model-card"},                                     // required
      {{"--robot", "r", "--model-card", "/nonexistent/card.json"}, "/nonexistent/card.json"},
      {{"--robot", "r", "--model-card", kCard, "--task", "dance"}, "--task"},
      {{"--robot", "r", "--model-card", kCard, "--camera", "-1"}, "--camera"},
      {{"--robot", "r", "--model-card", kCard, "--camera", "2x"}, "--camera"},
      {{"--robot", "r", "--model-card", kCard, "--speed", "nan"}, "--speed"},
      {{"--robot", "r", "--model-card", kCard, "--speed", "20abc"}, "--speed"},
      {{"--robot", "r", "--model-card", kCard, "--max-speed", "1e300"}, "--max-speed"},
      {{"--robot", "r", "--model-card", kCard, "--duration", "0"}, "--duration"},
      {{"--robot", "r", "--model-card", kCard, "--mount", "1,2,3"}, "--mount"},
      {{"--robot", "r", "--model-card", kCard, "--mount", "1,2,3,4,5,abc"}, "--mount"},
      {{"--robot", "r", "--model-card", kCard, "--start", "1,2,3,4,5,inf"}, "--start"},
      {{"--robot", "r", "--model-card", kCard, "--target", "0,0"}, "--target"},
      {{"--robot", "r", "--model-card", kCard, "--bogus", "1"}, "--bogus"},
  };
  for (const auto& [args, named] : bad) {
    Options o;
    o.robot_ip = "unchanged";
    std::string errors;
    const int status = parse(args, o, &errors);
    INFO(args.back() << ": " << errors);
    CHECK(status == lieservo::cli::kUsageOrSetup);
    CHECK(errors.find(named) != std::string::npos);
    CHECK(o.robot_ip == "unchanged");
    CHECK(o.mount == std::vector<double>{0, 0, 0, 0, 0, 0});
  }
}
