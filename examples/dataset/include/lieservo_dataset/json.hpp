// lieservo_dataset/json.hpp — the project's JSON files (the data set's parameter files, the ONNX
// model cards) read into a RapidJSON Document (Debian rapidjson-dev; header-only, no OpenCV);
// json_writer.hpp writes them. Standard JSON plus RapidJSON's non-finite literals (NaN, Inf,
// Infinity, signed: the shared meta.json has Infinity), parsed iteratively (no recursion). A
// syntax error names "<file>:<line>:<col>"; a missing key or a wrong type names the file and the
// value's path ("models.gdn.file"). JsonParseOptions::repair_stray_closers skips a closing
// bracket that matches no open container (the shared env_params.json ends "225]]}") with a warning.
#pragma once

#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <rapidjson/document.h>
#include <rapidjson/error/en.h>

namespace lieservo::dataset {

/// Any problem reading or writing a data set file; what() names the file (and where in it).
class DatasetError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

using JsonValue = rapidjson::Value;

struct JsonParseOptions {
  bool allow_non_finite = true;       ///< accept NaN, Inf, Infinity (with a sign)
  bool repair_stray_closers = false;  ///< skip an unmatched ']' or '}' (with a warning)
};

/// Member `key` of an object (the first, if repeated), or nullptr (also when `v` is not an object).
inline const JsonValue* find(const JsonValue& v, std::string_view key) {
  if (!v.IsObject()) return nullptr;
  const JsonValue name(rapidjson::StringRef(key.data(), rapidjson::SizeType(key.size())));
  const auto it = v.FindMember(name);
  return it == v.MemberEnd() ? nullptr : &it->value;
}

/// A parsed file and typed access to its values: a mismatch throws DatasetError
/// "<name>: error: "<what>" must be ..." (`what`: the value's path, e.g. "bbox[0]").
struct JsonDocument {
  std::string name;                   ///< file name used in messages
  rapidjson::Document root;
  std::vector<std::string> warnings;  ///< "<file>:<line>:<col>: warning: ..."

  [[noreturn]] void fail(std::string_view what, const std::string& problem) const {
    throw DatasetError(name + ": error: " + (what.empty() ? "" : "\"" + std::string(what) + "\" ") + problem);
  }
  const JsonValue& expect(bool ok, const JsonValue& v, std::string_view what, const char* problem) const {
    return ok ? v : (fail(what, problem), v);
  }
  /// Member `key` of the object `obj` (`what`: its path; empty: the top level).
  const JsonValue& at(const JsonValue& obj, std::string_view key, std::string_view what = {}) const {
    const JsonValue* v = find(expect(obj.IsObject(), obj, what, "must be a JSON object"), key);
    const std::string in = what.empty() ? "" : " in \"" + std::string(what) + "\"";
    return v != nullptr ? *v : (fail({}, "missing key \"" + std::string(key) + "\"" + in), obj);
  }
  bool asBool(const JsonValue& v, std::string_view w) const { return expect(v.IsBool(), v, w, "must be true or false").GetBool(); }
  double asNumber(const JsonValue& v, std::string_view w) const { return expect(v.IsNumber(), v, w, "must be a number").GetDouble(); }
  /// A number that is an exact integer, |x| ≤ INT_MAX.
  int asInt(const JsonValue& v, std::string_view what) const {
    const double x = asNumber(v, what);
    if (!(std::floor(x) == x && std::abs(x) <= double(std::numeric_limits<int>::max()))) fail(what, "must be an integer");
    return int(x);
  }
  std::string asString(const JsonValue& v, std::string_view what) const {
    return expect(v.IsString(), v, what, "must be a string").GetString();  // (no NUL inside: validated UTF-8)
  }
  JsonValue::ConstArray asArray(const JsonValue& v, std::string_view what) const {
    return expect(v.IsArray(), v, what, "must be an array").GetArray();
  }
  /// An array of numbers; expected_size < 0: any size.
  std::vector<double> asNumbers(const JsonValue& v, std::string_view what, int expected_size = -1) const {
    std::vector<double> out;
    for (const JsonValue& e : asArray(v, what)) out.push_back(asNumber(e, std::string(what) + "[]"));
    if (expected_size >= 0 && out.size() != std::size_t(expected_size))
      fail(what, "must have " + std::to_string(expected_size) + " elements, has " + std::to_string(out.size()));
    return out;
  }

  // Members of the top-level object.
  bool has(std::string_view key) const { return find(root, key) != nullptr; }
  const JsonValue& member(std::string_view key) const { return at(root, key); }
  double number(std::string_view key) const { return asNumber(member(key), key); }
  bool boolean(std::string_view key) const { return asBool(member(key), key); }
  std::string string(std::string_view key) const { return asString(member(key), key); }
  std::vector<double> numbers(std::string_view k, int size = -1) const { return asNumbers(member(k), k, size); }
};

/// "<name>:<line>:<col>" of a byte offset into text (1-based, in bytes).
inline std::string jsonWhere(std::string_view text, std::size_t offset, const std::string& name) {
  int line = 1, col = 1;
  for (std::size_t i = 0; i < offset && i < text.size(); ++i) {
    if (text[i] == '\n') ++line, col = 1;
    else ++col;
  }
  return name + ":" + std::to_string(line) + ":" + std::to_string(col);
}

/// Parses text (`name` in messages); throws DatasetError.
inline JsonDocument parseJson(std::string_view text, const std::string& name, const JsonParseOptions& opt = {}) {
  JsonDocument doc;
  doc.name = name;
  std::string buf(text);  // NUL-terminated for RapidJSON, and repairable
  if (buf.compare(0, 3, "\xEF\xBB\xBF") == 0) buf.replace(0, 3, "   ");  // UTF-8 byte-order mark
  std::vector<char> open;  // repair: a stray closer is blanked (a space: positions stay)
  for (std::size_t i = 0; opt.repair_stray_closers && i < buf.size(); ++i) {
    const char c = buf[i];
    if (c == '"') {  // skip the string, escapes included
      for (++i; i < buf.size() && buf[i] != '"'; ++i) i += buf[i] == '\\';
    } else if (c == '[' || c == '{') {
      open.push_back(c == '[' ? ']' : '}');
    } else if ((c == ']' || c == '}') && !open.empty() && open.back() == c) {
      open.pop_back();
    } else if (c == ']' || c == '}') {
      doc.warnings.push_back(jsonWhere(buf, i, name) + ": warning: ignored stray '" + c + "'");
      buf[i] = ' ';
    }
  }
  constexpr unsigned flags =
      rapidjson::kParseFullPrecisionFlag | rapidjson::kParseValidateEncodingFlag | rapidjson::kParseIterativeFlag;
  opt.allow_non_finite ? doc.root.Parse<flags | rapidjson::kParseNanAndInfFlag>(buf.c_str()) : doc.root.Parse<flags>(buf.c_str());
  if (doc.root.HasParseError())
    throw DatasetError(jsonWhere(buf, doc.root.GetErrorOffset(), name) +
                       ": error: " + rapidjson::GetParseError_En(doc.root.GetParseError()));
  return doc;
}

inline std::string readTextFile(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw DatasetError(path + ": error: cannot open file for reading");
  std::string text((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  if (f.bad()) throw DatasetError(path + ": error: read failed");
  return text;
}

/// Reads and parses a JSON file; messages name `path`.
inline JsonDocument readJsonFile(const std::string& path, const JsonParseOptions& opt = {}) {
  return parseJson(readTextFile(path), path, opt);
}

}  // namespace lieservo::dataset
