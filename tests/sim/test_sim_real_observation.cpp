// The `real` observation mode (examples/sim real_observation.hpp) against direct computations:
// only images the card's network did not train on are used (the reproduction model: all of
// val; the deployed model: the rows its card lists as held out); the k-d tree's nearest image
// is the brute-force nearest; at an image's own contact the
// observation is the GDN's output on that image, called directly through the OpenCV adapters;
// elsewhere μ − ξ_true is that image's GDN error; bad set-up names what is missing.
// Skipped with a message when the TacTip data or the exported GDN is absent.
#include <catch2/catch.hpp>

#include <fstream>
#include <set>
#include <string>

#include <lieservo/sampling/random.hpp>
#include <lieservo_adapters/onnx_pose_model.hpp>
#include <lieservo_adapters/preprocessing.hpp>
#include <lieservo_sim/real_observation.hpp>
#include <lieservo_sim/tasks.hpp>

#include "file_test_util.hpp"

using lieservo::sampling::uniform;
using namespace lieservo::sim;
using Catch::Matchers::Contains;

namespace {
const std::string kData = LIESERVO_DATA_DIR;
const std::string kCard = std::string(LIESERVO_SOURCE_DIR) + "/examples/gdn/models/model_card.json";

bool available() {
  if (!std::ifstream(kData + "/train/targets.csv") || !std::ifstream(kData + "/val/targets.csv")) {
    WARN("TacTip data not found under " << kData << ": skipping");
    return false;
  }
  if (!std::ifstream(kCard) || !std::ifstream(std::string(LIESERVO_SOURCE_DIR) + "/examples/gdn/models/gdn.onnx")) {
    WARN("GDN model not exported (" << kCard << "): skipping");
    return false;
  }
  return true;
}

RealGdnObservations& shared() {
  static RealGdnObservations real({kData, kCard, {"train", "val"}});
  return real;
}

// A contact whose true pose is X_fs = Euler6(e) (mm, rad).
ContactState contactAt(const Vec6& e) {
  ContactState c;
  c.in_contact = true;
  c.X_fs = SE3d::fromEulerXYZ6(e);
  c.depth = e[2];
  return c;
}
}  // namespace

TEST_CASE("real observations: the k-d tree's nearest image is the brute-force nearest", "[sim][real]") {
  if (!available()) return;
  RealGdnObservations& real = shared();
  REQUIRE(real.size() == 2000);  // the 2000 val images: the card's network trained on all of train
  // Brute force in the same scaled space: the scale is the labels' standard deviation.
  const std::size_t n = real.size();
  Vec6 mean = Vec6::Zero(), sq = Vec6::Zero();
  for (std::size_t i = 0; i < n; ++i) mean += real.labelEuler(i);
  mean /= double(n);
  for (std::size_t i = 0; i < n; ++i) sq += (real.labelEuler(i) - mean).cwiseAbs2();
  const Vec6 scale = (sq / double(n - 1)).cwiseSqrt();
  lieservo::sampling::Rng rng(7);
  for (int q = 0; q < 2000; ++q) {
    Vec6 e;  // over and beyond the data's range: shear ±7 mm, depth −1…8 mm, tilts ±35°, γ ±8°
    const Vec6 half_range(7, 7, 4.5, deg2rad(35), deg2rad(35), deg2rad(8));
    for (int i = 0; i < 6; ++i) e[i] = half_range[i] * uniform(rng, -1.0, 1.0);
    e[2] += 3.5;
    double best = 1e300;
    for (std::size_t i = 0; i < n; ++i) best = std::min(best, (real.labelEuler(i) - e).cwiseQuotient(scale).squaredNorm());
    const std::size_t k = real.nearest(e);
    INFO("query " << e.transpose());
    CHECK((real.labelEuler(k) - e).cwiseQuotient(scale).squaredNorm() == Approx(best).epsilon(1e-9));
  }
}

