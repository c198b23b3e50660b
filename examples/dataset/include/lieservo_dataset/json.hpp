// lieservo_dataset/json.hpp — the project's one JSON reader/writer (header-only, no OpenCV): the
// data set's parameter files, lieservo_collect's output and the ONNX model cards.
//
// Reads standard JSON plus the Python json module's non-standard literals Infinity,
// -Infinity and NaN (the shared meta.json uses them). With JsonParseOptions::repair_stray_closers
// a closing bracket that does not match the open container (the shared env_params.json ends
// "225]]}") is skipped with a warning instead of failing. Every error and warning names the
// file, line and column: "<file>:<line>:<col>: error: <what>".
//
// Writes valid JSON only: non-finite numbers are written as null (JSON has no Infinity),
// numbers in shortest round-trip form.
#pragma once

#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

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

class JsonParser {
 public:
  JsonParser(std::string_view text, std::string name, const JsonParseOptions& opt)
      : s_(text), opt_(opt) {
    doc_.name = std::move(name);
  }

  JsonDocument parse() {
    skipSpace();
    if (pos_ == 0 && s_.substr(0, 3) == "\xEF\xBB\xBF") {  // UTF-8 byte-order mark
      advance(3);
      skipSpace();
    }
    doc_.root = value(0);
    skipSpace();
    while (pos_ < s_.size()) {
      const char c = s_[pos_];
      if ((c == ']' || c == '}') && opt_.repair_stray_closers) {
        warn(std::string("ignored stray '") + c + "' after the top-level value");
        advance(1);
        skipSpace();
        continue;
      }
      error(std::string("unexpected ") + describe(c) + " after the top-level value");
    }
    return std::move(doc_);
  }

 private:
  std::string_view s_;
  JsonParseOptions opt_;
  JsonDocument doc_;
  std::size_t pos_ = 0;
  int line_ = 1, col_ = 1;

  static std::string describe(char c) {
    if (c == '\0') return "NUL byte";
    if (static_cast<unsigned char>(c) < 0x20) return "control character";
    return std::string("'") + c + "'";
  }
  [[noreturn]] void error(const std::string& what) const {
    throw DatasetError(doc_.name + ":" + std::to_string(line_) + ":" + std::to_string(col_) +
                       ": error: " + what);
  }
  void warn(const std::string& what) {
    doc_.warnings.push_back(doc_.name + ":" + std::to_string(line_) + ":" + std::to_string(col_) +
                            ": warning: " + what);
  }
  void advance(std::size_t n) {
    for (std::size_t i = 0; i < n && pos_ < s_.size(); ++i, ++pos_) {
      if (s_[pos_] == '\n') {
        ++line_;
        col_ = 1;
      } else {
        ++col_;
      }
    }
  }
  void skipSpace() {
    while (pos_ < s_.size() &&
           (s_[pos_] == ' ' || s_[pos_] == '\t' || s_[pos_] == '\n' || s_[pos_] == '\r')) {
      advance(1);
    }
  }
  bool startsWith(std::string_view w) const { return s_.substr(pos_, w.size()) == w; }

  JsonValue value(int depth) {
    if (depth > opt_.max_depth) error("nesting deeper than " + std::to_string(opt_.max_depth));
    skipSpace();
    if (pos_ >= s_.size()) error("unexpected end of file, expected a value");
    JsonValue v;
    v.line = line_;
    v.column = col_;
    const char c = s_[pos_];
    if (c == '{') {
      v.type = JsonValue::Type::object;
      object(v, depth);
    } else if (c == '[') {
      v.type = JsonValue::Type::array;
      array(v, depth);
    } else if (c == '"') {
      v.type = JsonValue::Type::string;
      v.string = stringLiteral();
    } else if (startsWith("true")) {
      v.type = JsonValue::Type::boolean;
      v.boolean = true;
      advance(4);
    } else if (startsWith("false")) {
      v.type = JsonValue::Type::boolean;
      advance(5);
    } else if (startsWith("null")) {
      advance(4);
    } else {
      v.type = JsonValue::Type::number;
      v.number = numberLiteral();
    }
    return v;
  }

