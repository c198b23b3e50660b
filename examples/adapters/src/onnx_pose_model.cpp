#include "lieservo_adapters/onnx_pose_model.hpp"

#include <cctype>
#include <cmath>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <openssl/evp.h>

#include <lieservo/units.hpp>
#include <lieservo_dataset/json.hpp>

namespace lieservo::adapters {

namespace {

using lieservo::dataset::DatasetError;
using lieservo::dataset::JsonDocument;
using lieservo::dataset::JsonValue;
using lieservo::dataset::find;

constexpr double kPi = lieservo::pi<double>();

const char* kindName(ModelKind k) { return k == ModelKind::gdn ? "gdn" : "cnn"; }

std::string trim(const std::string& s) {
  std::size_t a = 0, b = s.size();
  while (a < b && std::isspace(static_cast<unsigned char>(s[a])) != 0) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1])) != 0) --b;
  return s.substr(a, b - a);
}

/// "mm" -> 1, "deg"/"degrees" -> π/180, "rad"/"radians" -> 1.
double unitFactor(const std::string& unit, const std::string& where) {
  const std::string u = trim(unit);
  if (u == "mm") return 1.0;
  if (u == "deg" || u == "degree" || u == "degrees") return kPi / 180.0;
  if (u == "rad" || u == "radian" || u == "radians") return 1.0;
  throw std::runtime_error(where + ": unknown unit \"" + u + "\" (expected mm, deg or rad)");
}

/// Units of the six μ components from either an array of strings or the project's
/// free-text form "mu: mm, mm, mm, deg, deg, deg; sigma_inv: ..." (or "mm, mm, ... deg").
std::array<std::string, 6> parseUnits(const JsonDocument& doc, const JsonValue& v, const std::string& where) {
  std::vector<std::string> tokens;
  if (v.IsArray()) {
    for (const auto& e : v.GetArray()) tokens.push_back(trim(doc.asString(e, where)));
  } else {
    std::string text = doc.asString(v, where);
    const auto mu = text.find("mu:");
    if (mu != std::string::npos) text = text.substr(mu + 3);
    const auto semi = text.find(';');
    if (semi != std::string::npos) text = text.substr(0, semi);
    std::stringstream ss(text);
    std::string tok;
    while (std::getline(ss, tok, ',')) tokens.push_back(trim(tok));
  }
  if (tokens.size() < 6) throw std::runtime_error(where + ": expected 6 component units, found " +
                                                  std::to_string(tokens.size()));
  std::array<std::string, 6> out;
  for (int i = 0; i < 6; ++i) out[static_cast<std::size_t>(i)] = tokens[static_cast<std::size_t>(i)];
  return out;
}

/// sigma_calibration: {"scale": [6 finite numbers > 0], "source": "..." (optional)}.
void parseSigmaCalibration(const JsonDocument& doc, const JsonValue& v, const std::string& where, ModelCard& c) {
  const auto scale = doc.asArray(doc.at(v, "scale", where), where + ".scale");
  if (scale.Size() != 6)
    doc.fail(where + ".scale", "expected 6 factors, found " + std::to_string(scale.Size()));
  for (rapidjson::SizeType i = 0; i < 6; ++i) {
    const std::string at = where + ".scale[" + std::to_string(i) + "]";
    const double k = doc.asNumber(scale[i], at);
    if (!(k > 0.0) || !std::isfinite(k)) doc.fail(at, "must be a finite number > 0");
    c.sigma_scale[i] = k;
  }
  if (const JsonValue* src = find(v, "source")) c.sigma_calibration_source = doc.asString(*src, where + ".source");
}

int lastNumber(const JsonDocument& doc, const JsonValue& shape, const std::string& where) {
  const auto a = doc.asArray(shape, where);
  if (a.Empty()) doc.fail(where, "is an empty shape");
  return doc.asInt(a[a.Size() - 1], where + " (last entry)");
}

std::string dirOf(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? std::string(".") : path.substr(0, slash);
}

bool fileExists(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return static_cast<bool>(f);
}

}  // namespace

