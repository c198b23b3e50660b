// lieservo_cli/cli.hpp — the command-line programs' options: CLI11 parses them (typed options,
// generated --help); these validators add what CLI11 2.1 lets through (a negative number for an
// unsigned option, NaN and infinity for a real one), and parse() maps the outcome to the
// programs' shared exit statuses (program.hpp).
#pragma once

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <string>

#include <CLI/CLI.hpp>

#include "lieservo_cli/program.hpp"

namespace lieservo::cli {

/// A decimal integer in [lo, hi]: digits only (a leading '-' where lo < 0), no exponent, no
/// suffix, no wrap-around.
template <class Int>
CLI::Validator integerIn(Int lo, Int hi) {
  std::ostringstream d;
  d << "INT in [" << lo << ", " << hi << "]";
  return CLI::Validator(
      [lo, hi](std::string& s) -> std::string {
        Int v{};
        const char* end = s.data() + s.size();
        const auto r = std::from_chars(s.data(), end, v);
        if (s.empty() || r.ec != std::errc() || r.ptr != end || v < lo || v > hi) {
          std::ostringstream m;
          m << "'" << s << "' is not an integer in [" << lo << ", " << hi << "]";
          return m.str();
        }
        return std::string();
      },
      d.str());
}

/// A finite real number in [lo, hi] (not NaN, not infinite), nothing after it.
inline CLI::Validator finiteIn(double lo, double hi) {
  std::ostringstream d;
  d << "FLOAT in [" << lo << ", " << hi << "]";
  return CLI::Validator(
      [lo, hi](std::string& s) -> std::string {
        char* end = nullptr;
        const double v = s.empty() ? std::nan("") : std::strtod(s.c_str(), &end);
        if (s.empty() || end != s.c_str() + s.size() || !std::isfinite(v) || v < lo || v > hi) {
          std::ostringstream m;
          m << "'" << s << "' is not a finite number in [" << lo << ", " << hi << "]";
          return m.str();
        }
        return std::string();
      },
      d.str());
}

/// A path that is not empty (an empty one would silently fall back to a default).
inline CLI::Validator nonEmptyPath() {
  return CLI::Validator(
      [](std::string& s) -> std::string { return s.empty() ? std::string("an empty path") : std::string(); }, "PATH");
}

/// Parses argv into `app`. Returns -1 when the program should go on, otherwise the status to
/// exit with: kOk after --help (printed to stdout), kUsageOrSetup after a malformed, unknown or
/// out-of-range option (the message, naming the option, on stderr).
inline int parse(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
    return -1;
  } catch (const CLI::CallForHelp&) {
    std::cout << app.help();
    return kOk;
  } catch (const CLI::ParseError& e) {
    std::cerr << app.get_name() << ": " << e.what() << "\n(" << app.get_name() << " --help lists the options)\n";
    return kUsageOrSetup;
  }
}

}  // namespace lieservo::cli