  // After a member/element: ',' continues, `close` ends; a mismatched closer may be skipped.
  bool separatorOrClose(char close, const char* what) {
    for (;;) {
      skipSpace();
      if (pos_ >= s_.size()) error(std::string("unexpected end of file in ") + what + ", expected ',' or '" + close + "'");
      const char c = s_[pos_];
      if (c == ',') {
        advance(1);
        return true;
      }
      if (c == close) {
        advance(1);
        return false;
      }
      const char other = close == ']' ? '}' : ']';
      if (c == other && opt_.repair_stray_closers) {
        warn(std::string("ignored stray '") + c + "' in " + what);
        advance(1);
        continue;
      }
      error(std::string("expected ',' or '") + close + "' in " + what + ", got " + describe(c));
    }
  }

  void object(JsonValue& v, int depth) {
    advance(1);  // '{'
    skipSpace();
    if (pos_ < s_.size() && s_[pos_] == '}') {
      advance(1);
      return;
    }
    for (;;) {
      skipSpace();
      if (pos_ >= s_.size()) error("unexpected end of file in an object, expected a key");
      if (s_[pos_] != '"') error("expected a string key in an object, got " + describe(s_[pos_]));
      std::string key = stringLiteral();
      skipSpace();
      if (pos_ >= s_.size() || s_[pos_] != ':') error("expected ':' after key \"" + key + "\"");
      advance(1);
      JsonValue member = value(depth + 1);
      v.object.push_back(JsonMember{std::move(key), std::move(member)});
      if (!separatorOrClose('}', "an object")) return;
    }
  }

  void array(JsonValue& v, int depth) {
    advance(1);  // '['
    skipSpace();
    if (pos_ < s_.size() && s_[pos_] == ']') {
      advance(1);
      return;
    }
    for (;;) {
      v.array.push_back(value(depth + 1));
      if (!separatorOrClose(']', "an array")) return;
    }
  }

