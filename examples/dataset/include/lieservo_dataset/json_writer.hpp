// lieservo_dataset/json_writer.hpp — flat JSON objects on one line through RapidJSON's Writer
// (lieservo_collect's parameter files): valid JSON only, so a non-finite number is written as
// null (JSON has no Infinity); every other number reads back to the same double.
#pragma once

#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include <rapidjson/stringbuffer.h>
#include <rapidjson/writer.h>

namespace lieservo::dataset {

/// JsonObjectWriter().field("a", 1).field("b", std::vector<double>{1, 2}).str() == {"a":1,"b":[1.0,2.0]}.
class JsonObjectWriter {
 public:
  JsonObjectWriter() { w_.StartObject(); }
  template <class T>
  JsonObjectWriter& field(std::string_view key, const T& v) {
    w_.Key(key.data(), rapidjson::SizeType(key.size()));
    value(v);
    return *this;
  }
  std::string str() {
    if (!w_.IsComplete()) w_.EndObject();
    return std::string(buf_.GetString(), buf_.GetSize());
  }

 private:
  void value(double x) { std::isfinite(x) ? w_.Double(x) : w_.Null(); }
  void value(int x) { w_.Int(x); }
  void value(long long x) { w_.Int64(x); }
  void value(unsigned long long x) { w_.Uint64(x); }
  void value(bool x) { w_.Bool(x); }
  void value(const char* s) { w_.String(s); }
  void value(const std::string& s) { w_.String(s.data(), rapidjson::SizeType(s.size())); }
  void value(const std::vector<double>& v) {
    w_.StartArray();
    for (const double x : v) value(x);
    w_.EndArray();
  }
  rapidjson::StringBuffer buf_;
  rapidjson::Writer<rapidjson::StringBuffer> w_{buf_};
};

}  // namespace lieservo::dataset
