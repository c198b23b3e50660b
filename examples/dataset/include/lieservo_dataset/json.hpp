// lieservo_dataset/json.hpp — the project's one JSON reader/writer (header-only, no OpenCV): the
// data set's parameter files, lieservo_collect's output and the ONNX model cards.
//
// Reading is RapidJSON's (Debian rapidjson-dev; its SAX reader builds the JsonValue tree
// below, each value with its line and column): standard JSON plus the Python json module's
// non-standard literals Infinity, -Infinity and NaN (the shared meta.json uses them). With
// JsonParseOptions::repair_stray_closers
// a closing bracket that does not match the open container (the shared env_params.json ends
// "225]]}") is skipped with a warning instead of failing. Every error and warning names the
// file, line and column: "<file>:<line>:<col>: error: <what>".
//
// Writes valid JSON only: non-finite numbers are written as null (JSON has no Infinity),
// numbers in shortest round-trip form.
#pragma once

#include <cctype>
#include <charconv>
#include <cstdint>
#include <cmath>
#include <cstddef>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <rapidjson/error/en.h>
#include <rapidjson/reader.h>

namespace lieservo::dataset {

/// Any problem reading or writing a data set file; what() names the file (and line:column).
class DatasetError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct JsonMember;

struct JsonValue {
  enum class Type { null, boolean, number, string, array, object };
  Type type = Type::null;
  bool boolean = false;
  double number = 0;
  std::string string;
  std::vector<JsonValue> array;
  std::vector<JsonMember> object;                         // file order
  int line = 0, column = 0;                               // where the value starts (1-based)

  bool isNull() const { return type == Type::null; }
  bool isBool() const { return type == Type::boolean; }
  bool isNumber() const { return type == Type::number; }
  bool isString() const { return type == Type::string; }
  bool isArray() const { return type == Type::array; }
  bool isObject() const { return type == Type::object; }

  /// Member of an object, or nullptr (last one wins on duplicates, like Python).
  const JsonValue* find(std::string_view key) const;
};

/// One member of a JSON object. (A named struct, not std::pair<std::string, JsonValue>:
/// the standard containers accept an incomplete element type, std::pair does not.)
struct JsonMember {
  std::string key;
  JsonValue value;
};

inline const JsonValue* JsonValue::find(std::string_view key) const {
  const JsonValue* hit = nullptr;
  for (const auto& m : object) {
    if (m.key == key) hit = &m.value;
  }
  return hit;
}

struct JsonParseOptions {
  bool allow_non_finite = true;        ///< accept Infinity, -Infinity, NaN
  bool repair_stray_closers = false;   ///< skip an unmatched ']' or '}' (with a warning)
  int max_depth = 64;
};

struct JsonDocument {
  std::string name;                    ///< file name used in messages
  JsonValue root;
  std::vector<std::string> warnings;   ///< "<file>:<line>:<col>: warning: ..."

  /// "<name>:<line>:<col>: error: <what>" for a value of this document.
  [[noreturn]] void fail(const JsonValue& at, const std::string& what) const {
    throw DatasetError(name + ":" + std::to_string(at.line) + ":" + std::to_string(at.column) +
                       ": error: " + what);
  }
  const JsonValue& member(std::string_view key) const {
    if (!root.isObject()) fail(root, "expected a JSON object at the top level");
    const JsonValue* v = root.find(key);
    if (v == nullptr) fail(root, "missing key \"" + std::string(key) + "\"");
    return *v;
  }
  bool has(std::string_view key) const { return root.isObject() && root.find(key) != nullptr; }
  double number(std::string_view key) const {
    const JsonValue& v = member(key);
    if (!v.isNumber()) fail(v, "\"" + std::string(key) + "\" must be a number");
    return v.number;
  }
  bool boolean(std::string_view key) const {
    const JsonValue& v = member(key);
    if (!v.isBool()) fail(v, "\"" + std::string(key) + "\" must be true or false");
    return v.boolean;
  }
  std::string string(std::string_view key) const {
    const JsonValue& v = member(key);
    if (!v.isString()) fail(v, "\"" + std::string(key) + "\" must be a string");
    return v.string;
  }