  static void appendUtf8(std::string& out, unsigned cp) {
    if (cp < 0x80) {
      out += static_cast<char>(cp);
    } else if (cp < 0x800) {
      out += static_cast<char>(0xC0 | (cp >> 6));
      out += static_cast<char>(0x80 | (cp & 0x3F));
    } else if (cp < 0x10000) {
      out += static_cast<char>(0xE0 | (cp >> 12));
      out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (cp & 0x3F));
    } else {
      out += static_cast<char>(0xF0 | (cp >> 18));
      out += static_cast<char>(0x80 | ((cp >> 12) & 0x3F));
      out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (cp & 0x3F));
    }
  }

  unsigned hex4() {
    if (pos_ + 4 > s_.size()) error("truncated \\u escape");
    unsigned cp = 0;
    for (int i = 0; i < 4; ++i) {
      const char h = s_[pos_];
      cp <<= 4;
      if (h >= '0' && h <= '9') cp |= static_cast<unsigned>(h - '0');
      else if (h >= 'a' && h <= 'f') cp |= static_cast<unsigned>(h - 'a' + 10);
      else if (h >= 'A' && h <= 'F') cp |= static_cast<unsigned>(h - 'A' + 10);
      else error("invalid hex digit in \\u escape");
      advance(1);
    }
    return cp;
  }

  std::string stringLiteral() {
    advance(1);  // '"'
    std::string out;
    for (;;) {
      if (pos_ >= s_.size() || s_[pos_] == '\n') error("unterminated string");
      const char c = s_[pos_];
      if (c == '"') {
        advance(1);
        return out;
      }
      if (static_cast<unsigned char>(c) < 0x20) error("control character in a string");
      if (c != '\\') {
        out += c;
        advance(1);
        continue;
      }
      advance(1);
      if (pos_ >= s_.size()) error("unterminated escape");
      const char e = s_[pos_];
      switch (e) {
        case '"': out += '"'; break;
        case '\\': out += '\\'; break;
        case '/': out += '/'; break;
        case 'b': out += '\b'; break;
        case 'f': out += '\f'; break;
        case 'n': out += '\n'; break;
        case 'r': out += '\r'; break;
        case 't': out += '\t'; break;
        case 'u': {
          advance(1);
          unsigned cp = hex4();
          if (cp >= 0xD800 && cp < 0xDC00 && startsWith("\\u")) {
            advance(2);
            const unsigned lo = hex4();
            if (lo >= 0xDC00 && lo < 0xE000) cp = 0x10000 + ((cp - 0xD800) << 10) + (lo - 0xDC00);
            else error("invalid surrogate pair");
          }
          appendUtf8(out, cp);
          continue;
        }
        default: error(std::string("invalid escape '\\") + e + "'");
      }
      advance(1);
    }
  }

  double numberLiteral() {
    const bool neg = s_[pos_] == '-';
    const std::size_t start = pos_ + (neg ? 1 : 0);
    const std::string_view rest = s_.substr(start);
    if (rest.substr(0, 8) == "Infinity" || rest.substr(0, 3) == "NaN") {
      const bool inf = rest[0] == 'I';
      if (!opt_.allow_non_finite) error(std::string("non-finite literal '") + (inf ? "Infinity" : "NaN") + "' not allowed");
      if (!inf && neg) error("'-NaN' is not a valid literal");
      advance((neg ? 1 : 0) + (inf ? 8 : 3));
      const double x = inf ? std::numeric_limits<double>::infinity() : std::numeric_limits<double>::quiet_NaN();
      return neg ? -x : x;
    }
    // JSON grammar: -?(0|[1-9][0-9]*)(\.[0-9]+)?([eE][+-]?[0-9]+)?
    std::size_t i = start;
    auto digits = [&](std::size_t& k) {
      const std::size_t k0 = k;
      while (k < s_.size() && s_[k] >= '0' && s_[k] <= '9') ++k;
      return k - k0;
    };
    bool ok = true;
    if (i < s_.size() && s_[i] == '0') ++i;
    else ok = digits(i) > 0;
    if (ok && i < s_.size() && s_[i] == '.') {
      ++i;
      ok = digits(i) > 0;
    }
    if (ok && i < s_.size() && (s_[i] == 'e' || s_[i] == 'E')) {
      ++i;
      if (i < s_.size() && (s_[i] == '+' || s_[i] == '-')) ++i;
      ok = digits(i) > 0;
    }
    if (!ok || i == start) {
      std::size_t j = pos_;
      while (j < s_.size() && j < pos_ + 20 && s_[j] != ',' && s_[j] != ']' && s_[j] != '}' &&
             s_[j] != '\n' && s_[j] != ' ')
        ++j;
      error("invalid value '" + std::string(s_.substr(pos_, j - pos_)) + "'");
    }
    double x = 0;
    const auto r = std::from_chars(s_.data() + pos_, s_.data() + i, x);
    if (r.ec == std::errc::result_out_of_range) {
      // from_chars leaves x unchanged on overflow/underflow; Python gives ±inf / 0.
      x = std::strtod(std::string(s_.substr(pos_, i - pos_)).c_str(), nullptr);
    } else if (r.ec != std::errc() || r.ptr != s_.data() + i) {
      error("invalid number '" + std::string(s_.substr(pos_, i - pos_)) + "'");
    }
    advance(i - pos_);
    return x;
  }
};

}  // namespace detail

/// Parse text; `name` is used in messages. Throws DatasetError.
inline JsonDocument parseJson(std::string_view text, const std::string& name,
                              const JsonParseOptions& opt = {}) {
  return detail::JsonParser(text, name, opt).parse();
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
