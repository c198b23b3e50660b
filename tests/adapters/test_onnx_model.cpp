// The ONNX pose-model adapter on the tiny committed test models
// (tests/adapters/data/make_tiny_model.py): cv::dnn against the PyTorch reference,
// unit conversion from the model card, batch = singles, and error paths.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "lieservo_adapters/gdn_observation.hpp"
#include "lieservo_adapters/onnx_pose_model.hpp"
#include "file_test_util.hpp"

using namespace lieservo::adapters;
using lieservo::Status;

namespace {

/// The prediction for one image, which must succeed.
Prediction predicted(OnnxPoseModel& model, const cv::Mat& image) {
  Prediction p;
  const Status s = model.predict(image, p);
  INFO(model.lastError());
  REQUIRE(s == Status::ok);
  return p;
}

const std::string kData = LIESERVO_ADAPTERS_TEST_DATA;
constexpr double kDeg = lieservo::pi<double>() / 180.0;

/// Same synthetic inputs as make_tiny_model.py.
cv::Mat syntheticInput(int k) {
  cv::Mat m(128, 128, CV_32F);
  for (int i = 0; i < 128; ++i)
    for (int j = 0; j < 128; ++j)
      m.at<float>(i, j) = static_cast<float>((0.4 + 0.3 * k) * (((i * (7 + k) + j * 13 + 3 * k) % 17) / 16.0));
  return m;
}

std::vector<double> reference(const std::string& model, int k) {
  for (const auto& row : file_test::readCsv(kData + "/tiny_reference.csv")) {
    if (row.size() < 3 || row[0] != model || row[1] != std::to_string(k)) continue;
    std::vector<double> v;
    for (std::size_t i = 2; i < row.size(); ++i) v.push_back(std::stod(row[i]));
    return v;
  }
  return {};
}

}  // namespace

TEST_CASE("onnx: model card parsing", "[adapters][onnx]") {
  const ModelCard g = ModelCard::fromJsonFile(kData + "/tiny_model_card.json", ModelKind::gdn);
  CHECK(g.outputs == 12);
  CHECK(g.input_size == 128);
  CHECK(g.onnx_file == kData + "/tiny_gdn.onnx");
  CHECK(g.units[0] == "mm");
  CHECK(g.units[5] == "deg");
  CHECK(g.to_library[2] == 1.0);
  CHECK(g.to_library[3] == Approx(kDeg));
  const ModelCard c = ModelCard::fromJsonFile(kData + "/tiny_model_card.json", ModelKind::cnn);
  CHECK(c.outputs == 6);
  CHECK(c.to_library[4] == Approx(kDeg));

  const std::string dir = file_test::makeTempDir("card");
  const std::string flat = dir + "/card.json";
  std::ofstream(flat) << R"({"kind": "gdn", "input_size": 128, "outputs": 12, "file": "m.onnx",
                             "output_units": ["mm", "mm", "mm", "rad", "rad", "rad"]})";
  const ModelCard f = ModelCard::fromJsonFile(flat, ModelKind::gdn);
  CHECK(f.to_library[3] == 1.0);
  CHECK(f.onnx_file == dir + "/m.onnx");
  CHECK_THROWS_WITH(ModelCard::fromJsonFile(flat, ModelKind::cnn), Catch::Contains("not \"cnn\""));

  std::ofstream(flat) << R"({"kind": "gdn", "input_size": 128, "outputs": 12, "output_units": ["mm", "mm", "mm", "furlong", "rad", "rad"]})";
  CHECK_THROWS_WITH(ModelCard::fromJsonFile(flat, ModelKind::gdn), Catch::Contains("furlong"));
  std::ofstream(flat) << R"({"kind": "gdn", "input_size": 128, "outputs": 6, "output_units": ["mm", "mm", "mm", "deg", "deg", "deg"]})";
  CHECK_THROWS_WITH(ModelCard::fromJsonFile(flat, ModelKind::gdn), Catch::Contains("12 outputs"));
  std::ofstream(flat) << R"({"models": {"cnn": {}}})";
  CHECK_THROWS_WITH(ModelCard::fromJsonFile(flat, ModelKind::gdn), Catch::Contains("models.gdn"));
  std::ofstream(flat) << R"({"models": {"gdn": {"file": "x.onnx", "input": {"shape": ["N", 1, 128, 128]}}}})";
  CHECK_THROWS_WITH(ModelCard::fromJsonFile(flat, ModelKind::gdn), Catch::Contains("missing key \"output\""));
  std::ofstream(flat) << "{\"models\": {\"gdn\": ";
  CHECK_THROWS_WITH(ModelCard::fromJsonFile(flat, ModelKind::gdn), Catch::Contains(flat + ":1:"));
  CHECK_THROWS_WITH(ModelCard::fromJsonFile(dir + "/none.json", ModelKind::gdn), Catch::Contains("cannot open"));
  file_test::removeTree(dir);
}

