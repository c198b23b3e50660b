// Which images a model card says its network trained on (lieservo_dataset/trained_on.hpp):
// the project's two shipped cards, synthetic cards for each form, and malformed cards and
// held-out lists (errors name the file).
#include <catch2/catch.hpp>

#include <lieservo_dataset/trained_on.hpp>
#include "file_test_util.hpp"

#include <cstdio>
#include <fstream>
#include <string>

using namespace lieservo::dataset;
using Catch::Matchers::Contains;

namespace {
std::string writeCard(const std::string& dir, const std::string& data, const std::string& held_csv = "") {
  const std::string card = dir + "/model_card.json";
  std::ofstream(card) << "{\"data\": " << data << ", \"models\": {}}";
  if (!held_csv.empty()) std::ofstream(dir + "/held_out.csv") << held_csv;
  return card;
}

std::string cardErrorOf(const std::string& card) {
  try {
    readTrainedOn(card);
  } catch (const DatasetError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST_CASE("trained_on: a card without data.trained_on means all of train", "[dataset][trained_on]") {
  const std::string dir = file_test::makeTempDir("trained_on_none");
  const TrainedOn t = readTrainedOn(writeCard(dir, R"({"train": 6000, "val": 2000})"));
  CHECK_FALSE(t.listed);
  CHECK(t.saw("train", "image_1.png"));
  CHECK(t.sawAll("train"));
  CHECK_FALSE(t.saw("val", "image_1.png"));
  CHECK_FALSE(t.sawSplit("val"));
  file_test::removeTree(dir);
}

TEST_CASE("trained_on: whole splits and held-out rows", "[dataset][trained_on]") {
  const std::string dir = file_test::makeTempDir("trained_on_rows");
  SECTION("train only, all of it") {
    const TrainedOn t = readTrainedOn(writeCard(dir, R"({"train": 4, "val": 2, "trained_on": {"train": 4}})"));
    CHECK(t.listed);
    CHECK(t.sawAll("train"));
    CHECK(t.saw("train", "image_3.png"));
    CHECK_FALSE(t.sawSplit("val"));
    CHECK_FALSE(t.saw("val", "image_3.png"));
  }
  SECTION("both splits, one row of each held out") {
    const TrainedOn t = readTrainedOn(writeCard(
        dir, R"({"train": 4, "val": 2, "trained_on": {"train": 3, "val": 1}, "held_out": {"train": 1, "val": 1, "file": "held_out.csv"}})",
        "split,sensor_image\ntrain,image_2.png\r\nval,image_1.png\n"));
    CHECK(t.held_out_file == dir + "/held_out.csv");
    CHECK(t.held_out.size() == 2);
    CHECK(t.sawSplit("train"));
    CHECK_FALSE(t.sawAll("train"));
    CHECK(t.saw("train", "image_1.png"));
    CHECK_FALSE(t.saw("train", "image_2.png"));  // the CRLF line ending is trimmed
    CHECK_FALSE(t.saw("val", "image_1.png"));
    CHECK(t.saw("val", "image_2.png"));
    CHECK_FALSE(t.saw("test", "image_1.png"));
  }
  file_test::removeTree(dir);
}

TEST_CASE("trained_on: malformed cards and lists are refused, naming the file", "[dataset][trained_on]") {
  const std::string dir = file_test::makeTempDir("trained_on_bad");
  const std::string list = dir + "/held_out.csv";
  CHECK_THAT(cardErrorOf(writeCard(dir, R"({"trained_on": [6000]})")), Contains("model_card.json:") && Contains("object"));
  CHECK_THAT(cardErrorOf(writeCard(dir, R"({"trained_on": {"train": -1}})")), Contains("trained_on.train"));
  CHECK_THAT(cardErrorOf(writeCard(dir, R"({"trained_on": {"train": 5}, "held_out": {"train": 1}})")),
             Contains("\"file\""));
  std::remove(list.c_str());
  CHECK_THAT(cardErrorOf(writeCard(dir, R"({"trained_on": {"train": 5}, "held_out": {"train": 1, "file": "held_out.csv"}})")),
             Contains(list) && Contains("cannot read"));
  // A list that does not match the card's counts (a stale file) would mislabel images.
  CHECK_THAT(cardErrorOf(writeCard(dir, R"({"trained_on": {"train": 5}, "held_out": {"train": 2, "file": "held_out.csv"}})",
                               "split,sensor_image\ntrain,image_2.png\n")),
             Contains("held_out.train") && Contains("1 rows"));
  CHECK_THAT(cardErrorOf(writeCard(dir, R"({"trained_on": {"train": 5}, "held_out": {"train": 1, "file": "held_out.csv"}})",
                               "split,sensor_image\ntrain,image_2.png,extra\n")),
             Contains(list + ":2:1") && Contains("split,sensor_image"));
  CHECK_THAT(cardErrorOf(dir + "/missing.json"), Contains("missing.json"));
  file_test::removeTree(dir);
}

TEST_CASE("trained_on: the project's two GDN cards", "[dataset][trained_on]") {
  const std::string models = std::string(LIESERVO_SOURCE_DIR) + "/examples/gdn/models";
  if (!file_test::exists(models + "/model_card.json") || !file_test::exists(models + "/train_val/model_card.json")) {
    WARN("GDN model cards not exported (" << models << "): skipping");
    return;
  }
  // The paper's reproduction model: all of train, none of val.
  const TrainedOn paper = readTrainedOn(models + "/model_card.json");
  CHECK(paper.listed);
  CHECK(paper.sawAll("train"));
  CHECK_FALSE(paper.sawSplit("val"));
  // The deployed model: train and val but 500 rows of each.
  const TrainedOn deployed = readTrainedOn(models + "/train_val/model_card.json");
  CHECK(deployed.images.at("train") == 5500);
  CHECK(deployed.images.at("val") == 1500);
  CHECK(deployed.held_out.size() == 1000);
  CHECK_FALSE(deployed.sawAll("val"));
  CHECK(deployed.sawSplit("val"));
}
