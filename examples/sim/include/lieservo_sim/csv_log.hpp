// lieservo_sim/csv_log.hpp — the tasks' per-step logs (CSV) and their output folder. The
// figures are drawn with lieservo_plot/svg_figure.hpp (examples/plot).
#pragma once

#include <fstream>
#include <string>
#include <vector>

namespace lieservo::sim {

/// Minimal CSV writer (header + rows of numbers). The rows go to a temporary file beside
/// `path`, renamed to `path` by close() (or the destructor): a killed run leaves the old file
/// or the new one, never half of one.
class CsvWriter {
 public:
  CsvWriter() = default;
  ~CsvWriter() { close(); }
  CsvWriter(const CsvWriter&) = delete;
  CsvWriter& operator=(const CsvWriter&) = delete;
  bool open(const std::string& path, const std::vector<std::string>& header);
  void row(const std::vector<double>& values);
  bool isOpen() const { return out_.is_open(); }
  /// Finishes the file: true when it was written in full and is now at `path`.
  bool close();

 private:
  std::ofstream out_;
  std::string path_, tmp_;
};

/// Creates a directory (and parents); returns false on failure.
bool makeDirectories(const std::string& path);

}  // namespace lieservo::sim