TEST_CASE("onnx: the model file must match its card's SHA-256", "[adapters][onnx]") {
  const std::string dir = file_test::makeTempDir("sha");
  // Known answers (FIPS 180-2): "abc" and the empty message.
  std::ofstream(dir + "/abc", std::ios::binary) << "abc";
  std::ofstream(dir + "/empty", std::ios::binary).flush();
  CHECK(sha256OfFile(dir + "/abc") == "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  CHECK(sha256OfFile(dir + "/empty") == "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  CHECK_THROWS_WITH(sha256OfFile(dir + "/none"), Catch::Contains(dir + "/none"));

  // The tiny GDN copied, under a flat card with its hash: loads. Its first 4 KB zeroed: refused,
  // both hashes named.
  const ModelCard tiny = ModelCard::fromJsonFile(kData + "/tiny_model_card.json", ModelKind::gdn);
  REQUIRE(tiny.sha256.size() == 64);
  std::string bytes;
  {
    std::ifstream in(tiny.onnx_file, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  REQUIRE(bytes.size() > 4096);
  std::ofstream(dir + "/m.onnx", std::ios::binary) << bytes;
  const std::string card = dir + "/card.json";
  std::ofstream(card) << R"({"kind": "gdn", "input_size": 128, "outputs": 12, "file": "m.onnx", "sha256": ")" << tiny.sha256
                      << R"(", "output_units": ["mm", "mm", "mm", "deg", "deg", "deg"]})";
  CHECK_NOTHROW(OnnxPoseModel::fromCard(card, ModelKind::gdn));
  std::fill(bytes.begin(), bytes.begin() + 4096, '\0');
  std::ofstream(dir + "/m.onnx", std::ios::binary) << bytes;
  const std::string corrupted = sha256OfFile(dir + "/m.onnx");
  CHECK_THROWS_WITH(OnnxPoseModel::fromCard(card, ModelKind::gdn),
                    Catch::Contains(corrupted) && Catch::Contains(tiny.sha256) && Catch::Contains("m.onnx"));
  // A malformed hash in the card is refused when the card is read.
  std::ofstream(card) << R"({"kind": "gdn", "input_size": 128, "outputs": 12, "file": "m.onnx", "sha256": "ABC",
                             "output_units": ["mm", "mm", "mm", "deg", "deg", "deg"]})";
  CHECK_THROWS_WITH(ModelCard::fromJsonFile(card, ModelKind::gdn), Catch::Contains("64 lowercase hex digits"));
  file_test::removeTree(dir);
}

TEST_CASE("onnx: every model card the project ships carries its model's SHA-256", "[adapters][onnx]") {
  const std::string models = LIESERVO_GDN_MODELS_DIR;
  struct Entry {
    std::string card;
    ModelKind kind;
  };
  for (const Entry& e : {Entry{models + "/model_card.json", ModelKind::gdn}, Entry{models + "/model_card.json", ModelKind::cnn},
                         Entry{models + "/train_val/model_card.json", ModelKind::gdn},
                         Entry{kData + "/tiny_model_card.json", ModelKind::gdn},
                         Entry{kData + "/tiny_model_card.json", ModelKind::cnn}}) {
    const ModelCard c = ModelCard::fromJsonFile(e.card, e.kind);
    INFO(e.card << ": " << c.onnx_file);
    REQUIRE(c.sha256.size() == 64);
    CHECK(sha256OfFile(c.onnx_file) == c.sha256);
  }
}