  // Typed access to any value of this document; a mismatch throws DatasetError naming
  // "<name>:<line>:<col>" of the value and `what` (e.g. "bbox[0]").
  const JsonValue& at(const JsonValue& obj, std::string_view key) const {
    if (!obj.isObject()) fail(obj, "expected a JSON object");
    const JsonValue* v = obj.find(key);
    if (v == nullptr) fail(obj, "missing key \"" + std::string(key) + "\"");
    return *v;
  }
  bool asBool(const JsonValue& v, std::string_view what) const {
    if (!v.isBool()) fail(v, "\"" + std::string(what) + "\" must be true or false");
    return v.boolean;
  }
  double asNumber(const JsonValue& v, std::string_view what) const {
    if (!v.isNumber()) fail(v, "\"" + std::string(what) + "\" must be a number");
    return v.number;
  }
  /// A number that is an exact integer in int range.
  int asInt(const JsonValue& v, std::string_view what) const {
    const double x = asNumber(v, what);
    if (!(x >= static_cast<double>(std::numeric_limits<int>::min()) &&
          x <= static_cast<double>(std::numeric_limits<int>::max()) && std::floor(x) == x)) {
      fail(v, "\"" + std::string(what) + "\" must be an integer");
    }
    return static_cast<int>(x);
  }
  const std::string& asString(const JsonValue& v, std::string_view what) const {
    if (!v.isString()) fail(v, "\"" + std::string(what) + "\" must be a string");
    return v.string;
  }
  const std::vector<JsonValue>& asArray(const JsonValue& v, std::string_view what) const {
    if (!v.isArray()) fail(v, "\"" + std::string(what) + "\" must be an array");
    return v.array;
  }

  /// An array of numbers; expected_size < 0: any size.
  std::vector<double> numbers(std::string_view key, int expected_size = -1) const {
    const JsonValue& v = member(key);
    if (!v.isArray()) fail(v, "\"" + std::string(key) + "\" must be an array of numbers");
    if (expected_size >= 0 && v.array.size() != static_cast<std::size_t>(expected_size)) {
      fail(v, "\"" + std::string(key) + "\" must have " + std::to_string(expected_size) +
                  " elements, has " + std::to_string(v.array.size()));
    }
    std::vector<double> out;
    for (const auto& e : v.array) {
      if (!e.isNumber()) fail(e, "\"" + std::string(key) + "\" must contain numbers only");
      out.push_back(e.number);
    }
    return out;
  }
};

namespace detail {

inline bool jsonSpace(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

// "<name>:<line>:<col>" of a byte offset into text (1-based line and column, in bytes).
inline std::string jsonWhere(std::string_view text, std::size_t offset, const std::string& name) {
  int line = 1, col = 1;
  for (std::size_t i = 0; i < offset && i < text.size(); ++i) {
    if (text[i] == '\n') ++line, col = 1;
    else ++col;
  }
  return name + ":" + std::to_string(line) + ":" + std::to_string(col);
}

// The known quirk of the shared data (env_params.json ends "225]]}"): a closing bracket that
// does not match the open container is blanked out (a space, so that positions stay) and
// reported as a warning. Strings are skipped, escapes included.
inline void blankStrayClosers(std::string& text, const std::string& name, std::vector<std::string>& warnings) {
  std::vector<char> open;
  bool in_string = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\') ++i;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      open.push_back(c == '[' ? ']' : '}');
    } else if (c == ']' || c == '}') {
      if (!open.empty() && open.back() == c) {
        open.pop_back();
      } else {
        warnings.push_back(jsonWhere(text, i, name) + ": warning: ignored stray '" + c + "'");
        text[i] = ' ';
      }
    }
  }
}

// RapidJSON reads the text through this stream, which remembers where the last value began:
// the first non-space byte after the start or a ',', ':', '[' or '{'.
struct JsonTrackingStream {
  using Ch = char;
  explicit JsonTrackingStream(const char* text) : head(text), p(text) {}
  Ch Peek() const { return *p; }
  Ch Take() {
    const char c = *p;
    if (expect_value && !jsonSpace(c)) {
      value_start = Tell();
      expect_value = false;
    }
    if (c == ',' || c == ':' || c == '[' || c == '{') expect_value = true;
    ++p;
    return c;
  }
  std::size_t Tell() const { return static_cast<std::size_t>(p - head); }
  // Output (in-situ parsing only): not used.
  Ch* PutBegin() { return nullptr; }
  void Put(Ch) {}
  void Flush() {}
  std::size_t PutEnd(Ch*) { return 0; }

  const char* head;
  const char* p;
  std::size_t value_start = 0;
  bool expect_value = true;
};

