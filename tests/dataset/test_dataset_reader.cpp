// The C++ data set reader (examples/dataset: lieservo_dataset/dataset_reader.hpp) on the real splits and on
// synthetic malformed targets.csv files.
#include <catch2/catch.hpp>

#include <lieservo_dataset/dataset_reader.hpp>
#include "test_support.hpp"

#include <fstream>
#include <string>

using namespace lieservo::dataset;
using Catch::Matchers::Contains;

namespace {
using lieservo::test::fileReadable;
const std::string kHeader =
    "sensor_image,pose_x,pose_y,pose_z,pose_Rx,pose_Ry,pose_Rz,shear_x,shear_y,shear_z,shear_Rx,shear_Ry,shear_Rz\n";

std::string csvErrorOf(const std::string& text) {
  try {
    parseTargetsCsv(text, "targets.csv");
  } catch (const DatasetError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST_CASE("targets.csv: parsing, CRLF, blank lines, label mapping", "[collection][reader]") {
  const std::string text = kHeader +
                           "image_1.png,0,0,0.5,11.7,-16.2,0,0.55,-2.2,0,0,0,2.49\r\n"
                           "\n"
                           "image_2.png, 0, 0, 6, -1e1, 2.5E-1, 0, -5, 0, 0, 0, 0, -5\n";
  const auto rows = parseTargetsCsv(text, "t.csv");
  REQUIRE(rows.size() == 2);
  CHECK(rows[0].sensor_image == "image_1.png");
  CHECK(rows[0].line == 2);
  CHECK(rows[1].line == 4);
  CHECK(rows[1].pose[3] == -10);
  CHECK(rows[1].pose[4] == 0.25);
  CHECK(rows[0].componentsSeparated());
  Eigen::Matrix<double, 6, 1> e;
  e << 0.55, -2.2, 0.5, 11.7, -16.2, 2.49;
  CHECK(rows[0].euler6Degrees() == e);
  TargetsReadOptions o;
  o.max_rows = 1;
  CHECK(parseTargetsCsv(text, "t.csv", o).size() == 1);
}

TEST_CASE("targets.csv: malformed files give file:line:col errors", "[collection][reader]") {
  CHECK_THAT(csvErrorOf(""), Contains("targets.csv:1:1") && Contains("missing header"));
  CHECK_THAT(csvErrorOf("sensor_image,pose_x\n"), Contains("targets.csv:1:1") && Contains("header has 2 columns"));
  CHECK_THAT(csvErrorOf("sensor_image,pose_x,pose_y,pose_z,pose_Rx,pose_Ry,pose_Rz,shear_x,shear_y,shear_z,shear_Rx,shear_Ry,Rz\n"),
             Contains("targets.csv:1:") && Contains("'Rz', expected 'shear_Rz'"));
  CHECK_THAT(csvErrorOf(kHeader + "image_1.png,0,0,0.5,1,2,0,0,0,0,0,0,1\nimage_2.png,0,0,abc,1,2,0,0,0,0,0,0,1\n"),
             Contains("targets.csv:3:17") && Contains("column 'pose_z'") && Contains("'abc'"));
  CHECK_THAT(csvErrorOf(kHeader + "image_1.png,0,0,0.5,1,2,0,0,0,0,0\n"),
             Contains("targets.csv:2:1") && Contains("row has 11 fields, expected 13"));
  CHECK_THAT(csvErrorOf(kHeader + "image_1.png,0,0,inf,1,2,0,0,0,0,0,0,1\n"),
             Contains("targets.csv:2:17") && Contains("non-finite"));
  CHECK_THAT(csvErrorOf(kHeader + ",0,0,1,1,2,0,0,0,0,0,0,1\n"), Contains("targets.csv:2:1") && Contains("empty sensor_image"));
  CHECK_THAT(csvErrorOf(kHeader + "image_1.png,0,0,1,1,2,0,0,0,0,0,0,1e\n"), Contains("targets.csv:2:") && Contains("'1e'"));
  CHECK_THROWS_WITH(readTargetsCsv("/nonexistent/targets.csv"), Contains("/nonexistent/targets.csv") && Contains("cannot open"));
}

TEST_CASE("the real splits read completely, with the JSON quirks repaired", "[collection][reader][real-data]") {
  for (const char* split : {"train", "val"}) {
    const std::string dir = lieservo::test::dataDir() + "/" + split;
    if (!fileReadable(dir + "/targets.csv")) {
      WARN("SKIPPED: real data not found at " << dir);
      continue;
    }
    const DatasetSplit s = readDatasetSplit(dir);
    INFO(dir);
    CHECK(s.targets.size() == (std::string(split) == "train" ? 6000u : 2000u));
    REQUIRE(s.collect_params.has_value());
    REQUIRE(s.env_params.has_value());
    REQUIRE(s.meta.has_value());
    REQUIRE(s.processed_image_params.has_value());
    REQUIRE(s.warnings.size() == 1);  // the stray ']' of env_params.json
    CHECK_THAT(s.warnings[0], Contains("env_params.json:1:"));
    const CollectParams cp = CollectParams::fromJson(*s.collect_params);
    CHECK(cp.pose_llims[2] == 0.5);
    CHECK(cp.pose_ulims[3] == 25);
    CHECK(cp.shear_ulims[0] == 5);
    CHECK(cp.sample_disk);
    double prev_z = -1;
    for (const auto& r : s.targets) {
      REQUIRE(r.componentsSeparated());
      REQUIRE(r.pose[2] >= prev_z);  // README: rows ordered by increasing depth
      prev_z = r.pose[2];
    }
    for (std::size_t i : {std::size_t{0}, s.targets.size() - 1}) {
      int w = 0, h = 0;
      REQUIRE(readPngSize(s.imagePath(s.targets[i]), w, h));
      CHECK(w > 0);
      CHECK(h > 0);
    }
    DatasetReadOptions strict;
    strict.tolerate_quirks = false;
    CHECK_THROWS_WITH(readDatasetSplit(dir, strict), Contains("env_params.json:1:"));
  }
}
