// lieservo_sim/csv_log.hpp — the tasks' per-step logs (CSV) and their output folder. The
// figures are drawn with lieservo_plot/svg_figure.hpp (examples/plot).
#pragma once

#include <fstream>
#include <string>
#include <vector>

namespace lieservo::sim {

/// Minimal CSV writer (header + rows of numbers).
class CsvWriter {
 public:
  CsvWriter() = default;
  bool open(const std::string& path, const std::vector<std::string>& header);
  void row(const std::vector<double>& values);
  bool isOpen() const { return out_.is_open(); }

 private:
  std::ofstream out_;
};

/// Creates a directory (and parents); returns false on failure.
bool makeDirectories(const std::string& path);

}  // namespace lieservo::sim
