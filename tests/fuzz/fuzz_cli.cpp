// libFuzzer target: the command-line programs' option parsing (CLI11 with lieservo_cli's
// validators and parse(), examples/cli), on arbitrary argument vectors: options of every kind
// the programs use (an unsigned seed, a bounded count, a finite real, a list of reals, a choice,
// flags, text). Properties (abort on violation):
//   * no crash, no UB (ASan+UBSan), no exception escapes parse();
//   * parse() returns -1 (go on), 0 (help) or 2 (refused);
//   * when it goes on, every parsed value is finite and inside its validator's range.
// The same words then go through the Franka example's own parser (franka_example_options.hpp).
#include <lieservo_cli/cli.hpp>

#include <cmath>
#include <cstdint>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "franka_example_options.hpp"
#include "fuzz_common.hpp"

namespace {

// Quiet parse(): its messages go to std::cout / std::cerr.
struct Silence {
  std::ostringstream sink;
  std::streambuf* out = std::cout.rdbuf(sink.rdbuf());
  std::streambuf* err = std::cerr.rdbuf(sink.rdbuf());
  ~Silence() {
    std::cout.rdbuf(out);
    std::cerr.rdbuf(err);
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace cli = lieservo::cli;
  // The bytes as arguments, split at NUL; a few option names first so that they occur often.
  static const char* const names[] = {"--seed", "--trials", "--rate", "--sigmas", "--observations",
                                      "--quick", "--mount", "--help", "--robot", "@card"};
  std::vector<std::string> args{"fuzz_cli"};
  std::string cur;
  for (std::size_t i = 0; i < size; ++i) {
    const auto c = char(data[i]);
    if (c == '\0') {
      args.push_back(cur);
      cur.clear();
    } else if (std::uint8_t(c) >= 0xF6 && cur.empty()) {
      const std::string name = names[std::uint8_t(c) - 0xF6];
      if (name == "@card") {  // a model card that exists, so the Franka parser can succeed
        args.push_back("--model-card");
        args.push_back("/proc/self/exe");
      } else {
        args.push_back(name);
      }
    } else {
      cur += c;
    }
  }
  if (!cur.empty()) args.push_back(cur);
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());

  std::uint64_t seed = 1;
  int trials = 5;
  double rate = 20;
  std::vector<double> sigmas{10, 1};
  std::string observations = "auto", out = "results";
  bool quick = false;
  CLI::App app("fuzz", "fuzz_cli");
  app.add_option("--seed", seed)->check(cli::integerIn<std::uint64_t>(0, 1000000000000000));
  app.add_option("--trials", trials)->check(cli::integerIn(1, 100));
  app.add_option("--rate", rate)->check(cli::finiteIn(1, 1000));
  app.add_option("--sigmas", sigmas)->delimiter(',')->check(cli::finiteIn(1e-6, 100));
  app.add_option("--observations", observations)->check(CLI::IsMember({"auto", "real", "gaussian"}));
  app.add_option("--out", out);
  app.add_flag("--quick", quick);
  int status;
  {
    Silence quiet;
    status = cli::parse(app, int(argv.size()), argv.data());
  }
  LIESERVO_FUZZ_REQUIRE(status == -1 || status == cli::kOk || status == cli::kUsageOrSetup);
  if (status == -1) {
    LIESERVO_FUZZ_REQUIRE(seed <= 1000000000000000ULL);
    LIESERVO_FUZZ_REQUIRE(trials >= 1 && trials <= 100);
    LIESERVO_FUZZ_REQUIRE(std::isfinite(rate) && rate >= 1 && rate <= 1000);
    for (const double s : sigmas) LIESERVO_FUZZ_REQUIRE(std::isfinite(s) && s >= 1e-6 && s <= 100);
    LIESERVO_FUZZ_REQUIRE(observations == "auto" || observations == "real" || observations == "gaussian");
  }

  // The Franka example's own parser (examples/franka/franka_example_options.hpp) on the same
  // words: on success every list has its length and every number is finite and in range; on
  // refusal the options are as they were.
  namespace fe = lieservo::franka_example;
  fe::Options o;
  o.robot_ip = "before";
  {
    Silence quiet;
    status = fe::parseOptions(int(argv.size()), argv.data(), o);
  }
  LIESERVO_FUZZ_REQUIRE(status == -1 || status == cli::kOk || status == cli::kUsageOrSetup);
  if (status == -1) {
    LIESERVO_FUZZ_REQUIRE(o.mount.size() == 6 && o.target.size() == 3 && (o.start.empty() || o.start.size() == 6));
    for (const auto* v : {&o.mount, &o.target, &o.start})
      for (const double x : *v) LIESERVO_FUZZ_REQUIRE(std::isfinite(x) && std::abs(x) <= 5000);
    LIESERVO_FUZZ_REQUIRE(o.task == "follow" || o.task == "push");
    LIESERVO_FUZZ_REQUIRE(o.camera >= 0 && o.camera <= 63);
    for (const double x : {o.heading_deg, o.speed, o.approach_speed, o.approach_max_mm, o.contact_threshold,
                           o.duration, o.max_speed})
      LIESERVO_FUZZ_REQUIRE(std::isfinite(x));
    LIESERVO_FUZZ_REQUIRE(o.speed > 0 && o.max_speed > 0 && o.max_speed <= 1700 && o.duration > 0);
  } else {
    LIESERVO_FUZZ_REQUIRE(o.robot_ip == "before" && o.mount == std::vector<double>(6, 0.0));
  }
  return 0;
}
