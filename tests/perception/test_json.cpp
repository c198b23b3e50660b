// The tolerant JSON reader (Python-style Infinity/NaN) and PreprocessParams loading.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include "lieservo_adapters/json.hpp"
#include "lieservo_adapters/preprocessing.hpp"
#include "perception_test_util.hpp"

using namespace lieservo::adapters;

TEST_CASE("json: standard values, nesting and Python's Infinity/NaN", "[perception][json]") {
  const JsonValue v = parseJson(R"({"a": [1, -2.5e1, true, false, null], "s": "x\"y\u00e9",
      "inf": [Infinity, -Infinity, NaN], "o": {"k": {}}})");
  REQUIRE(v.isObject());
  const auto a = v.at("a").asArray();
  REQUIRE(a.size() == 5);
  CHECK(a[0].asInt() == 1);
  CHECK(a[1].asNumber() == -25.0);
  CHECK(a[2].asBool());
  CHECK(a[4].isNull());
  CHECK(v.at("s").asString() == "x\"y\xc3\xa9");
  const auto inf = v.at("inf").asNumberArray();
  CHECK(std::isinf(inf[0]));
  CHECK(inf[0] > 0);
  CHECK(inf[1] < 0);
  CHECK(std::isnan(inf[2]));
  CHECK(v.at("o").at("k").asObject().empty());
  CHECK(v.find("missing") == nullptr);
}

TEST_CASE("json: malformed input names the source, line and column", "[perception][json]") {
  auto message = [](const std::string& text) {
    try {
      parseJson(text, "params.json");
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string m1 = message("{\"a\": 1,\n \"b\": [1, 2,, 3]}");
  CHECK(m1.find("params.json:2:") != std::string::npos);
  CHECK(m1.find("malformed JSON") != std::string::npos);
  CHECK(message("{\"a\": 1").find("unterminated object") != std::string::npos);
  CHECK(message("[1, 2] x").find("trailing") != std::string::npos);
  CHECK(message("{\"a\": Inf}").find("unexpected character") != std::string::npos);
  CHECK(message("\"abc").find("unterminated string") != std::string::npos);
  CHECK(message("").find("unexpected end") != std::string::npos);
  CHECK_THROWS_WITH(parseJson("{\"a\": 1}").at("b"), Catch::Contains("missing key \"b\""));
  CHECK_THROWS_WITH(parseJson("{\"a\": 1.5}").at("a").asInt("a"), Catch::Contains("integer"));
  CHECK_THROWS_WITH(parseJson("{\"a\": \"x\"}").at("a").asNumber("a"), Catch::Contains("a number"));
}

TEST_CASE("json: files: missing file and malformed file are reported with the path", "[perception][json]") {
  CHECK_THROWS_WITH(readJsonFile("/nonexistent/dir/params.json"), Catch::Contains("/nonexistent/dir/params.json"));
  const std::string dir = perception_test::makeTempDir("json");
  const std::string bad = dir + "/processed_image_params.json";
  std::ofstream(bad) << "{\"gray\": true, \"bbox\": [105, 20, 550 460]}";
  CHECK_THROWS_WITH(PreprocessParams::fromJsonFile(bad), Catch::Contains(bad + ":1:"));
  std::ofstream(bad) << "{\"gray\": true, \"bbox\": [105, 20, 550]}";
  CHECK_THROWS_WITH(PreprocessParams::fromJsonFile(bad), Catch::Contains("bbox should have 4 entries"));
  std::ofstream(bad) << "{\"bbox\": [105, 20, 700, 460]}";
  CHECK_THROWS_WITH(PreprocessParams::fromJsonFile(bad), Catch::Contains("outside"));
  std::ofstream(bad) << "{\"thresh\": [60, 5]}";
  CHECK_THROWS_WITH(PreprocessParams::fromJsonFile(bad), Catch::Contains("odd"));
  perception_test::removeTree(dir);
}

TEST_CASE("json: the data set's parameter files", "[perception][json][data]") {
  const std::string val = std::string(LIESERVO_DATA_DIR) + "/val";
  if (!perception_test::exists(val + "/processed_image_params.json")) {
    WARN("TacTip data not found under " << LIESERVO_DATA_DIR << ": skipping");
    return;
  }
  const PreprocessParams p = PreprocessParams::fromJsonFile(val + "/processed_image_params.json");
  CHECK(p.gray);
  CHECK(p.bbox == cv::Rect(105, 20, 445, 440));
  CHECK(p.processedSize() == cv::Size(445, 440));
  CHECK(p.threshold);
  CHECK(p.threshold_block == 61);
  CHECK(p.threshold_c == 5.0);
  CHECK(p.circle_mask_radius == 230);
  CHECK(p.output_size == 128);
  // meta.json holds Python's Infinity literals.
  const JsonValue c = readJsonFile(val + "/meta.json");
  const auto rng = c.at("z_shear_rng").asNumberArray("z_shear_rng");
  REQUIRE(rng.size() == 2);
  CHECK(std::isinf(rng[0]));
  CHECK(c.at("n_samples").asInt() == 2000);
}
