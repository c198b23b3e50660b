// lieservo_collect end to end against the kinematic stand-in arm and the synthetic image
// source: an uninterrupted run, a run interrupted (--stop-after) and resumed, runs killed
// mid-sample (test hook: after the image / in the middle of the row) and resumed, and the
// refusal to mix parameters. Every resumed directory must equal the uninterrupted one byte
// for byte (targets.csv, images, parameter files).
#include <catch2/catch.hpp>

#include "collector.hpp"
#include <lieservo_dataset/dataset_reader.hpp>
#include <lieservo_dataset/json.hpp>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>

#if defined(__unix__) || defined(__APPLE__)
#include <sys/wait.h>
#endif

using namespace lieservo::collection;
using namespace lieservo::dataset;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

const std::string kExe = LIESERVO_COLLECT_EXE;
const std::string kWork = LIESERVO_TEST_WORK_DIR;
constexpr int kSamples = 20;

struct RunResult {
  int code = -1;
  std::string log;
};

RunResult collect(const std::string& dir, const std::string& extra = "") {
  // The build does not order this test after the program (CMakeLists.txt says why): a build of
  // this target alone has to build lieservo_collect too.
  INFO("the program " << kExe << " is not built: cmake --build builds it");
  REQUIRE(fs::exists(kExe));
  const std::string log = dir + ".log";
  const std::string cmd = "'" + kExe + "' --out '" + dir + "' --samples " + std::to_string(kSamples) +
                          " --seed 7 --image-size 64 48 " + extra + " 2> '" + log + "'";
  const int raw = std::system(cmd.c_str());
  RunResult r;
#if defined(__unix__) || defined(__APPLE__)
  r.code = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
#else
  r.code = raw;
#endif
  r.log = readTextFile(log);
  return r;
}

std::string freshDir(const std::string& name) {
  const std::string d = kWork + "/" + name;
  fs::remove_all(d);
  fs::remove(d + ".log");
  fs::create_directories(kWork);
  return d;
}

std::map<std::string, std::string> dirContents(const std::string& dir) {
  std::map<std::string, std::string> m;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (e.is_regular_file()) m[fs::relative(e.path(), dir).generic_string()] = readTextFile(e.path().string());
  }
  return m;
}

/// An uninterrupted reference run, one per test case (CTest may run the cases in parallel).
std::string referenceDir(const std::string& tag) {
  const std::string d = freshDir("reference_" + tag);
  const RunResult r = collect(d);
  INFO(r.log);
  REQUIRE(r.code == 0);
  return d;
}

void requireSameAsReference(const std::string& dir) {
  const std::string tag = fs::path(dir).filename().string();
  const auto a = dirContents(dir), b = dirContents(referenceDir(tag));
  REQUIRE(a.size() == b.size());
  for (const auto& [name, bytes] : b) {
    INFO("file " << name);
    REQUIRE(a.count(name) == 1);
    REQUIRE(a.at(name) == bytes);
  }
}

}  // namespace

TEST_CASE("collect: an uninterrupted run writes the data set format", "[collection][e2e]") {
  const std::string dir = referenceDir("format");
  const DatasetSplit s = readDatasetSplit(dir, DatasetReadOptions{{}, false, true});  // strict JSON, params required
  REQUIRE(s.targets.size() == kSamples);
  CHECK(s.warnings.empty());
  std::set<std::string> names, images;
  for (std::size_t i = 0; i < s.targets.size(); ++i) {
    const auto& r = s.targets[i];
    CHECK(r.sensor_image == "image_" + std::to_string(i + 1) + ".png");
    CHECK(r.componentsSeparated());
    CHECK(std::hypot(r.shear[0], r.shear[1]) <= 5);
    CHECK(r.pose[2] >= 0.5);
    CHECK(r.pose[2] <= 6);
    CHECK(std::abs(r.shear[5]) <= 5);
    int w = 0, h = 0;
    REQUIRE(readPngSize(s.imagePath(r), w, h));
    CHECK(w == 64);
    CHECK(h == 48);
    names.insert(r.sensor_image);
    images.insert(readTextFile(s.imagePath(r)));
  }
  CHECK(names.size() == kSamples);
  CHECK(images.size() == kSamples);  // every pose gave a different image
  // parameter files: valid JSON (no Infinity), ranges as the paper's
  JsonParseOptions strict;
  strict.allow_non_finite = false;
  for (const char* f : {"collect_params.json", "processed_image_params.json", "env_params.json", "meta.json"}) {
    CHECK_NOTHROW(readJsonFile(dir + "/" + f, strict));
  }
  const CollectParams cp = CollectParams::fromJson(*s.collect_params);
  CHECK(cp.pose_ulims[3] == 25);
  CHECK(cp.shear_llims[5] == -5);
  CHECK(cp.seed == 7u);
  CHECK(cp.n_samples == std::size_t{kSamples});
  // the rows are the seeded plan
  CollectionConfig c;
  c.n_samples = kSamples;
  c.seed = 7;
  const auto plan = collectionPlan(c);
  for (std::size_t i = 0; i < plan.size(); ++i) {
    CHECK((s.targets[i].euler6Degrees() - plan[i].euler6Degrees()).cwiseAbs().maxCoeff() == 0.0);
  }
}

