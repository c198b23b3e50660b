#include "lieservo_adapters/json.hpp"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace lieservo::adapters {

JsonValue JsonValue::makeBool(bool b) {
  JsonValue v;
  v.type_ = Type::boolean;
  v.b_ = b;
  return v;
}
JsonValue JsonValue::makeNumber(double d) {
  JsonValue v;
  v.type_ = Type::number;
  v.d_ = d;
  return v;
}
JsonValue JsonValue::makeString(std::string s) {
  JsonValue v;
  v.type_ = Type::string;
  v.s_ = std::move(s);
  return v;
}
JsonValue JsonValue::makeArray(std::vector<JsonValue> a) {
  JsonValue v;
  v.type_ = Type::array;
  v.a_ = std::move(a);
  return v;
}
JsonValue JsonValue::makeObject(std::vector<std::pair<std::string, JsonValue>> o) {
  JsonValue v;
  v.type_ = Type::object;
  v.o_ = std::move(o);
  return v;
}

namespace {
const char* typeName(JsonValue::Type t) {
  switch (t) {
    case JsonValue::Type::null: return "null";
    case JsonValue::Type::boolean: return "a boolean";
    case JsonValue::Type::number: return "a number";
    case JsonValue::Type::string: return "a string";
    case JsonValue::Type::array: return "an array";
    case JsonValue::Type::object: return "an object";
  }
  return "?";
}
[[noreturn]] void typeError(const std::string& what, const char* expected, JsonValue::Type got) {
  throw std::runtime_error("JSON: " + what + " should be " + expected + " but is " + typeName(got));
}
}  // namespace

bool JsonValue::asBool(const std::string& what) const {
  if (type_ != Type::boolean) typeError(what, "a boolean", type_);
  return b_;
}
double JsonValue::asNumber(const std::string& what) const {
  if (type_ != Type::number) typeError(what, "a number", type_);
  return d_;
}
int JsonValue::asInt(const std::string& what) const {
  const double d = asNumber(what);
  if (!std::isfinite(d) || d != std::floor(d) || std::fabs(d) > 2.0e9) {
    std::ostringstream os;
    os << "JSON: " << what << " should be an integer but is " << d;
    throw std::runtime_error(os.str());
  }
  return static_cast<int>(d);
}
const std::string& JsonValue::asString(const std::string& what) const {
  if (type_ != Type::string) typeError(what, "a string", type_);
  return s_;
}
const std::vector<JsonValue>& JsonValue::asArray(const std::string& what) const {
  if (type_ != Type::array) typeError(what, "an array", type_);
  return a_;
}
std::vector<double> JsonValue::asNumberArray(const std::string& what) const {
  const auto& a = asArray(what);
  std::vector<double> out;
  out.reserve(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) out.push_back(a[i].asNumber(what + "[" + std::to_string(i) + "]"));
  return out;
}
const std::vector<std::pair<std::string, JsonValue>>& JsonValue::asObject(const std::string& what) const {
  if (type_ != Type::object) typeError(what, "an object", type_);
  return o_;
}
const JsonValue* JsonValue::find(const std::string& key) const noexcept {
  if (type_ != Type::object) return nullptr;
  for (const auto& kv : o_)
    if (kv.first == key) return &kv.second;
  return nullptr;
}
const JsonValue& JsonValue::at(const std::string& key) const {
  if (type_ != Type::object) typeError("container of \"" + key + "\"", "an object", type_);
  const JsonValue* v = find(key);
  if (v == nullptr) throw std::runtime_error("JSON: missing key \"" + key + "\"");
  return *v;
}

namespace {

class Parser {
 public:
  Parser(const std::string& text, const std::string& source) : t_(text), src_(source) {}

  JsonValue parseDocument() {
    skipWs();
    JsonValue v = parseValue(0);
    skipWs();
    if (p_ != t_.size()) fail("unexpected trailing characters");
    return v;
  }

 private:
  static constexpr int kMaxDepth = 64;

  [[noreturn]] void fail(const std::string& msg) const {
    std::size_t line = 1, col = 1;
    for (std::size_t i = 0; i < p_ && i < t_.size(); ++i) {
      if (t_[i] == '\n') {
        ++line;
        col = 1;
      } else {
        ++col;
      }
    }
    std::ostringstream os;
    os << src_ << ":" << line << ":" << col << " (offset " << p_ << "): malformed JSON: " << msg;
    throw std::runtime_error(os.str());
  }

  void skipWs() {
    while (p_ < t_.size() && (t_[p_] == ' ' || t_[p_] == '\t' || t_[p_] == '\n' || t_[p_] == '\r')) ++p_;
  }
  bool consumeWord(const char* w) {
    std::size_t n = 0;
    while (w[n] != '\0') ++n;
    if (t_.compare(p_, n, w) == 0) {
      p_ += n;
      return true;
    }
    return false;
  }

  JsonValue parseValue(int depth) {
    if (depth > kMaxDepth) fail("nesting too deep");
    if (p_ >= t_.size()) fail("unexpected end of input, expected a value");
    const char c = t_[p_];
    if (c == '{') return parseObject(depth);
    if (c == '[') return parseArray(depth);
    if (c == '"') return JsonValue::makeString(parseString());
    if (consumeWord("true")) return JsonValue::makeBool(true);
    if (consumeWord("false")) return JsonValue::makeBool(false);
    if (consumeWord("null")) return JsonValue();
    // Python's json module extensions.
    if (consumeWord("Infinity")) return JsonValue::makeNumber(std::numeric_limits<double>::infinity());
    if (consumeWord("-Infinity")) return JsonValue::makeNumber(-std::numeric_limits<double>::infinity());
    if (consumeWord("NaN")) return JsonValue::makeNumber(std::numeric_limits<double>::quiet_NaN());
    if (c == '-' || (c >= '0' && c <= '9')) return parseNumber();
    fail(std::string("unexpected character '") + c + "'");
  }

