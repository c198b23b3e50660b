// results_page.hpp — what the demo shows: the summary table on the console and, in the results
// folder, index.html (the table, the pushing figure at the top, every figure and log).
#pragma once

#include <string>
#include <vector>

#include "lieservo_sim/tasks.hpp"

namespace lieservo::sim::programs {

/// One row of the summary table. `judged`: the row decides (pass is its verdict); a row that
/// only reports (`judged` false) reads "reported" on the page.
struct Row {
  std::string task, item, sim, paper;
  bool pass = true;
  bool judged = true;
};

/// The summary figure's file in the results folder, shown at the top of the page.
constexpr const char* kSummaryFigure = "pushing_summary.svg";

/// Prints the summary table to stdout.
void printSummaryTable(const std::vector<Row>& rows);

/// Each pushing case's final target error, mean ± sd, beside the paper's (Tables 3–5), one
/// panel per controller, the criterion (Bounds::pushing_error_max) drawn. False if the file
/// cannot be written.
bool writePushingSummaryFigure(const std::string& path, const std::vector<const PushingResult*>& results,
                               const std::vector<std::string>& titles);

/// Writes dir/index.html; false if it cannot be written.
bool writeIndex(const std::string& dir, const std::string& heading, const std::vector<Row>& rows,
                const std::vector<std::string>& failures);

}  // namespace lieservo::sim::programs
