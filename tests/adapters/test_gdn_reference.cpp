// The real GDNs (examples/gdn/models/gdn.onnx, the paper's reproduction model, and
// examples/gdn/models/train_val/gdn.onnx, the deployed one) run from C++ (pre-processing + cv::dnn)
// on the first validation images match the PyTorch outputs recorded by
// examples/gdn/export_onnx.py (gdn_reference_outputs.csv) within 1e-4 (relative to
// max(1, |value|)). Skipped with a message until the model and the data exist.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>

#include "lieservo_adapters/onnx_pose_model.hpp"
#include "lieservo_adapters/preprocessing.hpp"
#include "file_test_util.hpp"

using namespace lieservo::adapters;

TEST_CASE("gdn: C++ inference on real images matches the recorded PyTorch outputs", "[adapters][onnx][data][gdn]") {
  const std::string models =
      GENERATE(std::string(LIESERVO_GDN_MODELS_DIR), std::string(LIESERVO_GDN_MODELS_DIR) + "/train_val");
  INFO("models: " << models);
  const std::string val = std::string(LIESERVO_DATA_DIR) + "/val";
  const std::string card = models + "/model_card.json", csv = models + "/gdn_reference_outputs.csv";
  if (!file_test::exists(models + "/gdn.onnx") || !file_test::exists(card) ||
      !file_test::exists(csv)) {
    WARN("real GDN not exported yet (" << models << "/{gdn.onnx,model_card.json,gdn_reference_outputs.csv}): skipping");
    return;
  }
  if (!file_test::exists(val + "/processed_images/image_1.png")) {
    WARN("TacTip data not found under " << LIESERVO_DATA_DIR << ": skipping");
    return;
  }
  const Preprocessor pre(PreprocessParams::fromJsonFile(val + "/processed_image_params.json"));
  OnnxPoseModel gdn = OnnxPoseModel::fromCard(card, ModelKind::gdn);
  const auto rows = file_test::readCsv(csv);
  REQUIRE(rows.size() >= 2);
  REQUIRE(rows[0].size() == 13);
  int checked = 0;
  double worst = 0.0;
  for (std::size_t r = 1; r < rows.size(); ++r) {
    const auto& row = rows[r];
    REQUIRE(row.size() == 13);
    cv::Mat img;
    REQUIRE(pre.loadProcessed(val + "/processed_images/" + row[0], img) == lieservo::Status::ok);
    Prediction p;
    REQUIRE(gdn.predict(img, p) == lieservo::Status::ok);
    for (std::size_t j = 0; j < 12; ++j) {
      const double ref = std::stod(row[j + 1]);
      const double err = std::fabs(p.raw[j] - ref) / std::max(1.0, std::fabs(ref));
      worst = std::max(worst, err);
      INFO(row[0] << " output " << j << ": C++ " << p.raw[j] << " vs PyTorch " << ref);
      CHECK(err <= 1e-4);
    }
    ++checked;
  }
  CHECK(checked >= 8);
  INFO("worst relative difference " << worst);
  SUCCEED();
}