TEST_CASE("onnx: a card's sigma calibration scales sigma and nothing else", "[adapters][onnx]") {
  const ModelCard plain = ModelCard::fromJsonFile(kData + "/tiny_model_card.json", ModelKind::gdn);
  CHECK_FALSE(plain.hasSigmaCalibration());
  CHECK(plain.sigma_calibration_source.empty());

  const std::string dir = file_test::makeTempDir("calib");
  const std::string card = dir + "/card.json";
  std::ofstream(card) << R"({"models": {"gdn": {"file": "g.onnx", "input": {"shape": [1, 1, 128, 128]},
      "output": {"shape": [1, 12], "units": ["mm", "mm", "mm", "deg", "deg", "deg"]},
      "sigma_calibration": {"scale": [1.0, 1.25, 0.5, 2.0, 1.0, 3.0], "source": "held-out images"}}}})";
  const ModelCard c = ModelCard::fromJsonFile(card, ModelKind::gdn);
  REQUIRE(c.hasSigmaCalibration());
  CHECK(c.sigma_calibration_source == "held-out images");
  const double raw[12] = {0.1, -0.2, 3.0, 1.5, -2.0, 0.25, 2.0, 4.0, 10.0, 1.0, 0.5, 0.8};
  Prediction a, b;
  REQUIRE(OnnxPoseModel::fromRaw(plain, raw, a) == Status::ok);
  REQUIRE(OnnxPoseModel::fromRaw(c, raw, b) == Status::ok);
  REQUIRE(a.sigma.has_value());
  REQUIRE(b.sigma.has_value());
  for (int j = 0; j < 6; ++j) {
    CHECK(b.mu(j) == a.mu(j));  // μ untouched
    CHECK((*b.sigma)(j) == Approx(c.sigma_scale[static_cast<std::size_t>(j)] * (*a.sigma)(j)).epsilon(1e-15));
  }
  for (std::size_t j = 0; j < 12; ++j) CHECK(b.raw[j] == raw[j]);  // the network's outputs as returned
  // A non-finite output or a σ⁻¹ ≤ 0 is a numerical failure that names the component and
  // leaves the prediction as it was.
  double bad[12];
  std::copy(raw, raw + 12, bad);
  bad[4] = std::nan("");
  std::string detail;
  const Prediction kept = b;
  CHECK(OnnxPoseModel::fromRaw(c, bad, b, &detail) == Status::numerical_failure);
  CHECK(detail.find("output 4") != std::string::npos);
  CHECK(b.mu == kept.mu);
  std::copy(raw, raw + 12, bad);
  bad[8] = 0.0;
  CHECK(OnnxPoseModel::fromRaw(c, bad, b, &detail) == Status::numerical_failure);
  CHECK(detail.find("component 3") != std::string::npos);

  // The flat card form takes the same entry.
  std::ofstream(card) << R"({"kind": "gdn", "input_size": 128, "outputs": 12, "output_units": ["mm", "mm", "mm", "deg", "deg", "deg"],
                             "sigma_calibration": {"scale": [1, 1, 1, 2, 2, 1]}})";
  CHECK(ModelCard::fromJsonFile(card, ModelKind::gdn).sigma_scale[4] == 2.0);
  // Bad factors name the field; a CNN has no σ to calibrate.
  const std::string head = R"({"kind": "gdn", "input_size": 128, "outputs": 12, "output_units": ["mm", "mm", "mm", "deg", "deg", "deg"], )";
  std::ofstream(card) << head << R"("sigma_calibration": {"scale": [1, 1, 1, 2, 2]}})";
  CHECK_THROWS_WITH(ModelCard::fromJsonFile(card, ModelKind::gdn), Catch::Contains("expected 6 factors, found 5"));
  std::ofstream(card) << head << R"("sigma_calibration": {"scale": [1, 1, 1, 2, 0, 1]}})";
  CHECK_THROWS_WITH(ModelCard::fromJsonFile(card, ModelKind::gdn), Catch::Contains("\"sigma_calibration.scale[4]\" must be a finite number > 0"));
  std::ofstream(card) << head << R"("sigma_calibration": {"scale": [1, 1, 1, 2, -1, 1]}})";
  CHECK_THROWS_WITH(ModelCard::fromJsonFile(card, ModelKind::gdn), Catch::Contains("scale[4]"));
  std::ofstream(card) << head << R"("sigma_calibration": {"scale": [1, 1, "x", 2, 1, 1]}})";
  CHECK_THROWS_WITH(ModelCard::fromJsonFile(card, ModelKind::gdn), Catch::Contains("scale[2]"));
  std::ofstream(card) << head << R"("sigma_calibration": {"factor": 2}})";
  CHECK_THROWS_WITH(ModelCard::fromJsonFile(card, ModelKind::gdn), Catch::Contains("missing key \"scale\""));
  std::ofstream(card) << R"({"kind": "cnn", "input_size": 128, "outputs": 6, "output_units": ["mm", "mm", "mm", "deg", "deg", "deg"],
                             "sigma_calibration": {"scale": [1, 1, 1, 2, 2, 1]}})";
  CHECK_THROWS_WITH(ModelCard::fromJsonFile(card, ModelKind::cnn), Catch::Contains("no sigma to calibrate"));
  file_test::removeTree(dir);
}

