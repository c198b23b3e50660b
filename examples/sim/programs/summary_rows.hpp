// summary_rows.hpp — the demo's summary table, one function per task: each turns a task's
// result into its rows beside the paper's numbers (Tables 3–9; docs/simulation.md).
#pragma once

#include <vector>

#include "results_page.hpp"

namespace lieservo::sim::programs {

void addTrackingRows(const TrackingResult& r, std::vector<Row>& rows);
void addFollowingRows(const FollowingResult& r, std::vector<Row>& rows);
/// Single- or dual-arm pushing, a row per case; `task` labels them.
void addPushingRows(const PushingResult& r, const char* task, std::vector<Row>& rows);
/// The tall objects pushed by one arm on foam: how many topple (reported).
void addTallPushRows(const PushingResult& r, std::vector<Row>& rows);
/// The toppling thresholds, the engine's beside the statics' (judged: within 10 %).
void addToppleRows(const std::vector<ToppleRow>& table, std::vector<Row>& rows);

}  // namespace lieservo::sim::programs