  JsonValue parseNumber() {
    const std::size_t start = p_;
    if (t_[p_] == '-') ++p_;
    auto digits = [&] {
      const std::size_t s = p_;
      while (p_ < t_.size() && t_[p_] >= '0' && t_[p_] <= '9') ++p_;
      return p_ > s;
    };
    if (!digits()) fail("expected digits in a number");
    if (p_ < t_.size() && t_[p_] == '.') {
      ++p_;
      if (!digits()) fail("expected digits after the decimal point");
    }
    if (p_ < t_.size() && (t_[p_] == 'e' || t_[p_] == 'E')) {
      ++p_;
      if (p_ < t_.size() && (t_[p_] == '+' || t_[p_] == '-')) ++p_;
      if (!digits()) fail("expected digits in the exponent");
    }
    const std::string s = t_.substr(start, p_ - start);
    char* end = nullptr;
    const double d = std::strtod(s.c_str(), &end);
    if (end == nullptr || *end != '\0') fail("bad number '" + s + "'");
    return JsonValue::makeNumber(d);
  }

  std::string parseString() {
    ++p_;  // opening quote
    std::string out;
    while (true) {
      if (p_ >= t_.size()) fail("unterminated string");
      const char c = t_[p_++];
      if (c == '"') break;
      if (static_cast<unsigned char>(c) < 0x20) fail("control character in a string");
      if (c != '\\') {
        out.push_back(c);
        continue;
      }
      if (p_ >= t_.size()) fail("unterminated escape");
      const char e = t_[p_++];
      switch (e) {
        case '"': out.push_back('"'); break;
        case '\\': out.push_back('\\'); break;
        case '/': out.push_back('/'); break;
        case 'b': out.push_back('\b'); break;
        case 'f': out.push_back('\f'); break;
        case 'n': out.push_back('\n'); break;
        case 'r': out.push_back('\r'); break;
        case 't': out.push_back('\t'); break;
        case 'u': {
          if (p_ + 4 > t_.size()) fail("short \\u escape");
          unsigned code = 0;
          for (int i = 0; i < 4; ++i) {
            const char h = t_[p_++];
            code <<= 4;
            if (h >= '0' && h <= '9') code |= static_cast<unsigned>(h - '0');
            else if (h >= 'a' && h <= 'f') code |= static_cast<unsigned>(h - 'a' + 10);
            else if (h >= 'A' && h <= 'F') code |= static_cast<unsigned>(h - 'A' + 10);
            else fail("bad hex digit in \\u escape");
          }
          // UTF-8 encode (basic multilingual plane; surrogates kept as-is).
          if (code < 0x80) {
            out.push_back(static_cast<char>(code));
          } else if (code < 0x800) {
            out.push_back(static_cast<char>(0xC0 | (code >> 6)));
            out.push_back(static_cast<char>(0x80 | (code & 0x3F)));
          } else {
            out.push_back(static_cast<char>(0xE0 | (code >> 12)));
            out.push_back(static_cast<char>(0x80 | ((code >> 6) & 0x3F)));
            out.push_back(static_cast<char>(0x80 | (code & 0x3F)));
          }
          break;
        }
        default: fail(std::string("bad escape '\\") + e + "'");
      }
    }
    return out;
  }

  JsonValue parseArray(int depth) {
    ++p_;
    std::vector<JsonValue> a;
    skipWs();
    if (p_ < t_.size() && t_[p_] == ']') {
      ++p_;
      return JsonValue::makeArray(std::move(a));
    }
    while (true) {
      skipWs();
      a.push_back(parseValue(depth + 1));
      skipWs();
      if (p_ >= t_.size()) fail("unterminated array, expected ',' or ']'");
      if (t_[p_] == ',') {
        ++p_;
        continue;
      }
      if (t_[p_] == ']') {
        ++p_;
        break;
      }
      fail("expected ',' or ']' in an array");
    }
    return JsonValue::makeArray(std::move(a));
  }

  JsonValue parseObject(int depth) {
    ++p_;
    std::vector<std::pair<std::string, JsonValue>> o;
    skipWs();
    if (p_ < t_.size() && t_[p_] == '}') {
      ++p_;
      return JsonValue::makeObject(std::move(o));
    }
    while (true) {
      skipWs();
      if (p_ >= t_.size() || t_[p_] != '"') fail("expected a string key in an object");
      std::string key = parseString();
      skipWs();
      if (p_ >= t_.size() || t_[p_] != ':') fail("expected ':' after key \"" + key + "\"");
      ++p_;
      skipWs();
      JsonValue v = parseValue(depth + 1);
      o.emplace_back(std::move(key), std::move(v));
      skipWs();
      if (p_ >= t_.size()) fail("unterminated object, expected ',' or '}'");
      if (t_[p_] == ',') {
        ++p_;
        continue;
      }
      if (t_[p_] == '}') {
        ++p_;
        break;
      }
      fail("expected ',' or '}' in an object");
    }
    return JsonValue::makeObject(std::move(o));
  }

  const std::string& t_;
  const std::string& src_;
  std::size_t p_ = 0;
};

}  // namespace

JsonValue parseJson(const std::string& text, const std::string& source) {
  return Parser(text, source).parseDocument();
}

JsonValue readJsonFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot open JSON file");
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw std::runtime_error(path + ": error while reading JSON file");
  return parseJson(ss.str(), path);
}

}  // namespace lieservo::adapters