TEST_CASE("onnx: tiny GDN through cv::dnn matches PyTorch and converts units", "[adapters][onnx]") {
  OnnxPoseModel gdn = OnnxPoseModel::fromCard(kData + "/tiny_model_card.json", ModelKind::gdn);
  REQUIRE(gdn.hasUncertainty());
  std::vector<cv::Mat> batch;
  for (int k = 0; k < 3; ++k) batch.push_back(syntheticInput(k));
  std::vector<Prediction> all;
  REQUIRE(gdn.predictBatch(batch, all) == Status::ok);
  REQUIRE(all.size() == 3);
  for (int k = 0; k < 3; ++k) {
    const auto ref = reference("gdn", k);
    REQUIRE(ref.size() == 12);
    const Prediction& p = all[static_cast<std::size_t>(k)];
    REQUIRE(p.sigma.has_value());
    REQUIRE(p.precisionSqrt().has_value());
    for (std::size_t j = 0; j < 12; ++j) CHECK(p.raw[j] == Approx(ref[j]).margin(1e-5));
    for (int j = 0; j < 6; ++j) {
      const double f = j < 3 ? 1.0 : kDeg;  // the card: mm, mm, mm, deg, deg, deg
      CHECK(p.mu(j) == Approx(ref[static_cast<std::size_t>(j)] * f).margin(1e-7));
      CHECK((*p.sigma)(j) == Approx(f / ref[static_cast<std::size_t>(6 + j)]).epsilon(1e-5));
      CHECK((*p.precisionSqrt())(j) == Approx(ref[static_cast<std::size_t>(6 + j)] / f).epsilon(1e-5));
    }
    // Single-image path = batch path.
    const Prediction one = predicted(gdn, batch[static_cast<std::size_t>(k)]);
    for (std::size_t j = 0; j < 12; ++j) CHECK(one.raw[j] == Approx(p.raw[j]).margin(1e-6));
  }
  // An 8-bit input is scaled by 1/255 first.
  cv::Mat u8;
  batch[2].convertTo(u8, CV_8U, 255.0);
  cv::Mat back;
  u8.convertTo(back, CV_32F, 1.0 / 255.0);
  const Prediction a = predicted(gdn, u8), b = predicted(gdn, back);
  for (std::size_t j = 0; j < 12; ++j) CHECK(a.raw[j] == Approx(b.raw[j]).margin(1e-6));
}

TEST_CASE("onnx: tiny CNN regression mode returns mu only", "[adapters][onnx]") {
  OnnxPoseModel cnn = OnnxPoseModel::fromCard(kData + "/tiny_model_card.json", ModelKind::cnn);
  CHECK_FALSE(cnn.hasUncertainty());
  for (int k = 0; k < 3; ++k) {
    const Prediction p = predicted(cnn, syntheticInput(k));
    CHECK_FALSE(p.sigma.has_value());
    CHECK_FALSE(p.precisionSqrt().has_value());
    const auto ref = reference("cnn", k);
    REQUIRE(ref.size() == 6);
    for (int j = 0; j < 6; ++j) {
      CHECK(p.raw[static_cast<std::size_t>(j)] == Approx(ref[static_cast<std::size_t>(j)]).margin(1e-5));
      CHECK(p.mu(j) == Approx(ref[static_cast<std::size_t>(j)] * (j < 3 ? 1.0 : kDeg)).margin(1e-7));
    }
  }
}

