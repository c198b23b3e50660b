// CSV logs and output folders (see lieservo_sim/csv_log.hpp).
#include "lieservo_sim/csv_log.hpp"

#include <lieservo_cli/program.hpp>

#include <filesystem>
#include <iomanip>

namespace lieservo::sim {

bool CsvWriter::open(const std::string& path, const std::vector<std::string>& header) {
  close();
  path_ = path;
  tmp_ = lieservo::cli::temporaryBeside(path);
  out_.open(tmp_);
  if (!out_) return false;
  for (std::size_t i = 0; i < header.size(); ++i) out_ << (i ? "," : "") << header[i];
  out_ << "\n";
  out_ << std::setprecision(7);
  return true;
}

void CsvWriter::row(const std::vector<double>& v) {
  if (!out_.is_open()) return;
  for (std::size_t i = 0; i < v.size(); ++i) out_ << (i ? "," : "") << v[i];
  out_ << "\n";
}

bool CsvWriter::close() {
  if (!out_.is_open()) return false;
  return lieservo::cli::finishTemporary(out_, tmp_, path_);
}

bool makeDirectories(const std::string& path) {
  std::error_code ec;
  std::filesystem::create_directories(path, ec);
  return !ec && std::filesystem::is_directory(path, ec);
}

}  // namespace lieservo::sim
