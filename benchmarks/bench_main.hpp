// benchmarks/bench_main.hpp — the benchmark programs' main(): Google Benchmark's own flags, with
// the exit statuses of every other program (0 ran, 2 bad usage) and its numeric flags checked
// first: Google Benchmark 1.7 takes --benchmark_min_time=nan and then never stops.
#pragma once

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

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

/// Parses Google Benchmark's flags and runs the registered benchmarks: 0, or 2 for a malformed
/// or unknown flag (named on stderr).
inline int runBenchmarks(int argc, char** argv) {
  if (!numericFlagsValid(argc, argv)) return 2;
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 2;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

}  // namespace lieservo::bench
