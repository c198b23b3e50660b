// The shared JSON reader and writer of examples/dataset (lieservo_dataset/json.hpp, json_writer.hpp): the real
// parameter files (Infinity literals, the malformed env_params.json) and synthetic malformed inputs (syntax errors
// name file:line:col, typed access the file and the value).
#include <catch2/catch.hpp>

#include <lieservo_dataset/json.hpp>
#include <lieservo_dataset/json_writer.hpp>
#include "test_support.hpp"

#include <cmath>
#include <fstream>
#include <string>

using namespace lieservo::dataset;
using Catch::Matchers::Contains;

namespace {
using lieservo::test::fileReadable;

std::string jsonErrorOf(const std::string& text, const std::string& name, JsonParseOptions o = {}) {
  try {
    parseJson(text, name, o);
  } catch (const DatasetError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST_CASE("json: values, nesting, escapes, Infinity/NaN", "[collection][json]") {
  const std::string text =
      "{\"a\": 1.5, \"b\": [1, -2e3, 0.25], \"s\": \"x\\\"y\\u00e9\\n\", \"t\": true, \"f\": false,\n"
      " \"n\": null, \"inf\": [Infinity, -Infinity], \"nan\": NaN, \"o\": {\"k\": []}}";
  const JsonDocument d = parseJson(text, "mem.json");
  CHECK(d.number("a") == 1.5);
  CHECK(d.numbers("b") == std::vector<double>{1, -2000, 0.25});
  CHECK(d.string("s") == "x\"y\xC3\xA9\n");
  CHECK(d.boolean("t"));
  CHECK_FALSE(d.boolean("f"));
  CHECK(d.member("n").IsNull());
  const auto inf = d.numbers("inf", 2);
  CHECK(std::isinf(inf[0]));
  CHECK(inf[0] > 0);
  CHECK(inf[1] < 0);
  CHECK(std::isnan(d.number("nan")));
  CHECK(d.member("o").IsObject());
  CHECK(d.warnings.empty());
  CHECK_THROWS_WITH(d.numbers("b", 6), Contains("mem.json: error: \"b\"") && Contains("must have 6 elements, has 3"));
  CHECK_THROWS_WITH(d.number("missing"), Contains("mem.json: error: missing key \"missing\""));
  CHECK_THROWS_WITH(d.number("s"), Contains("mem.json: error: \"s\" must be a number"));
}

TEST_CASE("json: malformed inputs give file:line:col errors", "[collection][json]") {
  struct Case {
    const char* text;
    const char* where;
    const char* what;
  };
  // RapidJSON's messages, at the byte where reading stopped.
  const Case cases[] = {
      {"{\"a\": 1,\n \"b\": [1, 2]]}", "bad.json:2:13", "Missing a comma or '}'"},  // the env_params quirk, strict
      {"{\"a\": 1,\n\n  \"b\" 2}", "bad.json:3:7", "Missing a colon"},
      {"{\"a\": [1, 2,\n 3", "bad.json:2:3", "Missing a comma or ']'"},
      {"{\"a\": tru}", "bad.json:1:", "Invalid value"},
      {"{\"a\": 01}", "bad.json:1:8", "Missing a comma or '}'"},
      {"{\"a\": \"abc\n\"}", "bad.json:1:", "string"},
      {"{\"a\": 1} x", "bad.json:1:10", "root must not be followed by other values"},
      {"{a: 1}", "bad.json:1:2", "Missing a name for object member"},
      {"", "bad.json:1:1", "The document is empty"},
      {"{\"a\": Infinit}", "bad.json:1:", "Invalid value"},
  };
  for (const auto& c : cases) {
    const std::string msg = jsonErrorOf(c.text, "bad.json");
    INFO("input: " << c.text << "\nmessage: " << msg);
    CHECK_THAT(msg, Contains(c.where) && Contains(c.what));
  }
  // RapidJSON's non-finite literals, signed; refused in strict mode.
  const JsonDocument nf = parseJson("[NaN, -NaN, Inf, -Inf, Infinity, -Infinity]", "nf.json");
  CHECK(std::isnan(nf.root[0].GetDouble()));
  CHECK(std::isnan(nf.root[1].GetDouble()));
  for (rapidjson::SizeType i = 2; i < 6; ++i) CHECK(std::isinf(nf.root[i].GetDouble()));
  CHECK(nf.root[3].GetDouble() < 0);
  JsonParseOptions strict;
  strict.allow_non_finite = false;
  CHECK_THAT(jsonErrorOf("{\"z\": [-Infinity]}", "m.json", strict), Contains("m.json:1:") && Contains("Invalid value"));
  // repair mode skips an unmatched closer with a warning, still fails on other garbage
  JsonParseOptions repair;
  repair.repair_stray_closers = true;
  const JsonDocument d = parseJson("{\"a\": [1, 2]],\n \"b\": \"]\\\"]\", \"c\": 3}]", "r.json", repair);
  CHECK(d.numbers("a") == std::vector<double>{1, 2});
  CHECK(d.string("b") == "]\"]");  // closers inside a string, after an escaped quote, are kept
  CHECK(d.number("c") == 3);
  REQUIRE(d.warnings.size() == 2);
  CHECK_THAT(d.warnings[0], Contains("r.json:1:13") && Contains("stray ']'"));
  CHECK_THAT(d.warnings[1], Contains("r.json:2:22"));
  CHECK_THAT(jsonErrorOf("{\"a\": [1 2]}", "r.json", repair), Contains("r.json:1:10"));
  // deep nesting: the iterative parser needs no recursion
  const JsonDocument deep = parseJson(std::string(100000, '[') + std::string(100000, ']'), "deep.json");
  CHECK(deep.root.IsArray());
}

TEST_CASE("json writer: valid JSON, numbers read back exactly, non-finite as null", "[collection][json]") {
  const std::string s = JsonObjectWriter()
                            .field("x", 0.1)
                            .field("v", std::vector<double>{0, -25, 0.5, 1e-300, std::nan(""), INFINITY})
                            .field("s", std::string("q\"\\\n"))
                            .field("b", true)
                            .field("n", 6000ULL)
                            .field("c", "text")
                            .str();
  CHECK(s == "{\"x\":0.1,\"v\":[0.0,-25.0,0.5,1e-300,null,null],\"s\":\"q\\\"\\\\\\n\",\"b\":true,\"n\":6000,\"c\":\"text\"}");
  JsonParseOptions strict;
  strict.allow_non_finite = false;
  const JsonDocument d = parseJson(s, "w.json", strict);
  CHECK(d.number("x") == 0.1);
  CHECK(d.string("s") == "q\"\\\n");
  CHECK(d.member("v")[4].IsNull());
  for (const double x : {0.1 + 0.2, 1.0 / 3, 6.02214076e23, -4.9e-324, 1.7976931348623157e308}) {
    const JsonDocument r = parseJson(JsonObjectWriter().field("x", x).str(), "r.json", strict);
    CHECK(r.number("x") == x);
  }
}

TEST_CASE("json: the real parameter files", "[collection][json][real-data]") {
  const std::string dir = lieservo::test::dataDir() + "/train";
  if (!fileReadable(dir + "/collect_params.json")) {
    WARN("SKIPPED: real data not found at " << dir);
    return;
  }
  const JsonDocument cp = readJsonFile(dir + "/collect_params.json");
  CHECK(cp.numbers("pose_ulims", 6)[3] == 25);
  CHECK(cp.numbers("shear_llims", 6)[5] == -5);
  CHECK(cp.boolean("sample_disk"));
  const JsonDocument meta = readJsonFile(dir + "/meta.json");  // Infinity literals
  CHECK(std::isinf(meta.numbers("z_shear_rng", 2)[0]));
  CHECK(meta.number("phi_max") == 25);
  CHECK(meta.string("robot_axes") == "sxyz");
  const JsonDocument pp = readJsonFile(dir + "/processed_image_params.json");
  CHECK(pp.numbers("bbox", 4) == std::vector<double>{105, 20, 550, 460});
  // env_params.json has an extra ']': strict reading fails naming the file and position,
  // repair mode reads it with a warning.
  const std::string env = dir + "/env_params.json";
  try {
    readJsonFile(env);
    FAIL("strict reading of the malformed env_params.json should fail");
  } catch (const DatasetError& e) {
    CHECK_THAT(std::string(e.what()), Contains(env + ":1:") && Contains("Missing a comma or '}'"));
  }
  JsonParseOptions repair;
  repair.repair_stray_closers = true;
  const JsonDocument e = readJsonFile(env, repair);
  CHECK(e.numbers("tcp_pose", 6) == std::vector<double>{0, 0, 72, 0, 0, 225});
  CHECK(e.string("robot") == "franka");
  REQUIRE(e.warnings.size() == 1);
  CHECK_THAT(e.warnings[0], Contains(env + ":1:") && Contains("stray ']'"));
}

TEST_CASE("json: typed access to any value names the file and the value, unreadable files name the path",
          "[collection][json]") {
  // What the model card and processed_image_params.json loaders of examples/adapters rely on.
  const JsonDocument d = parseJson("{\"a\": [1, -2.5e1, true, null],\n \"o\": {\"k\": {}}, \"s\": \"x\"}", "acc.json");
  const auto a = d.asArray(d.at(d.root, "a"), "a");
  REQUIRE(a.Size() == 4);
  CHECK(d.asInt(a[0], "a[0]") == 1);
  CHECK(d.asNumber(a[1], "a[1]") == -25.0);
  CHECK(d.asBool(a[2], "a[2]"));
  CHECK(a[3].IsNull());
  CHECK(d.at(d.at(d.root, "o"), "k", "o").ObjectEmpty());
  CHECK(d.asString(d.at(d.root, "s"), "s") == "x");
  CHECK(find(d.root, "missing") == nullptr);
  CHECK(find(a[0], "k") == nullptr);  // not an object
  CHECK(d.asInt(a[1], "a[1]") == -25);  // -2.5e1 is an exact integer
  const JsonDocument h = parseJson("[0.5, 3e10]", "int.json");
  CHECK_THROWS_WITH(h.asInt(h.root[0], "x"), Contains("int.json: error: \"x\" must be an integer"));
  CHECK_THROWS_WITH(h.asInt(h.root[1], "y"), Contains("int.json: error: \"y\" must be an integer"));
  CHECK_THROWS_WITH(d.asNumber(a[2], "a[2]"), Contains("acc.json: error: \"a[2]\" must be a number"));
  CHECK_THROWS_WITH(d.asString(a[0], "a[0]"), Contains("\"a[0]\" must be a string"));
  CHECK_THROWS_WITH(d.asArray(d.root, "top"), Contains("\"top\" must be an array"));
  CHECK_THROWS_WITH(d.at(d.at(d.root, "o"), "x", "o"), Contains("acc.json: error: missing key \"x\" in \"o\""));
  CHECK_THROWS_WITH(d.at(a[0], "x", "a[0]"), Contains("\"a[0]\" must be a JSON object"));
  CHECK_THROWS_AS(readJsonFile("/nonexistent/dir/params.json"), DatasetError);
  CHECK_THROWS_WITH(readJsonFile("/nonexistent/dir/params.json"),
                    Contains("/nonexistent/dir/params.json") && Contains("cannot open"));
}