TEST_CASE("real observations: at an image's contact the observation is the direct GDN call", "[sim][real]") {
  if (!available()) return;
  RealGdnObservations& real = shared();
  const lieservo::adapters::Preprocessor pre(
      lieservo::adapters::PreprocessParams::fromJsonFile(kData + "/val/processed_image_params.json"));
  lieservo::adapters::OnnxPoseModel gdn =
      lieservo::adapters::OnnxPoseModel::fromCard(kCard, lieservo::adapters::ModelKind::gdn);
  for (std::size_t i = 0; i < real.size(); i += 199) {
    INFO("image " << real.imagePath(i));
    cv::Mat image;
    REQUIRE(pre.loadProcessed(real.imagePath(i), image) == lieservo::Status::ok);
    lieservo::adapters::Prediction direct;
    REQUIRE(gdn.predict(image, direct) == lieservo::Status::ok);
    // At the image's own label: μ = ξ_true + (μ_GDN − ξ_image) = μ_GDN up to rounding.
    GdnObservation obs;
    REQUIRE(real.observe(contactAt(real.labelEuler(i)), obs) == lieservo::Status::ok);
    CHECK((real.labelEuler(real.nearest(real.labelEuler(i))) - real.labelEuler(i)).norm() == 0);
    CHECK((obs.mu - direct.mu).cwiseAbs().maxCoeff() < 1e-9);
    REQUIRE(direct.sigma.has_value());
    CHECK((obs.sigma - *direct.sigma).cwiseAbs().maxCoeff() == 0);
    // 0.02 mm and 0.02° away (still nearest to the same image): the same error carried over.
    Vec6 e = real.labelEuler(i);
    e[0] += 0.02, e[4] += deg2rad(0.02);
    REQUIRE(real.nearest(e) == real.nearest(real.labelEuler(i)));
    REQUIRE(real.observe(contactAt(e), obs) == lieservo::Status::ok);
    CHECK((obs.truth - SE3d::fromEulerXYZ6(e).inverse().log()).norm() < 1e-12);
    CHECK(((obs.mu - obs.truth) - (direct.mu - real.labelXi(i))).cwiseAbs().maxCoeff() < 1e-9);
  }
  CHECK(real.evaluatedImages() >= 10);
  // Bad input: no throw, no observation.
  Vec6 bad = Vec6::Zero();
  bad[2] = std::nan("");
  GdnObservation obs;
  CHECK(real.observe(contactAt(bad), obs) == lieservo::Status::non_finite_input);
}

TEST_CASE("real observations: in the loop, tracking and following meet their criteria", "[sim][real]") {
  if (!available()) return;
  TaskOptions o;
  o.seed = 3;
  o.duration_scale = 0.25;
  o.observations = std::shared_ptr<ObservationSource>(&shared(), [](ObservationSource*) {});  // not owned
  auto joined = [](const std::vector<std::string>& v) {
    std::string s;
    for (const auto& x : v) s += x + "\n";
    return s;
  };
  const TrackingResult t = runObjectTracking(o);
  INFO(joined(t.failures));
  CHECK(t.success);
  CHECK(t.single_axis.contact_kept);
  CHECK(t.periodic.contact_kept);
  o.duration_scale = 0.3;
  const FollowingResult f = runSurfaceFollowing(o);
  INFO(joined(f.failures));
  CHECK(f.success);
  CHECK(f.ramp.reached_end);
  CHECK(f.dome_pooled.contact_kept);
}

TEST_CASE("real observations: only images the network did not train on", "[sim][real]") {
  if (!available()) return;
  for (std::size_t i = 0; i < shared().size(); ++i)
    REQUIRE(shared().imagePath(i).find("/val/processed_images/") != std::string::npos);
  // The deployed GDN (train + val): exactly the rows its card lists as held out.
  const std::string models = std::string(LIESERVO_SOURCE_DIR) + "/examples/gdn/models/train_val";
  if (!std::ifstream(models + "/model_card.json")) {
    WARN("deployed GDN not exported (" << models << "): skipping");
    return;
  }
  const RealGdnObservations deployed({kData, models + "/model_card.json", {"train", "val"}});
  std::set<std::string> listed;
  const auto rows = file_test::readCsv(models + "/held_out.csv");  // split,sensor_image after a header
  for (std::size_t r = 1; r < rows.size(); ++r) listed.insert(kData + "/" + rows[r].at(0) + "/processed_images/" + rows[r].at(1));
  REQUIRE(listed.size() == 1000);
  REQUIRE(deployed.size() == listed.size());
  for (std::size_t i = 0; i < deployed.size(); ++i) CHECK(listed.count(deployed.imagePath(i)) == 1);
  CHECK_THAT(deployed.describe(), Contains("1000") && Contains("did not train on"));
  // A card whose network saw every image it is offered leaves nothing to observe with.
  CHECK_THROWS_WITH(RealGdnObservations({kData, kCard, {"train"}}),
                    Contains("fewer than two") && Contains("6000 it did"));
}

TEST_CASE("real observations: set-up errors name what is missing", "[sim][real]") {
  CHECK_THROWS_WITH(RealGdnObservations({"/nonexistent/tactip", kCard, {"train", "val"}}),
                    Contains("data set missing") && Contains("/nonexistent/tactip/train/targets.csv"));
  CHECK_THROWS_WITH(RealGdnObservations({kData, kCard, {"test"}}), Contains("only the shared train and val"));
  CHECK_THROWS_WITH(RealGdnObservations({"", kCard, {"train"}}), Contains("data_dir"));
  if (!available()) return;
  CHECK_THROWS_WITH(RealGdnObservations({kData, "/nonexistent/model_card.json", {"val"}}),
                    Contains("/nonexistent/model_card.json"));
}