ModelCard ModelCard::fromJsonFile(const std::string& path, ModelKind kind) {
  // The shared reader (examples/dataset): malformed input and wrongly typed or missing
  // entries throw DatasetError naming the path (and line:column, or the entry).
  const JsonDocument doc = lieservo::dataset::readJsonFile(path);
  ModelCard c;
  c.kind = kind;
  const std::string k = kindName(kind);
  try {
    const JsonValue& r = doc.expect(doc.root.IsObject(), doc.root, "", "top level should be an object");
    if (const JsonValue* models = find(r, "models")) {
      const std::string m = "models." + k;
      const JsonValue* e = find(*models, k);
      if (e == nullptr) doc.fail("", "no entry " + m + " (model not exported yet?)");
      if (const JsonValue* f = find(*e, "file")) c.onnx_file = doc.asString(*f, m + ".file");
      if (const JsonValue* h = find(*e, "sha256")) c.sha256 = doc.asString(*h, m + ".sha256");
      const JsonValue& in = doc.at(*e, "input", m);
      c.input_size = lastNumber(doc, doc.at(in, "shape", m + ".input"), m + ".input.shape");
      const JsonValue& out = doc.at(*e, "output", m);
      c.outputs = lastNumber(doc, doc.at(out, "shape", m + ".output"), m + ".output.shape");
      c.units = parseUnits(doc, doc.at(out, "units", m + ".output"), m + ".output.units");
      if (const JsonValue* cal = find(*e, "sigma_calibration"))
        parseSigmaCalibration(doc, *cal, "models." + k + ".sigma_calibration", c);
    } else {
      const std::string declared = doc.asString(doc.at(r, "kind"), "kind");
      if (declared != k) throw std::runtime_error("card is for a \"" + declared + "\" model, not \"" + k + "\"");
      if (const JsonValue* f = find(r, "file")) c.onnx_file = doc.asString(*f, "file");
      if (const JsonValue* h = find(r, "sha256")) c.sha256 = doc.asString(*h, "sha256");
      c.input_size = doc.asInt(doc.at(r, "input_size"), "input_size");
      c.outputs = doc.asInt(doc.at(r, "outputs"), "outputs");
      c.units = parseUnits(doc, doc.at(r, "output_units"), "output_units");
      if (const JsonValue* cal = find(r, "sigma_calibration")) parseSigmaCalibration(doc, *cal, "sigma_calibration", c);
    }
    for (std::size_t i = 0; i < 6; ++i)
      c.to_library[i] = unitFactor(c.units[i], "unit of component " + std::to_string(i + 1));
    const int expected = kind == ModelKind::gdn ? 12 : 6;
    if (c.outputs != expected)
      throw std::runtime_error("a " + k + " model should have " + std::to_string(expected) + " outputs, card says " +
                               std::to_string(c.outputs));
    if (c.input_size <= 0) throw std::runtime_error("input size must be positive");
    if (!c.sha256.empty() && (c.sha256.size() != 64 || c.sha256.find_first_not_of("0123456789abcdef") != std::string::npos))
      throw std::runtime_error("sha256 should be 64 lowercase hex digits, card says \"" + c.sha256 + "\"");
    if (kind == ModelKind::cnn && c.hasSigmaCalibration())
      throw std::runtime_error("a cnn model has no sigma to calibrate (sigma_calibration given)");
  } catch (const DatasetError&) {
    throw;  // already names the file, line and column
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(path + ": " + e.what());
  }
  if (!c.onnx_file.empty() && c.onnx_file.front() != '/') c.onnx_file = dirOf(path) + "/" + c.onnx_file;
  return c;
}

OnnxPoseModel::OnnxPoseModel(const std::string& onnx_path, const ModelCard& card) : card_(card), path_(onnx_path) {
  if (!fileExists(onnx_path)) throw std::runtime_error(onnx_path + ": ONNX model file not found");
  if (!card_.sha256.empty()) {
    const std::string actual = sha256OfFile(onnx_path);
    if (actual != card_.sha256)
      throw std::runtime_error(onnx_path + ": SHA-256 " + actual + " does not match the card's " + card_.sha256 +
                               " (a corrupted or replaced model file)");
  }
  try {
    net_ = cv::dnn::readNetFromONNX(onnx_path);
  } catch (const cv::Exception& e) {
    throw std::runtime_error(onnx_path + ": cannot load ONNX model: " + e.what());
  }
  if (net_.empty()) throw std::runtime_error(onnx_path + ": cannot load ONNX model (empty network)");
  net_.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
  net_.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
  // Check the output shape against the card with one blank image.
  const cv::Mat blank = cv::Mat::zeros(card_.input_size, card_.input_size, CV_32F);
  std::vector<Prediction> r;
  if (predictBatch({blank}, r) != Status::ok)
    throw std::runtime_error(onnx_path + ": model does not match its card: " + last_error_);
  last_error_.clear();
}

std::string sha256OfFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot read the file to hash it");
  std::unique_ptr<EVP_MD_CTX, decltype(&EVP_MD_CTX_free)> ctx(EVP_MD_CTX_new(), &EVP_MD_CTX_free);
  if (!ctx || EVP_DigestInit_ex(ctx.get(), EVP_sha256(), nullptr) != 1)
    throw std::runtime_error("OpenSSL: cannot start a SHA-256 digest");
  std::vector<char> buffer(1 << 16);
  while (in) {
    in.read(buffer.data(), std::streamsize(buffer.size()));
    if (in.gcount() > 0 && EVP_DigestUpdate(ctx.get(), buffer.data(), std::size_t(in.gcount())) != 1)
      throw std::runtime_error("OpenSSL: SHA-256 digest failed");
  }
  if (in.bad()) throw std::runtime_error(path + ": read error while hashing");
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  if (EVP_DigestFinal_ex(ctx.get(), digest, &length) != 1) throw std::runtime_error("OpenSSL: SHA-256 digest failed");
  static const char* hex = "0123456789abcdef";
  std::string out;
  for (unsigned int i = 0; i < length; ++i) out += {hex[digest[i] >> 4], hex[digest[i] & 15]};
  return out;
}

