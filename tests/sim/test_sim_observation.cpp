// GDN-like observation model: calibration to the per-component MAE (from the paper or a model
// card: the reproduction model's validation MAE, the deployed model's held-out MAE), heteroscedasticity.

#include <catch2/catch.hpp>

#include <fstream>
#include <string>

#include <lieservo/sampling/random.hpp>

#include "file_test_util.hpp"

#include "lieservo_sim/contact_model.hpp"
#include "lieservo_sim/observation_model.hpp"

using lieservo::sampling::uniform;
using namespace lieservo::sim;

namespace {
// A contact drawn from the paper's training distribution (Section 3.1.2, sec:data_collection).
ContactState sampleTrainingContact(lieservo::sampling::Rng& rng) {
  const double r = 5 * std::sqrt(uniform(rng, 0.0, 1.0)), th = 2 * kPi * uniform(rng, 0.0, 1.0);
  const double z = 0.5 + 5.5 * uniform(rng, 0.0, 1.0);
  const double phi = std::acos(1 - (1 - std::cos(deg2rad(25))) * uniform(rng, 0.0, 1.0)), th2 = 2 * kPi * uniform(rng, 0.0, 1.0);
  const double p = std::sin(phi) * std::cos(th2), q = std::sin(phi) * std::sin(th2), rr = std::cos(phi);
  const double a = -std::asin(q), b = -std::atan2(p, rr), g = deg2rad(-5 + 10 * uniform(rng, 0.0, 1.0));
  ContactState c;
  c.in_contact = true;
  c.depth = z;
  c.shear = Vec2(r * std::cos(th), r * std::sin(th));
  c.X_fs = SE3d::fromEulerXYZ6((Vec6() << c.shear.x(), c.shear.y(), z, a, b, g).finished());
  const Vec3 zs = c.X_fs.rotationMatrix().col(2);
  c.tilt = std::acos(std::min(1.0, zs.z()));
  c.twist = g;
  return c;
}
}  // namespace

TEST_CASE("observation: MAE over the training distribution matches the calibration", "[sim][observation]") {
  const GdnCalibration cal = GdnCalibration::paperTable1();
  GdnObservationModel gdn(cal, {}, 42);
  lieservo::sampling::Rng rng(7);
  Vec6 mae = Vec6::Zero();
  const int N = 40000;
  for (int i = 0; i < N; ++i) {
    const GdnObservation o = gdn.observe(sampleTrainingContact(rng));
    mae += (o.mu - o.truth).cwiseAbs();
  }
  mae /= N;
  for (int i = 0; i < 6; ++i) CHECK(mae[i] == Approx(cal.mae[i]).epsilon(0.04));
  CHECK(cal.mae[3] == Approx(deg2rad(0.45)));  // radians inside
}

TEST_CASE("observation: sigma grows with shear and at shallow depth", "[sim][observation]") {
  GdnObservationModel gdn;
  ContactState c;
  c.in_contact = true;
  c.depth = 3;
  const Vec6 s0 = gdn.sigmaFor(c);
  c.shear = Vec2(4, 0);
  const Vec6 s1 = gdn.sigmaFor(c);
  c.shear = Vec2::Zero();
  c.depth = 0.6;
  const Vec6 s2 = gdn.sigmaFor(c);
  c.in_contact = false;
  const Vec6 s3 = gdn.sigmaFor(c);
  for (int i = 0; i < 6; ++i) {
    CHECK(s1[i] > s0[i]);
    CHECK(s2[i] > s0[i]);
    CHECK(s3[i] > s2[i]);
  }
  CHECK(s1[0] / s0[0] > s1[2] / s0[2]);  // shear hits the shear components harder
}

TEST_CASE("observation: truth is log(X_sf) with X_sf = X_fs^-1", "[sim][observation]") {
  GdnObservationModel gdn;
  ContactState c;
  c.in_contact = true;
  c.depth = 2;
  c.X_fs = SE3d::fromEulerXYZ6((Vec6() << 1, -0.5, 2, 0.1, -0.05, 0.02).finished());
  const GdnObservation o = gdn.observe(c);
  CHECK((o.truth - c.X_fs.inverse().log()).norm() == Approx(0).margin(1e-12));
  CHECK((SE3d::exp(o.truth).matrix() - c.X_fs.inverse().matrix()).norm() == Approx(0).margin(1e-9));
}

TEST_CASE("observation: calibration from the project's GDN model card", "[sim][observation]") {
  GdnCalibration c = GdnCalibration::paperTable1();
  CHECK_FALSE(GdnCalibration::fromModelCard("/nonexistent/model_card.json", c));
  CHECK(c.mae[0] == Approx(0.426));  // unchanged on failure
  const std::string card = std::string(LIESERVO_SOURCE_DIR) + "/examples/gdn/models/model_card.json";
  if (!GdnCalibration::fromModelCard(card, c)) {
    WARN("no model card at " << card << ": skipping");
    return;
  }
  for (int i = 0; i < 6; ++i) CHECK(c.mae[i] > 0);
  CHECK(c.mae[3] < 0.2);  // converted to radians
  CHECK(c.source.find("model card") != std::string::npos);
  // The reproduction model never saw val: its validation MAE. The deployed model (train + val):
  // the MAE on the rows it held out, never the validation-set entry.
  CHECK(c.source.find("validation set (n = 2000)") != std::string::npos);
  const double shear_paper_model = c.mae[0];
  const std::string deployed = std::string(LIESERVO_SOURCE_DIR) + "/examples/gdn/models/train_val/model_card.json";
  REQUIRE(GdnCalibration::fromModelCard(deployed, c));
  CHECK(c.source.find("held-out rows (n = 1000)") != std::string::npos);
  CHECK(c.mae[0] != shear_paper_model);
  CHECK(c.mae[0] == Approx(0.504).margin(0.001));  // data.held_out of the card: 500 train + 500 val rows
}

TEST_CASE("observation: a card without a measured MAE is refused, the calibration kept", "[sim][observation]") {
  const std::string dir = file_test::makeTempDir("sim_card");
  const std::string card = dir + "/model_card.json";
  GdnCalibration c = GdnCalibration::paperTable1();
  for (const char* text : {R"({"models": {"gdn": {}}})", R"({"models": {"gdn": {"held_out": {"mae": {"rho1_mm": 0.5}}}}})",
                           R"({"models": {"gdn": {"validation": {"mae": {"rho1_mm": 0.5, "rho2_mm": 0.5, "rho3_mm": 0.1,
                               "phi1_deg": 0.4, "phi2_deg": 0.5, "phi3_deg": -1}}}}})",
                           "{not json"}) {
    std::ofstream(card) << text;
    INFO(text);
    CHECK_FALSE(GdnCalibration::fromModelCard(card, c));
    CHECK(c.mae[0] == Approx(0.426));
  }
  std::ofstream(card) << R"({"models": {"gdn": {"validation": {"n": 7, "mae": {"rho1_mm": 0.5, "rho2_mm": 0.5,
      "rho3_mm": 0.1, "phi1_deg": 0.4, "phi2_deg": 0.5, "phi3_deg": 1.2}}}}})";
  REQUIRE(GdnCalibration::fromModelCard(card, c));
  CHECK(c.mae[3] == Approx(0.4 * kPi / 180));
  CHECK(c.source.find("validation set (n = 7)") != std::string::npos);
  file_test::removeTree(dir);
}
