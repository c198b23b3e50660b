// Small helpers shared by the test executables.
#pragma once

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <string>

namespace lieservo::test {

/// Scale factor for long-running tests (Monte Carlo sample counts, closed-loop scene
/// lengths). 1 in a normal build; the sanitizer preset sets it lower through CMake
/// (LIESERVO_SLOW_TESTS_SCALE). Never below 0.01.
inline double slowTestsScale() {
  const char* s = std::getenv("LIESERVO_SLOW_TESTS_SCALE");
  const double v = s ? std::atof(s) : 1.0;
  return std::clamp(v > 0 ? v : 1.0, 0.01, 1.0);
}

/// `n` scaled by slowTestsScale(), at least `min_n`.
inline long scaledCount(long n, long min_n = 1) {
  return std::max(min_n, static_cast<long>(static_cast<double>(n) * slowTestsScale()));
}

/// The real TacTip data directory (compile-time default, overridable by LIESERVO_DATA).
inline std::string dataDir() {
  if (const char* env = std::getenv("LIESERVO_DATA")) return env;
#ifdef LIESERVO_DATA_DIR
  return LIESERVO_DATA_DIR;
#else
  return "";
#endif
}

/// Whether `path` names a file this process can open for reading.
inline bool fileReadable(const std::string& path) { return std::ifstream(path).good(); }

}  // namespace lieservo::test