// Builds the JsonValue tree from RapidJSON's events; stops (returns false) with `error` set
// for what RapidJSON accepts and the project does not.
class JsonTreeBuilder : public rapidjson::BaseReaderHandler<rapidjson::UTF8<>, JsonTreeBuilder> {
 public:
  JsonTreeBuilder(const JsonTrackingStream& in, std::string_view text, const JsonParseOptions& opt)
      : in_(in), text_(text), opt_(opt) {}

  bool Null() { return add(JsonValue{}); }
  bool Bool(bool b) {
    JsonValue v;
    v.type = JsonValue::Type::boolean;
    v.boolean = b;
    return add(std::move(v));
  }
  bool Int(int i) { return Double(i); }
  bool Uint(unsigned u) { return Double(u); }
  bool Int64(std::int64_t i) { return Double(static_cast<double>(i)); }
  bool Uint64(std::uint64_t u) { return Double(static_cast<double>(u)); }
  bool Double(double d) {
    if (!std::isfinite(d)) {
      // Python's json writes exactly NaN, Infinity and -Infinity; RapidJSON also takes
      // -NaN, Inf and -Inf.
      std::size_t end = in_.value_start;
      while (end < text_.size() && (text_[end] == '-' || std::isalpha(static_cast<unsigned char>(text_[end])))) ++end;
      const std::string_view token = text_.substr(in_.value_start, end - in_.value_start);
      if (!opt_.allow_non_finite) return stop("'" + std::string(token) + "' is not a JSON number");
      if (token != "NaN" && token != "Infinity" && token != "-Infinity")
        return stop("'" + std::string(token) + "' is not a number (non-finite values: NaN, Infinity, -Infinity)");
    }
    JsonValue v;
    v.type = JsonValue::Type::number;
    v.number = d;
    return add(std::move(v));
  }
  bool String(const char* str, rapidjson::SizeType length, bool) {
    JsonValue v;
    v.type = JsonValue::Type::string;
    v.string.assign(str, length);
    return add(std::move(v));
  }
  bool StartObject() { return open(JsonValue::Type::object); }
  bool Key(const char* str, rapidjson::SizeType length, bool) {
    key_.assign(str, length);
    return true;
  }
  bool EndObject(rapidjson::SizeType) { return close(); }
  bool StartArray() { return open(JsonValue::Type::array); }
  bool EndArray(rapidjson::SizeType) { return close(); }

  JsonValue root;
  std::string error;               // why the builder stopped
  std::size_t error_offset = 0;    // where

 private:
  bool stop(std::string what) {
    error = std::move(what);
    error_offset = in_.value_start;
    return false;
  }
  JsonValue located(JsonValue v) {
    int line = 1, col = 1;
    for (std::size_t i = line_offset_; i < in_.value_start; ++i) {
      if (text_[i] == '\n') ++line, col = 1;
      else ++col;
    }
    line_ += line - 1;
    column_ = line > 1 ? col : column_ + col - 1;
    line_offset_ = in_.value_start;
    v.line = line_;
    v.column = column_;
    return v;
  }
  // Places a finished value in its parent (or as the root).
  bool add(JsonValue v) {
    v = located(std::move(v));
    if (stack_.empty()) {
      root = std::move(v);
    } else if (stack_.back()->isArray()) {
      stack_.back()->array.push_back(std::move(v));
    } else {
      stack_.back()->object.push_back({key_, std::move(v)});
    }
    return true;
  }
  bool open(JsonValue::Type type) {
    if (static_cast<int>(stack_.size()) >= opt_.max_depth)
      return stop("nesting deeper than " + std::to_string(opt_.max_depth));
    JsonValue v;
    v.type = type;
    add(std::move(v));
    JsonValue* self = stack_.empty() ? &root
                      : stack_.back()->isArray() ? &stack_.back()->array.back()
                                                 : &stack_.back()->object.back().value;
    stack_.push_back(self);
    return true;
  }
  bool close() {
    stack_.pop_back();
    return true;
  }

  const JsonTrackingStream& in_;
  std::string_view text_;
  JsonParseOptions opt_;
  std::string key_;
  std::vector<JsonValue*> stack_;  // open containers (their vectors are not resized while open)
  std::size_t line_offset_ = 0;  // the last value's start, and its line and column
  int line_ = 1, column_ = 1;
};

}  // namespace detail

