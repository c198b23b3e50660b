// benchmarks/bench_main.hpp — the benchmark programs' main(): Google Benchmark's own flags, with
// the exit statuses of every other program (0 ran, 2 bad usage) and the output rule of every
// other program (lieservo_cli/program.hpp). Checked first, because Google Benchmark 1.7 lets
// them through: a non-finite or non-positive number (--benchmark_min_time=nan never stops), a
// format it does not know, an empty --benchmark_out, and a filter that matches nothing (an
// invalid regular expression among them) run nothing and exit 0. --benchmark_out overwrites
// only a file that Google Benchmark wrote (JSON or CSV), through a temporary name.
#pragma once

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include <lieservo_cli/program.hpp>

namespace lieservo::bench {

/// Whether every numeric --benchmark_* flag of argv holds a finite number > 0 (reported on
/// stderr when one does not).
inline bool numericFlagsValid(int argc, char** argv) {
  static const char* const kNumeric[] = {"--benchmark_min_time=", "--benchmark_min_warmup_time=",
                                         "--benchmark_repetitions="};
  for (int i = 1; i < argc; ++i)
    for (const char* flag : kNumeric) {
      const std::size_t n = std::strlen(flag);
      if (std::strncmp(argv[i], flag, n) != 0) continue;
      const char* value = argv[i] + n;
      char* end = nullptr;
      const double v = std::strtod(value, &end);
      if (*value == '\0' || *end != '\0' || !std::isfinite(v) || !(v > 0)) {
        std::fprintf(stderr, "%s: %.*s needs a finite number > 0, got '%s'\n", argv[0], int(n - 1), flag, value);
        return false;
      }
    }
  return true;
}

/// The value of `--flag=VALUE` when argv[i] is that flag, else nullptr.
inline const char* flagValue(const char* arg, const char* flag) {
  const std::size_t n = std::strlen(flag);
  return std::strncmp(arg, flag, n) == 0 && arg[n] == '=' ? arg + n + 1 : nullptr;
}

/// Whether the format flags name formats that Google Benchmark knows (reported when not).
inline bool formatFlagsValid(int argc, char** argv) {
  for (int i = 1; i < argc; ++i)
    for (const char* flag : {"--benchmark_format", "--benchmark_out_format"})
      if (const char* v = flagValue(argv[i], flag);
          v && std::strcmp(v, "console") != 0 && std::strcmp(v, "json") != 0 && std::strcmp(v, "csv") != 0) {
        std::fprintf(stderr, "%s: %s must be console, json or csv, got '%s'\n", argv[0], flag, v);
        return false;
      }
  return true;
}

/// Whether `path` is absent or a file Google Benchmark wrote: JSON ("{" then its "context")
/// or CSV (its header), or the console format's first line (a date and "Running").
inline bool writtenByBenchmark(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(std::filesystem::symlink_status(path, ec))) return true;
  if (!std::filesystem::is_regular_file(path, ec)) return false;
  std::ifstream in(path);
  std::string first, second;
  std::getline(in, first);
  std::getline(in, second);
  return (first == "{" && second.rfind("  \"context\":", 0) == 0) || first.rfind("name,iterations,", 0) == 0 ||
         first.find(" Running ") != std::string::npos;
}

/// A reporter that reports nothing and declines the context, so that Google Benchmark starts no
/// run: RunSpecifiedBenchmarks with it only counts the benchmarks that the filter matches.
class MatchCounter : public benchmark::BenchmarkReporter {
 public:
  MatchCounter() { SetOutputStream(&silent_); }  // --benchmark_list_tests lists once, in the real call
  bool ReportContext(const Context&) override { return false; }
  void ReportRuns(const std::vector<Run>&) override {}

 private:
  std::ostringstream silent_;
};

/// Parses Google Benchmark's flags (`what`: what the program measures, the first line of its
/// --help), checks that the filter matches a benchmark, then calls `set_up` (when given: the
/// program's own set-up, -1 to go on or its exit status, e.g. kSkipped without the data), then
/// runs the registered benchmarks: 0, or 2 for a malformed or unknown flag, a --benchmark_out
/// that is not Google Benchmark's file, or a filter that matches no benchmark (named on stderr).
inline int runBenchmarks(int argc, char** argv, const char* what, const std::function<int()>& set_up = {}) {
  for (int i = 1; i < argc; ++i)
    if (std::strcmp(argv[i], "--help") == 0 || std::strcmp(argv[i], "-h") == 0)
      std::printf("%s: %s; Google Benchmark's flags below. Exit status: 0 ran, 2 bad usage or set-up (a malformed\n"
                  "or unknown flag, a filter that matches nothing, a --benchmark_out that Google Benchmark did not\n"
                  "write), 77 skipped: the data it needs is absent.\n",
                  std::filesystem::path(argv[0]).filename().string().c_str(), what);
  if (!numericFlagsValid(argc, argv) || !formatFlagsValid(argc, argv)) return lieservo::cli::kUsageOrSetup;
  // --benchmark_out=FILE: checked, then written under a temporary name renamed at the end.
  std::vector<std::string> args(argv, argv + argc);
  std::string out, tmp;
  for (std::string& a : args)
    if (const char* v = flagValue(a.c_str(), "--benchmark_out")) {
      out = v;
      std::string why;
      if (out.empty())
        why = "--benchmark_out: an empty path";
      else if (!writtenByBenchmark(out))
        why = "--benchmark_out " + out + ": the file exists and was not written by Google Benchmark; it is left "
              "untouched: name another file";
      if (!why.empty() || !lieservo::cli::mayOverwrite("--benchmark_out", out, "", why)) {
        std::fprintf(stderr, "%s: %s\n", argv[0], why.c_str());
        return lieservo::cli::kUsageOrSetup;
      }
      tmp = lieservo::cli::temporaryBeside(out);
      a = "--benchmark_out=" + tmp;
    }
  std::vector<char*> ptrs;
  for (std::string& a : args) ptrs.push_back(a.data());
  int n = argc;
  benchmark::Initialize(&n, ptrs.data());
  if (benchmark::ReportUnrecognizedArguments(n, ptrs.data())) return lieservo::cli::kUsageOrSetup;
  // The filter is checked before the set-up, which can take seconds (the replay's GDN pass).
  const auto noMatch = [&] {
    if (!tmp.empty()) std::remove(tmp.c_str());  // nothing ran: the old file stays
    std::fprintf(stderr, "%s: --benchmark_filter matches no benchmark (or is not a valid regular expression)\n", argv[0]);
    return lieservo::cli::kUsageOrSetup;
  };
  MatchCounter counter;
  if (benchmark::RunSpecifiedBenchmarks(&counter) == 0) return noMatch();
  if (set_up) {
    const int status = lieservo::cli::runProgram(argv[0], [&] { return set_up(); });
    if (status >= 0) {
      if (!tmp.empty()) std::remove(tmp.c_str());
      return status;
    }
  }
  const std::size_t ran = benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  if (ran == 0) return noMatch();
  if (!tmp.empty()) {
    std::string why;
    if (!lieservo::cli::commitTemporary(tmp, out, why)) {
      std::fprintf(stderr, "%s: --benchmark_out %s\n", argv[0], why.c_str());
      return lieservo::cli::kUsageOrSetup;
    }
  }
  return lieservo::cli::kOk;
}

}  // namespace lieservo::bench