TEST_CASE("onnx: wrong inputs and missing or malformed models give clear errors", "[adapters][onnx]") {
  OnnxPoseModel gdn = OnnxPoseModel::fromCard(kData + "/tiny_model_card.json", ModelKind::gdn);
  // Every wrong input is invalid_argument, says what was wrong, and leaves the output as it was.
  Prediction p;
  p.mu.setConstant(7.0);
  auto rejected = [&](const cv::Mat& image, const std::string& words) {
    CHECK(gdn.predict(image, p) == Status::invalid_argument);
    CHECK(gdn.lastError().find(words) != std::string::npos);
    CHECK(p.mu(0) == 7.0);
  };
  rejected(cv::Mat::zeros(440, 445, CV_32F), "128x128");
  rejected(cv::Mat::zeros(128, 128, CV_32FC3), "1 channel");
  rejected(cv::Mat(), "empty");
  rejected(cv::Mat::zeros(128, 128, CV_64F), "CV_32FC1");
  std::vector<Prediction> batch_out(1);
  CHECK(gdn.predictBatch({}, batch_out) == Status::invalid_argument);
  CHECK(gdn.predictBatch({syntheticInput(0), cv::Mat::zeros(64, 64, CV_32F)}, batch_out) == Status::invalid_argument);
  CHECK(gdn.lastError().find("input image 1") != std::string::npos);
  CHECK(batch_out.size() == 1);

  const ModelCard card = ModelCard::fromJsonFile(kData + "/tiny_model_card.json", ModelKind::gdn);
  CHECK_THROWS_WITH(OnnxPoseModel("/nonexistent/gdn.onnx", card), Catch::Contains("not found"));
  const std::string dir = file_test::makeTempDir("onnx");
  std::ofstream(dir + "/garbage.onnx") << "definitely not a protobuf";
  CHECK_THROWS_WITH(OnnxPoseModel(dir + "/garbage.onnx", card), Catch::Contains(dir + "/garbage.onnx"));
  // A CNN file loaded with a GDN card: refused by its hash; without the hash, the output-count
  // mismatch is caught at load.
  CHECK_THROWS_WITH(OnnxPoseModel(kData + "/tiny_cnn.onnx", card), Catch::Contains("SHA-256"));
  ModelCard unhashed = card;
  unhashed.sha256.clear();
  CHECK_THROWS_WITH(OnnxPoseModel(kData + "/tiny_cnn.onnx", unhashed), Catch::Contains("does not match its card"));
  file_test::removeTree(dir);
}

TEST_CASE("onnx: a GDN prediction as the SE(3) observation Gaussian (eq. 14, eq:se3_inverse_transform)",
          "[adapters][onnx][estimation]") {
  OnnxPoseModel gdn = OnnxPoseModel::fromCard(kData + "/tiny_model_card.json", ModelKind::gdn);
  const Prediction p = predicted(gdn, syntheticInput(1));
  lieservo::ConcentratedGaussian<lieservo::SE3d> obs;
  REQUIRE(toObservation(p, obs) == lieservo::Status::ok);
  const lieservo::SE3d::Tangent mu = p.mu;
  CHECK(obs.mean.isApprox(lieservo::SE3d::exp(mu), 1e-12));
  REQUIRE(p.sigma.has_value());
  const lieservo::SE3d::Jacobian S = p.sigma->array().square().matrix().asDiagonal();
  // J by the library's one default on the observation path (the paper's series), the
  // Jacobian the filter's fusion uses; the exact J with ClosedFormJacobian.
  const lieservo::SE3d::Jacobian Jd = lieservo::DefaultJacobian::forward<lieservo::SE3d>(mu);
  CHECK((obs.covariance - Jd * S * Jd.transpose()).norm() <= 1e-12 * S.norm());
  CHECK(obs.validate() == lieservo::Status::ok);
  lieservo::ConcentratedGaussian<lieservo::SE3d> exact;
  REQUIRE(toObservation<lieservo::ClosedFormJacobian>(p, exact) == lieservo::Status::ok);
  const lieservo::SE3d::Jacobian J = lieservo::SE3d::leftJacobian(mu);
  CHECK((exact.covariance - J * S * J.transpose()).norm() <= 1e-12 * S.norm());

  // A CNN prediction has no σ: refused, output untouched.
  OnnxPoseModel cnn = OnnxPoseModel::fromCard(kData + "/tiny_model_card.json", ModelKind::cnn);
  const Prediction c = predicted(cnn, syntheticInput(1));
  const auto before = obs;
  CHECK(toObservation(c, obs) == lieservo::Status::invalid_argument);
  CHECK(obs.mean.isApprox(before.mean, 0.0));
  // A non-positive σ: not_spd.
  Prediction bad = p;
  REQUIRE(bad.sigma.has_value());
  (*bad.sigma)(2) = 0.0;
  CHECK(toObservation(bad, obs) == lieservo::Status::not_spd);
}