/// Parse text; `name` is used in messages. Throws DatasetError.
inline JsonDocument parseJson(std::string_view text, const std::string& name,
                              const JsonParseOptions& opt = {}) {
  JsonDocument doc;
  doc.name = name;
  std::string buf(text);  // NUL-terminated for RapidJSON, and repairable
  if (buf.compare(0, 3, "\xEF\xBB\xBF") == 0) buf.replace(0, 3, "   ");  // UTF-8 byte-order mark
  if (opt.repair_stray_closers) detail::blankStrayClosers(buf, name, doc.warnings);
  detail::JsonTrackingStream in(buf.c_str());
  detail::JsonTreeBuilder builder(in, buf, opt);
  rapidjson::Reader reader;
  // Recursive (not iterative) parsing: it calls StartObject/StartArray after taking the
  // bracket, so the stream knows where the container began; the builder's depth limit bounds
  // the recursion.
  constexpr unsigned flags =
      rapidjson::kParseNanAndInfFlag | rapidjson::kParseFullPrecisionFlag | rapidjson::kParseValidateEncodingFlag;
  const rapidjson::ParseResult r = reader.Parse<flags>(in, builder);
  if (!builder.error.empty())
    throw DatasetError(detail::jsonWhere(buf, builder.error_offset, name) + ": error: " + builder.error);
  if (r.IsError()) {
    std::size_t at = r.Offset();
    std::string what = rapidjson::GetParseError_En(r.Code());
    if (r.Code() == rapidjson::kParseErrorValueInvalid) {
      at = in.value_start;  // the start of the bad token, not where reading it stopped
      std::size_t end = at;
      while (end < buf.size() && !detail::jsonSpace(buf[end]) && buf[end] != ',' && buf[end] != ']' && buf[end] != '}')
        ++end;
      what += " ('" + buf.substr(at, end - at) + "')";
    } else if (r.Code() == rapidjson::kParseErrorStringEscapeInvalid && at < buf.size() &&
               static_cast<unsigned char>(buf[at]) < 0x20) {
      what = "a control character in a string (an unterminated string?)";
    }
    throw DatasetError(detail::jsonWhere(buf, at, name) + ": error: " + what);
  }
  doc.root = std::move(builder.root);
  return doc;
}

inline std::string readTextFile(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw DatasetError(path + ": error: cannot open file for reading");
  std::ostringstream ss;
  ss << f.rdbuf();
  if (f.bad()) throw DatasetError(path + ": error: read failed");
  return ss.str();
}

/// Read and parse a JSON file; messages name `path`.
inline JsonDocument readJsonFile(const std::string& path, const JsonParseOptions& opt = {}) {
  return parseJson(readTextFile(path), path, opt);
}

// ---- writing ------------------------------------------------------------------------------

/// Shortest decimal that reads back to the same double; non-finite → "null" (valid JSON).
inline std::string jsonNumber(double x) {
  if (!std::isfinite(x)) return "null";
  if (x == 0) return "0";  // also -0
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, x);
  return std::string(buf, r.ptr);
}

inline std::string jsonString(std::string_view s) {
  std::string out = "\"";
  for (const char c : s) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          const char* hex = "0123456789abcdef";
          out += "\\u00";
          out += hex[(c >> 4) & 0xF];
          out += hex[c & 0xF];
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

/// A flat JSON object written on one line, like Python's json.dump: {"a": 1, "b": [1, 2]}.
class JsonObjectWriter {
 public:
  JsonObjectWriter& field(std::string_view key, double v) { return raw(key, jsonNumber(v)); }
  JsonObjectWriter& field(std::string_view key, int v) { return raw(key, std::to_string(v)); }
  JsonObjectWriter& field(std::string_view key, long long v) { return raw(key, std::to_string(v)); }
  JsonObjectWriter& field(std::string_view key, unsigned long long v) { return raw(key, std::to_string(v)); }
  JsonObjectWriter& field(std::string_view key, bool v) { return raw(key, v ? "true" : "false"); }
  JsonObjectWriter& field(std::string_view key, const char* v) { return raw(key, jsonString(v)); }
  JsonObjectWriter& field(std::string_view key, const std::string& v) { return raw(key, jsonString(v)); }
  JsonObjectWriter& field(std::string_view key, const std::vector<double>& v) {
    std::string a = "[";
    for (std::size_t i = 0; i < v.size(); ++i) a += (i ? ", " : "") + jsonNumber(v[i]);
    return raw(key, a + "]");
  }
  JsonObjectWriter& raw(std::string_view key, const std::string& json_value) {
    body_ += (body_.empty() ? "" : ", ") + jsonString(key) + ": " + json_value;
    return *this;
  }
  std::string str() const { return "{" + body_ + "}"; }

 private:
  std::string body_;
};

}  // namespace lieservo::dataset