TEST_CASE("collect: interrupted after 8 (--stop-after), resumed, equals the uninterrupted run", "[collection][e2e]") {
  const std::string dir = freshDir("stop_after");
  RunResult r = collect(dir, "--stop-after 8");
  INFO(r.log);
  REQUIRE(r.code == 0);
  CHECK_THAT(r.log, Contains("8/20 (40.0%)") && Contains("ETA") && Contains("incomplete"));
  CHECK(readTargetsCsv(dir + "/targets.csv").size() == 8);
  r = collect(dir);
  INFO(r.log);
  REQUIRE(r.code == 0);
  CHECK_THAT(r.log, Contains("resuming at sample 9 of 20") && Contains("20/20 (100.0%)") && Contains("complete"));
  const auto rows = readTargetsCsv(dir + "/targets.csv");
  REQUIRE(rows.size() == kSamples);
  std::set<std::string> names, images;
  for (const auto& row : rows) {
    names.insert(row.sensor_image);
    images.insert(readTextFile(dir + "/processed_images/" + row.sensor_image));
  }
  CHECK(names.size() == kSamples);   // no duplicated rows
  CHECK(images.size() == kSamples);  // unique images
  requireSameAsReference(dir);       // rows, images and parameter files identical to an uninterrupted run
  // running again is a no-op
  r = collect(dir);
  REQUIRE(r.code == 0);
  CHECK_THAT(r.log, Contains("0 written now, 20 found"));
  requireSameAsReference(dir);
}

TEST_CASE("collect: killed after an image but before its row, resumed", "[collection][e2e]") {
  const std::string dir = freshDir("crash_after_image");
  RunResult r = collect(dir, "--crash-at 5 --crash-point 0");
  REQUIRE(r.code == 75);
  CHECK(readTargetsCsv(dir + "/targets.csv").size() == 4);
  CHECK(fs::exists(dir + "/processed_images/image_5.png"));  // orphan image
  r = collect(dir);
  INFO(r.log);
  REQUIRE(r.code == 0);
  CHECK_THAT(r.log, Contains("image without a row"));
  requireSameAsReference(dir);
}

TEST_CASE("collect: killed in the middle of a row (torn CSV line), resumed", "[collection][e2e]") {
  const std::string dir = freshDir("crash_torn_row");
  RunResult r = collect(dir, "--crash-at 12 --crash-point 1");
  REQUIRE(r.code == 75);
  const std::string csv = readTextFile(dir + "/targets.csv");
  CHECK(csv.back() != '\n');  // torn
  r = collect(dir);
  INFO(r.log);
  REQUIRE(r.code == 0);
  CHECK_THAT(r.log, Contains("cut a torn last line"));
  requireSameAsReference(dir);
}

TEST_CASE("collect: refuses to resume with other parameters or a missing image", "[collection][e2e]") {
  const std::string dir = freshDir("mismatch");
  REQUIRE(collect(dir, "--stop-after 3").code == 0);
  const std::string log_path = dir + ".log";
  const std::string cmd = "'" + kExe + "' --out '" + dir + "' --samples 20 --seed 8 --image-size 64 48 2> '" + log_path + "'";
  CHECK(std::system(cmd.c_str()) != 0);
  CHECK_THAT(readTextFile(log_path), Contains("collect_params.json") && Contains("different content"));
  fs::remove(dir + "/processed_images/image_2.png");
  const RunResult r = collect(dir);
  CHECK(r.code == 2);  // set-up: the data set does not match
  CHECK_THAT(r.log, Contains("targets.csv:3:1") && Contains("image_2.png"));
  // an edited row is detected too
  const std::string d2 = freshDir("edited");
  REQUIRE(collect(d2, "--stop-after 2").code == 0);
  std::string text = readTextFile(d2 + "/targets.csv");
  text.replace(text.find("image_2.png,0,0,"), 16, "image_2.png,0,0,1");
  writeFileAtomic(d2 + "/targets.csv", text);
  const RunResult r2 = collect(d2);
  CHECK(r2.code == 2);
  CHECK_THAT(r2.log, Contains("targets.csv:3:1") && Contains("is not sample 2"));
  // bad options
  CHECK(collect(freshDir("badopt"), "--phi-max 120").code == 2);
  CHECK(collect(freshDir("badopt3"), "--z-min 7").code == 2);
  CHECK(collect(freshDir("badopt2"), "--frobnicate").code == 2);
}
