// libFuzzer target: the command-line programs' option parsing (CLI11 with lieservo_cli's
// validators and parse(), examples/cli), on arbitrary argument vectors: options of every kind
// the programs use (an unsigned seed, a bounded count, a finite real, a list of reals, a choice,
// flags, text). Properties (abort on violation):
//   * no crash, no UB (ASan+UBSan), no exception escapes parse();
//   * parse() returns -1 (go on), 0 (help) or 2 (refused);
//   * when it goes on, every parsed value is finite and inside its validator's range.
#include <lieservo_cli/cli.hpp>

#include <cmath>
#include <cstdint>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

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
                                      "--quick", "--out", "--help", "-h", "--"};
  std::vector<std::string> args{"fuzz_cli"};
  std::string cur;
  for (std::size_t i = 0; i < size; ++i) {
    const auto c = char(data[i]);
    if (c == '\0') {
      args.push_back(cur);
      cur.clear();
    } else if (std::uint8_t(c) >= 0xF6 && cur.empty()) {
      args.push_back(names[std::uint8_t(c) - 0xF6]);
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
  return 0;
}
