// lieservo_adapters/json.hpp — a small, tolerant JSON reader for the data set's
// parameter files and the model cards.
//
// Why not cv::FileStorage: the data set's JSON files are written by Python's
// json module, which emits the non-standard literals Infinity, -Infinity and NaN
// (e.g. meta.json: "z_shear_rng": [-Infinity, -Infinity]); FileStorage
// rejects them. This reader accepts standard JSON plus those three literals.
// Malformed input throws std::runtime_error naming the source, line and column.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace lieservo::adapters {

class JsonValue {
 public:
  enum class Type { null, boolean, number, string, array, object };

  JsonValue() = default;
  static JsonValue makeBool(bool b);
  static JsonValue makeNumber(double d);
  static JsonValue makeString(std::string s);
  static JsonValue makeArray(std::vector<JsonValue> a);
  static JsonValue makeObject(std::vector<std::pair<std::string, JsonValue>> o);

  Type type() const noexcept { return type_; }
  bool isNull() const noexcept { return type_ == Type::null; }
  bool isBool() const noexcept { return type_ == Type::boolean; }
  bool isNumber() const noexcept { return type_ == Type::number; }
  bool isString() const noexcept { return type_ == Type::string; }
  bool isArray() const noexcept { return type_ == Type::array; }
  bool isObject() const noexcept { return type_ == Type::object; }

  // Accessors throw std::runtime_error naming `what` when the type differs.
  bool asBool(const std::string& what = "value") const;
  double asNumber(const std::string& what = "value") const;
  int asInt(const std::string& what = "value") const;  ///< a number that is an exact integer
  const std::string& asString(const std::string& what = "value") const;
  const std::vector<JsonValue>& asArray(const std::string& what = "value") const;
  std::vector<double> asNumberArray(const std::string& what = "value") const;
  const std::vector<std::pair<std::string, JsonValue>>& asObject(const std::string& what = "value") const;

  /// Object member or nullptr (first match, in file order).
  const JsonValue* find(const std::string& key) const noexcept;
  /// Object member; throws std::runtime_error naming the key when absent.
  const JsonValue& at(const std::string& key) const;

 private:
  Type type_ = Type::null;
  bool b_ = false;
  double d_ = 0.0;
  std::string s_;
  std::vector<JsonValue> a_;
  std::vector<std::pair<std::string, JsonValue>> o_;
};

/// Parses `text`; `source` names it in error messages (a file name).
JsonValue parseJson(const std::string& text, const std::string& source = "<string>");
/// Reads and parses a file; throws std::runtime_error when it cannot be read or parsed.
JsonValue readJsonFile(const std::string& path);

}  // namespace lieservo::adapters