OnnxPoseModel OnnxPoseModel::fromCard(const std::string& card_path, ModelKind kind) {
  ModelCard card = ModelCard::fromJsonFile(card_path, kind);
  if (card.onnx_file.empty()) throw std::runtime_error(card_path + ": card names no model file");
  const std::string file = card.onnx_file;
  return OnnxPoseModel(file, card);
}

Status OnnxPoseModel::fail(Status s, std::string detail) {
  last_error_ = std::move(detail);
  return s;
}

Status OnnxPoseModel::checkInput(const cv::Mat& image, std::size_t index, cv::Mat& input) {
  const std::string what = "input image " + std::to_string(index);
  if (image.empty()) return fail(Status::invalid_argument, what + ": empty");
  if (image.channels() != 1)
    return fail(Status::invalid_argument, what + ": expected 1 channel, got " + std::to_string(image.channels()));
  if (image.rows != card_.input_size || image.cols != card_.input_size) {
    std::ostringstream os;
    os << what << ": expected " << card_.input_size << "x" << card_.input_size << " but got " << image.cols << "x"
       << image.rows << " (pre-process it first)";
    return fail(Status::invalid_argument, os.str());
  }
  if (image.type() == CV_32FC1) {
    input = image;
    return Status::ok;
  }
  if (image.type() == CV_8UC1) {
    image.convertTo(input, CV_32F, 1.0 / 255.0);
    return Status::ok;
  }
  return fail(Status::invalid_argument, what + ": expected CV_32FC1 in [0,1] or CV_8UC1");
}

Status OnnxPoseModel::predictBatch(const std::vector<cv::Mat>& images, std::vector<Prediction>& predictions) {
  if (images.empty()) return fail(Status::invalid_argument, "predictBatch: empty batch");
  std::vector<cv::Mat> inputs(images.size());
  for (std::size_t i = 0; i < images.size(); ++i) {
    const Status s = checkInput(images[i], i, inputs[i]);
    if (s != Status::ok) return s;
  }
  cv::Mat out;
  try {
    const cv::Mat blob = cv::dnn::blobFromImages(inputs, 1.0, cv::Size(), cv::Scalar(), false, false, CV_32F);
    net_.setInput(blob);
    out = net_.forward().clone();
  } catch (const cv::Exception& e) {
    return fail(Status::device_error, path_ + ": forward pass failed: " + e.what());
  }
  const int n = static_cast<int>(images.size());
  if (out.type() != CV_32F || out.total() != static_cast<std::size_t>(n) * static_cast<std::size_t>(card_.outputs)) {
    std::ostringstream os;
    os << path_ << ": unexpected output: " << out.total() << " values of type " << out.type() << " for a batch of " << n
       << " (expected " << card_.outputs << " per image, float32)";
    return fail(Status::device_error, os.str());
  }
  out = out.reshape(1, n);
  std::vector<Prediction> preds(static_cast<std::size_t>(n));
  std::array<double, 12> raw{};
  for (int i = 0; i < n; ++i) {
    const float* row = out.ptr<float>(i);
    for (int j = 0; j < card_.outputs; ++j) raw[static_cast<std::size_t>(j)] = static_cast<double>(row[j]);
    std::string detail;
    const Status s = fromRaw(card_, raw.data(), preds[static_cast<std::size_t>(i)], &detail);
    if (s != Status::ok) return fail(s, path_ + ": image " + std::to_string(i) + ": " + detail);
  }
  predictions = std::move(preds);
  return Status::ok;
}

Status OnnxPoseModel::fromRaw(const ModelCard& card, const double* raw, Prediction& prediction, std::string* detail) {
  Prediction p;
  const bool gdn = card.outputs == 12;
  Eigen::Matrix<double, 6, 1> sigma;
  for (int j = 0; j < card.outputs; ++j) {
    p.raw[static_cast<std::size_t>(j)] = raw[j];
    if (!std::isfinite(raw[j])) {
      if (detail) *detail = "output " + std::to_string(j) + " is not finite";
      return Status::numerical_failure;
    }
  }
  for (int j = 0; j < 6; ++j) {
    const double f = card.to_library[static_cast<std::size_t>(j)];
    p.mu(j) = raw[j] * f;
    if (gdn) {
      const double s_inv = raw[6 + j];
      if (!(s_inv > 0.0)) {
        if (detail) *detail = "sigma^-1 of component " + std::to_string(j + 1) + " is not positive";
        return Status::numerical_failure;
      }
      sigma(j) = f * card.sigma_scale[static_cast<std::size_t>(j)] / s_inv;  // σ = 1/σ⁻¹, library units
    }
  }
  if (gdn) p.sigma = sigma;
  prediction = p;
  return Status::ok;
}

Status OnnxPoseModel::predict(const cv::Mat& image, Prediction& prediction) {
  std::vector<Prediction> one;
  const Status s = predictBatch({image}, one);
  if (s == Status::ok) prediction = one.front();
  return s;
}

}  // namespace lieservo::adapters
