// lieservo_cli/program.hpp — what every command-line program shares besides its options: the
// exit statuses, the main() wrapper that turns an escaped exception into one of them, and the
// rule for output files (a program overwrites only a file it can recognise as its own, and
// writes each one under a temporary name that it then renames, so that a killed run leaves the
// old file or the new one, never half of one).
#pragma once

#include <unistd.h>

#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <new>
#include <string>
#include <system_error>

namespace lieservo::cli {

/// Exit statuses shared by the programs.
enum ExitStatus : int {
  kOk = 0,              ///< ran, and met its criteria where it has any
  kCriteriaMissed = 1,  ///< ran, and a task missed its criteria
  kUsageOrSetup = 2,    ///< bad usage or set-up: a malformed option, missing data, an unreadable file
  kSkipped = 77,        ///< skipped: the data or model it needs is absent (asked for; CTest's SKIP_RETURN_CODE)
};

/// A program's main(): `run()` returns its exit status; an exception that escapes it (out of
/// memory, a library's error) is reported under the program's name as bad set-up.
template <class Run>
int runProgram(const char* name, Run&& run) noexcept {
  try {
    return run();
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "%s: out of memory\n", name);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", name, e.what());
  }
  return kUsageOrSetup;
}

/// The first line of `path` ("" when it has none or cannot be read).
inline std::string firstLine(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  if (in) std::getline(in, line);
  return line;
}

/// The temporary name beside `path` that a program writes before renaming it to `path`.
inline std::string temporaryBeside(const std::string& path) {
  return path + ".tmp-" + std::to_string(static_cast<long>(::getpid()));
}

/// May `path` (given as `option`) be written, before any work is done? Yes when it is absent
/// or a regular file whose first line starts with `own_first_line` (what this program writes
/// first: a magic line, a CSV header), and a file can be made beside it. Otherwise: false, and
/// `why` names the file and, when it exists, says that it is left as it was.
inline bool mayOverwrite(const std::string& option, const std::string& path, const std::string& own_first_line,
                         std::string& why) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::exists(fs::symlink_status(path, ec)) &&
      !(fs::is_regular_file(path, ec) && firstLine(path).compare(0, own_first_line.size(), own_first_line) == 0)) {
    why = option + " " + path + ": the file exists and was not written by this program (its first line does not " +
          "start '" + own_first_line + "'); it is left untouched: name another file";
    return false;
  }
  const std::string probe = temporaryBeside(path);
  if (!std::ofstream(probe)) {
    why = option + " " + path + ": cannot write it (its folder is missing or read-only)";
    return false;
  }
  std::remove(probe.c_str());
  return true;
}

/// Renames the finished temporary file `tmp` to `path`; on failure removes it and says why.
inline bool commitTemporary(const std::string& tmp, const std::string& path, std::string& why) {
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (!ec) return true;
  std::remove(tmp.c_str());
  why = path + ": cannot write it (" + ec.message() + ")";
  return false;
}

/// Finishes `out`, opened on `tmp` (temporaryBeside(path)): flushed and closed, then renamed
/// to `path` when all of it was written, removed otherwise. True when `path` now holds it.
inline bool finishTemporary(std::ofstream& out, const std::string& tmp, const std::string& path) {
  const bool written = bool(out.flush());
  out.close();
  std::error_code ec;
  if (written) std::filesystem::rename(tmp, path, ec);
  if (!written || ec) std::filesystem::remove(tmp, ec);
  return written && !ec;
}

/// Writes `content` to `path` under a temporary name, then renames it: all or nothing.
inline bool writeFileAtomically(const std::string& path, const std::string& content, std::string& why) {
  const std::string tmp = temporaryBeside(path);
  std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
  if (out) out << content;
  if (!out || !finishTemporary(out, tmp, path)) {
    std::remove(tmp.c_str());
    why = path + ": cannot write it";
    return false;
  }
  return true;
}

/// The marker a program leaves in an output folder it made; a later run may write there again.
constexpr const char* kOutputFolderMarker = ".lieservo-output";

/// Makes `dir` (given as `option`) this program's output folder: creates it when absent and
/// marks it. An existing folder is accepted when it is empty, carries the marker, or holds the
/// file `own_file` (when given) that this program writes there, as runs before the marker did;
/// anything else (a user's folder, a file) is refused with `why`, and nothing in it is touched.
inline bool claimOutputFolder(const std::string& option, const std::string& dir, const std::string& program,
                              std::string& why, const char* own_file = nullptr) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path marker = fs::path(dir) / kOutputFolderMarker;
  if (fs::exists(dir, ec)) {
    if (!fs::is_directory(dir, ec)) {
      why = option + " " + dir + ": exists and is not a folder";
      return false;
    }
    const bool own = fs::exists(marker, ec) || (own_file && fs::is_regular_file(fs::path(dir) / own_file, ec));
    if (!own && !fs::is_empty(dir, ec)) {
      why = option + " " + dir + ": the folder exists, is not empty and was not made by a lieservo program (no " +
            kOutputFolderMarker + " in it); it is left untouched: name another folder";
      return false;
    }
  } else if (!fs::create_directories(dir, ec) || ec) {
    why = option + " " + dir + ": cannot create the folder (" + ec.message() + ")";
    return false;
  }
  std::ofstream out(marker);
  out << "written by " << program << "; a later run may overwrite what is in this folder\n";
  if (!out) {
    why = option + " " + dir + ": cannot write in the folder";
    return false;
  }
  return true;
}

}  // namespace lieservo::cli
