// lieservo_dataset/trained_on.hpp — which images of the data set a model was trained on, as
// its model card says (examples/gdn/export_onnx.py writes it). Header-only, no OpenCV.
//
// The card's "data" object:
//   "train": 6000, "val": 2000                    images per split of the data set
//   "trained_on": {"train": 5500, "val": 1500}    images of each split the network saw
//   "held_out": {"train": 500, "val": 500, "file": "held_out.csv"}
//                                                 the rows of those splits it did not see,
//                                                 listed as split,sensor_image beside the card
// A split missing from trained_on was not trained on. A card without trained_on (older cards,
// other projects' cards) is read by the project's convention: the network saw all of `train`.
//
// Why it matters: an error measured on an image the network trained on is a fitting error,
// not what a new contact will show. The simulation's `real` observations and the replay's
// wording both use only this answer.
#pragma once

#include "lieservo_dataset/dataset_reader.hpp"
#include "lieservo_dataset/json.hpp"

#include <cstddef>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace lieservo::dataset {

struct TrainedOn {
  bool listed = false;                      ///< the card has data.trained_on
  std::map<std::string, long> images;       ///< split → images the network trained on
  std::set<std::pair<std::string, std::string>> held_out;  ///< (split, sensor_image) never seen
  std::string held_out_file;                ///< the list's path ("" if the card names none)

  /// Did it train on any image of this split?
  bool sawSplit(const std::string& split) const {
    if (!listed) return split == "train";
    const auto it = images.find(split);
    return it != images.end() && it->second > 0;
  }
  /// Did the network train on this image? A split trained on in part counts as seen except
  /// for the rows the held-out list names (a split trained on in part with no list: all seen).
  bool saw(const std::string& split, const std::string& sensor_image) const {
    return sawSplit(split) && held_out.count({split, sensor_image}) == 0;
  }
  /// Rows of this split the held-out list names (the images of a trained-on split it did not see).
  std::size_t heldOutCount(const std::string& split) const {
    std::size_t n = 0;
    for (const auto& row : held_out) n += row.first == split ? 1 : 0;
    return n;
  }
  /// Did it train on every image of this split (by saw(): a trained-on split none of whose rows
  /// is held out)?
  bool sawAll(const std::string& split) const { return sawSplit(split) && heldOutCount(split) == 0; }
};

/// From a card already read from card_path (its held-out list is read from beside it). Throws
/// DatasetError naming the file (and the entry) when the card's data or the list is malformed
/// or the list cannot be read.
inline TrainedOn trainedOn(const JsonDocument& card, const std::string& card_path) {
  TrainedOn t;
  const JsonValue* data = find(card.root, "data");
  if (data == nullptr || !data->IsObject()) return t;
  const JsonValue* trained = find(*data, "trained_on");
  if (trained == nullptr) return t;
  if (!trained->IsObject()) card.fail("data.trained_on", "must be an object {split: images}");
  t.listed = true;
  for (const auto& m : trained->GetObject()) {
    const std::string key = m.name.GetString();
    if (!m.value.IsNumber() || !(m.value.GetDouble() >= 0)) card.fail("data.trained_on." + key, "must be a number >= 0");
    t.images[key] = static_cast<long>(m.value.GetDouble());
  }
  const JsonValue* held = find(*data, "held_out");
  if (held == nullptr) return t;
  const JsonValue* file = find(*held, "file");
  if (file == nullptr || !file->IsString()) card.fail("data.held_out", "needs \"file\": the list of held-out rows");
  const std::size_t slash = card_path.find_last_of('/');
  t.held_out_file = (slash == std::string::npos ? std::string() : card_path.substr(0, slash + 1)) + file->GetString();
  std::ifstream in(t.held_out_file);
  if (!in) throw DatasetError(t.held_out_file + ": cannot read the held-out list named by " + card_path);
  std::string line;
  std::vector<std::string_view> fields;
  std::vector<int> columns;
  for (int n = 1; std::getline(in, line); ++n) {
    detail::splitCsvLine(line, fields, columns);
    if (fields.size() != 2)
      throw DatasetError(t.held_out_file + ":" + std::to_string(n) + ":1: error: expected split,sensor_image");
    const std::string split(detail::trimField(fields[0])), name(detail::trimField(fields[1]));
    if (n == 1 && split == "split") continue;  // header
    t.held_out.emplace(split, name);
  }
  // Each split's count in the card must match its list: a stale list would mislabel images.
  for (const auto& m : held->GetObject()) {
    const std::string key = m.name.GetString();
    if (key == "file") continue;
    long listed = 0;
    for (const auto& row : t.held_out) listed += row.first == key ? 1 : 0;
    if (!m.value.IsNumber() || static_cast<long>(m.value.GetDouble()) != listed)
      card.fail("data.held_out." + key, "does not match the " + std::to_string(listed) + " rows of that split in " +
                                            t.held_out_file);
  }
  return t;
}

/// Reads the card at card_path; errors as trainedOn.
inline TrainedOn readTrainedOn(const std::string& card_path) { return trainedOn(readJsonFile(card_path), card_path); }

}  // namespace lieservo::dataset
