// The table replay (examples/replay): labels, targets.csv reading, the Table 2 filter
// experiment on a synthetic sequence, and an end-to-end run on the tiny models.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <lieservo/sampling/random.hpp>
#include "lieservo/estimation/concentrated_gaussian.hpp"
#include "file_test_util.hpp"
#include "plots.hpp"
#include "replay.hpp"
#include "svg_test_util.hpp"

using lieservo::sampling::standardNormal;
using lieservo::sampling::uniform;
using namespace lieservo;
using namespace lieservo::replay;

namespace {

/// A models dir laid out like examples/gdn/models, holding the tiny random test models.
std::string tinyModelsDir(const char* name) {
  const std::string tiny = std::string(LIESERVO_SOURCE_DIR) + "/tests/adapters/data";
  const std::string models = file_test::makeTempDir(name);
  namespace fs = std::filesystem;
  fs::copy_file(tiny + "/tiny_model_card.json", models + "/model_card.json");
  fs::copy_file(tiny + "/tiny_gdn.onnx", models + "/tiny_gdn.onnx");
  fs::copy_file(tiny + "/tiny_cnn.onnx", models + "/tiny_cnn.onnx");
  return models;
}

/// Whether the real data's train split is there (a test that needs it skips with a message).
bool haveTrainSplit(const std::string& data) {
  if (file_test::exists(data + "/train/targets.csv")) return true;
  WARN("TacTip data not found under " << data << ": skipping");
  return false;
}

/// Options replaying the real train split through the tiny test GDN (no CNN, quiet).
ReplayOptions tinyTrainReplay(const std::string& data, const std::string& models) {
  ReplayOptions o;
  o.data_dir = data;
  o.split = "train";
  o.models_dir = models;
  o.verbose = false;
  o.run_cnn = false;
  return o;
}

/// Whether an SVG colour "#rrggbb" is saturated (max − min channel > 60): the markers' colours;
/// frame, grid, labels and the diagonal are grey or black.
bool saturated(const std::string& colour) {
  if (colour.size() != 7 || colour[0] != '#') return false;
  const int r = std::stoi(colour.substr(1, 2), nullptr, 16), g = std::stoi(colour.substr(3, 2), nullptr, 16),
            b = std::stoi(colour.substr(5, 2), nullptr, 16);
  return std::max({r, g, b}) - std::min({r, g, b}) > 60;
}

}  // namespace

TEST_CASE("replay: every scatter-plot panel shows its data, an empty plot shows none",
          "[replay][plots]") {
  const std::string dir = file_test::makeTempDir("replay_plots");
  // 50 points per component inside the axes (actual = predicted ± a little).
  std::vector<Vec6> actual, predicted, precision;
  lieservo::sampling::Rng rng(7);
  for (int i = 0; i < 50; ++i) {
    Vec6 a, p, q;
    for (std::size_t j = 0; j < 6; ++j) {
      a[j] = uniform(rng, -5.0, 5.0);
      p[j] = a[j] + 0.1 * uniform(rng, -5.0, 5.0);
      q[j] = 1.0 + std::fabs(uniform(rng, -5.0, 5.0));
    }
    actual.push_back(a);
    predicted.push_back(p);
    precision.push_back(q);
  }
  writeScatterPlot(dir + "/coloured.svg", "coloured", actual, predicted, precision);
  writeScatterPlot(dir + "/plain.svg", "plain", actual, predicted, {});
  writeScatterPlot(dir + "/empty.svg", "empty", {}, {}, {});
  // Every point is a saturated marker in its panel, at least 45 of the 50 inside the frame (the
  // axes span the actual values plus 5 %, so a prediction may fall just outside and be clipped);
  // nothing else in a panel is saturated.
  for (const char* name : {"coloured.svg", "plain.svg"}) {
    const auto ps = svg_test::panels(svg_test::slurp(dir + "/" + name));
    REQUIRE(ps.size() == 6);
    for (std::size_t c = 0; c < 6; ++c) {
      INFO(name << " panel " << c);
      CHECK(ps[c].circles.size() == 50);
      int inside = 0;
      for (const auto& m : ps[c].circles) {
        CHECK(saturated(m.fill));
        inside += ps[c].inside(m.x, m.y);
      }
      CHECK(inside >= 45);
      for (const auto& l : ps[c].lines) CHECK_FALSE(saturated(l.colour));
    }
  }
  // Coloured by precision: the most precise point is drawn last, in red.
  const auto coloured = svg_test::panels(svg_test::slurp(dir + "/coloured.svg"));
  for (std::size_t c = 0; c < 6; ++c) {
    const std::string last = coloured[c].circles.back().fill;
    CHECK(std::stoi(last.substr(1, 2), nullptr, 16) > 100);
    CHECK(std::stoi(last.substr(3, 2), nullptr, 16) < 60);
  }
  const auto none = svg_test::panels(svg_test::slurp(dir + "/empty.svg"));
  REQUIRE(none.size() == 6);
  for (const auto& p : none) CHECK(p.circles.empty());
  // An unwritable path is an error.
  CHECK_THROWS_AS(writeScatterPlot(dir + "/no_such_dir/x.svg", "x", actual, predicted, {}), std::runtime_error);
}

TEST_CASE("replay: labels match the Python reference (examples/gdn/labels_reference.csv)", "[replay]") {
  const std::string path = std::string(LIESERVO_SOURCE_DIR) + "/examples/gdn/labels_reference.csv";
  if (!file_test::exists(path)) {
    WARN(path << " not found: skipping");
    return;
  }
  const auto rows = file_test::readCsv(path);
  REQUIRE(rows.size() > 5);
  REQUIRE(rows[0].size() == 13);
  for (std::size_t r = 1; r < rows.size(); ++r) {
    Vec6 e;
    for (std::size_t j = 0; j < 6; ++j) e[j] = std::stod(rows[r][1 + j]);
    const Vec6 xi = labelFromEulerDegrees(e);
    for (std::size_t j = 0; j < 6; ++j) CHECK(xi[j] == Approx(std::stod(rows[r][7 + j])).margin(1e-9));
  }
}

TEST_CASE("replay: targets.csv reading and its errors", "[replay]") {
  const std::string dir = file_test::makeTempDir("targets");
  const std::string csv = dir + "/targets.csv";
  const std::string header =
      "sensor_image,pose_x,pose_y,pose_z,pose_Rx,pose_Ry,pose_Rz,shear_x,shear_y,shear_z,shear_Rx,shear_Ry,shear_Rz\n";
  std::ofstream(csv) << header << "image_1.png,0,0,1.5,2,-3,0,0.5,-1,0,0,0,4\n";
  const auto s = readTargets(csv);
  REQUIRE(s.size() == 1);
  CHECK(s[0].image == "image_1.png");
  const Vec6 expected_euler = (Vec6() << 0.5, -1, 1.5, 2, -3, 4).finished();
  for (std::size_t j = 0; j < 6; ++j) CHECK(s[0].euler[j] == expected_euler[j]);
  // ξ = log(X_fs⁻¹): the translation of X_sf = -R_fsᵀ t_fs, so for small angles ρ ≈ -t.
  CHECK(s[0].xi[2] == Approx(-1.5).margin(0.15));

  std::ofstream(csv) << header << "image_1.png,0,0,1.5,2,-3,0,0.5,abc,0,0,0,4\n";
  CHECK_THROWS_WITH(readTargets(csv), Catch::Contains(csv + ":2") && Catch::Contains("shear_y"));
  std::ofstream(csv) << "sensor_image,pose_x\nimage_1.png,0\n";
  CHECK_THROWS_WITH(readTargets(csv), Catch::Contains(csv + ":1") && Catch::Contains("header has 2 columns"));
  std::ofstream(csv) << header << "image_1.png,0,0\n";
  CHECK_THROWS_WITH(readTargets(csv), Catch::Contains(csv + ":2") && Catch::Contains("row has 3 fields"));
  CHECK_THROWS_WITH(readTargets(dir + "/none.csv"), Catch::Contains("cannot open"));
  file_test::removeTree(dir);
}

namespace {

/// A synthetic sequence of random contacts in the data set's ranges, with GDN-like noisy
/// observations of known σ (mm, deg).
void syntheticSequence(std::size_t n, std::vector<Sample>& samples, std::vector<ConcentratedGaussian<SE3d>>& obs) {
  lieservo::sampling::Rng rng(7);
  const double sigma[6] = {0.5, 0.5, 0.15, 0.6 * lieservo::pi<double>() / 180, 0.8 * lieservo::pi<double>() / 180, 1.5 * lieservo::pi<double>() / 180};
  samples.clear();
  obs.clear();
  for (std::size_t i = 0; i < n; ++i) {
    Sample s;
    s.image = "synthetic_" + std::to_string(i);
    s.euler = {5 * uniform(rng, -1.0, 1.0) / 1.5, 5 * uniform(rng, -1.0, 1.0) / 1.5, 3.25 + 2.75 * uniform(rng, -1.0, 1.0), 25 * uniform(rng, -1.0, 1.0), 25 * uniform(rng, -1.0, 1.0), 5 * uniform(rng, -1.0, 1.0)};
    s.xi = labelFromEulerDegrees(s.euler);
    SE3d::Tangent mu, sd;
    for (int j = 0; j < 6; ++j) {
      sd(j) = sigma[j];
      mu(j) = s.xi[static_cast<std::size_t>(j)] + sigma[j] * standardNormal(rng);
    }
    ConcentratedGaussian<SE3d> o;
    REQUIRE(fromTangentGaussian(mu, sd, o) == Status::ok);
    samples.push_back(s);
    obs.push_back(o);
  }
}

}  // namespace

TEST_CASE("replay: Table 2 filter experiment on a synthetic sequence", "[replay][filter]") {
  std::vector<Sample> samples;
  std::vector<ConcentratedGaussian<SE3d>> obs;
  syntheticSequence(400, samples, obs);
  const FilterRun raw = replayFilter(samples, obs, 1e6, 1);  // effectively no filtering
  const FilterRun f10 = replayFilter(samples, obs, 10.0, 1);
  const FilterRun f01 = replayFilter(samples, obs, 0.1, 1);
  const FilterRun f001 = replayFilter(samples, obs, 0.01, 1);
  REQUIRE(raw.mu.size() == 400);
  for (std::size_t j = 0; j < 6; ++j) {
    INFO("component " << j);
    CHECK(raw.row.failures == 0);
    CHECK(f001.row.failures == 0);
    // Observation-noise MAE ≈ σ sqrt(2/π).
    // σψ = 10 barely filters; 0.1 and 0.01 reduce the error, the smaller the more.
    CHECK(f10.row.mae[j] == Approx(raw.row.mae[j]).epsilon(0.1));
    CHECK(f01.row.mae[j] < 0.8 * raw.row.mae[j]);
    CHECK(f001.row.mae[j] < f01.row.mae[j]);
    CHECK(f001.row.mae[j] < 0.35 * raw.row.mae[j]);
    // And the filtered uncertainty shrinks accordingly.
    CHECK(f001.row.mean_sigma[j] < f10.row.mean_sigma[j]);
  }
  // Deterministic for a seed.
  const FilterRun again = replayFilter(samples, obs, 0.1, 1);
  for (std::size_t j = 0; j < 6; ++j) CHECK(again.row.mae[j] == f01.row.mae[j]);
  // The converged rule: fewer updates than the paper's 5, the same errors (within 1e-4 mm and
  // 1e-4 deg per component: it stops within 1e-6 of the converged result, as 5 iterations do).
  for (const FilterRun* paper : {&f10, &f01, &f001}) {
    const FilterRun rule =
        replayFilter(samples, obs, paper->row.sigma_psi, 1, lieservo::FusionOptions<double>::converged(), true);
    INFO("sigma_psi " << paper->row.sigma_psi << ": " << rule.row.mean_iterations << " updates per correction");
    CHECK(paper->row.mean_iterations == 5.0);
    CHECK(rule.row.mean_iterations >= 1.0);
    CHECK(rule.row.mean_iterations < 5.0);
    CHECK(rule.row.failures == 0);
    for (std::size_t j = 0; j < 6; ++j) CHECK(std::fabs(rule.row.mae[j] - paper->row.mae[j]) <= 1e-4);
    // Its fusion error against the fusion run to convergence on the same inputs stays under its
    // tolerance (0.001 σ); a single update's is larger, so the measure can tell them apart.
    lieservo::FusionOptions<double> one;
    one.max_iterations = 1;
    const FusionError e = rule.fusion_error;
    const FusionError e1 = replayFilter(samples, obs, paper->row.sigma_psi, 1, one, true).fusion_error;
    INFO("fusion error: converged rule " << e.sigma << " sigma, one update " << e1.sigma << " sigma");
    CHECK(e.sigma <= 1e-3);
    CHECK(e1.sigma > e.sigma);
    CHECK(e1.mm + e1.rad > e.mm + e.rad);
    CHECK(paper->fusion_error.sigma == 0.0);  // not measured unless asked
  }
}

TEST_CASE("replay: end to end on real images with the tiny test models", "[replay][data]") {
  const std::string data = LIESERVO_DATA_DIR;
  if (!file_test::exists(data + "/val/targets.csv")) {
    WARN("TacTip data not found under " << data << ": skipping");
    return;
  }
  const std::string models = tinyModelsDir("replay_models");
  ReplayOptions o;
  o.data_dir = data;
  o.models_dir = models;
  o.quick = 40;
  o.verbose = false;
  o.plot_dir = models + "/plots";
  o.cache_file = models + "/cache.txt";
  const ReplayResults r = runReplay(o);
  CHECK(r.n == 40);
  CHECK(r.have_gdn);
  CHECK(r.have_cnn);
  CHECK_FALSE(r.inference_cached);
  REQUIRE(r.filter.size() == 4);
  REQUIRE(r.filter_converged.size() == 4);
  for (std::size_t j = 0; j < 6; ++j) {
    CHECK(std::isfinite(r.gdn_mae[j]));
    CHECK(std::isfinite(r.cnn_mae[j]));
    for (const auto& row : r.filter) CHECK(std::isfinite(row.mae[j]));
    // The converged rule on real observations: the paper's errors (1e-4 mm and deg).
    for (std::size_t i = 0; i < 4; ++i) CHECK(std::fabs(r.filter_converged[i].mae[j] - r.filter[i].mae[j]) <= 1e-4);
  }
  for (const auto& row : r.filter_converged) CHECK(row.mean_iterations < 5.0);
  REQUIRE(r.converged_rule_error.size() == 4);
  for (const auto& e : r.converged_rule_error) CHECK(e.sigma <= 1e-3);
  CHECK(std::isfinite(r.gdn_nll_rad));
  CHECK(r.plots.size() == 6);
  for (const auto& p : r.plots) {
    // Every panel of every figure the replay writes holds its 40 points.
    const auto ps = svg_test::panels(svg_test::slurp(p));
    REQUIRE(ps.size() == 6);
    for (std::size_t c = 0; c < 6; ++c) {
      INFO(p << " panel " << c);
      CHECK(ps[c].circles.size() == 40);
    }
  }
  // The tiny card lists no data: the report says so and does not call the split "validation".
  CHECK_THAT(r.split_role, Catch::Matchers::Contains("`val` split") &&
                               Catch::Matchers::Contains("not listed in the model card"));
  const std::string md = r.markdown(o, "lieservo_replay --quick 40");
  CHECK(md.find("validation") == std::string::npos);
  CHECK(md.find(r.split_role) != std::string::npos);
  CHECK(md.find("Table 1") != std::string::npos);
  CHECK(md.find("Table 2") != std::string::npos);
  CHECK(md.find("lieservo_replay --quick 40") != std::string::npos);
  CHECK(r.table().find("GDN ours") != std::string::npos);
  // Second run: from the cache, same numbers.
  const ReplayResults c = runReplay(o);
  CHECK(c.inference_cached);
  for (std::size_t j = 0; j < 6; ++j) CHECK(c.gdn_mae[j] == Approx(r.gdn_mae[j]).epsilon(1e-6));
  CHECK_FALSE(c.have_calibration);
  CHECK(c.filter_calibrated.empty());

  // A card with a σ calibration: the paper's tables stay as they were (the network's σ), and
  // Table 2 is repeated with the scaled σ.
  {
    std::ifstream in(models + "/model_card.json");
    std::string card((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string at = "\"gdn\": {";
    REQUIRE(card.find(at) != std::string::npos);
    card.insert(card.find(at) + at.size(), R"("sigma_calibration": {"scale": [1, 1, 1, 3, 3, 1], "source": "unit test"},)");
    std::ofstream(models + "/model_card.json") << card;
  }
  const ReplayResults k = runReplay(o);
  REQUIRE(k.have_calibration);
  CHECK(k.calibration_source == "unit test");
  REQUIRE(k.filter_calibrated.size() == k.filter.size());
  for (std::size_t j = 0; j < 6; ++j) {
    CHECK(k.gdn_mae[j] == c.gdn_mae[j]);
    CHECK(k.gdn_coverage[j] == c.gdn_coverage[j]);
    for (std::size_t i = 0; i < k.filter.size(); ++i) CHECK(k.filter[i].mae[j] == c.filter[i].mae[j]);
    if (j == 3 || j == 4) CHECK(k.gdn_coverage_calibrated[j] > k.gdn_coverage[j]);  // σ × 3 covers more
    else CHECK(k.gdn_coverage_calibrated[j] == k.gdn_coverage[j]);
  }
  bool changed = false;  // a tilt σ three times larger changes the filtered tilts
  for (std::size_t i = 0; i < k.filter.size(); ++i)
    changed = changed || k.filter_calibrated[i].mae[3] != k.filter[i].mae[3];
  CHECK(changed);
  const std::string kmd = k.markdown(o, "lieservo_replay --quick 40");
  CHECK(kmd.find("Table 2 with the model card's σ calibration") != std::string::npos);
  CHECK(kmd.find("unit test") != std::string::npos);
  CHECK(md.find("calibration") == std::string::npos);

  // Missing model: clear error.
  std::filesystem::remove(models + "/tiny_gdn.onnx");
  o.cache_file.clear();
  CHECK_THROWS_WITH(runReplay(o), Catch::Contains("tiny_gdn.onnx"));
  file_test::removeTree(models);
}

TEST_CASE("replay: the report's caveat comes from the model card and the split", "[replay]") {
  const std::string dir = file_test::makeTempDir("replay_card");
  const std::string card = dir + "/model_card.json";
  std::ofstream(card) << R"J({"data": {"train": 6000, "val": 2000, "test": "not used (held out)"},
    "models": {"gdn": {"training": {"early_stopping": "patience 25 on val loss"}}}})J";
  CHECK_THAT(splitRole(card, "val"), Catch::Matchers::Contains("`val` split was used for model selection") &&
                                         Catch::Matchers::Contains("optimistic"));
  CHECK_THAT(splitRole(card, "train"), Catch::Matchers::Contains("trained on"));
  CHECK_THAT(splitRole(card, "test"), Catch::Matchers::Contains("not used (held out)"));
  CHECK_THAT(splitRole(card, "session2"), Catch::Matchers::Contains("not listed"));
  for (const char* split : {"train", "test", "session2"})
    CHECK(splitRole(card, split).find("validation") == std::string::npos);
  CHECK_THAT(splitRole(dir + "/missing.json", "val"), Catch::Matchers::Contains("cannot be read"));
  // A card trained on part of a split: the report says the numbers mix seen and unseen images.
  const std::string part = dir + "/part.json";
  std::ofstream(part) << R"J({"data": {"train": 4, "val": 2, "trained_on": {"train": 3, "val": 1},
    "held_out": {"train": 1, "val": 1, "file": "part_held_out.csv"}}})J";
  std::ofstream(dir + "/part_held_out.csv") << "split,sensor_image\ntrain,image_1.png\nval,image_2.png\n";
  CHECK_THAT(splitRole(part, "val"), Catch::Matchers::Contains("trained on 1 of its images") &&
                                         Catch::Matchers::Contains("mix trained-on and unseen"));
  CHECK_THAT(splitRole(part, "session2"), Catch::Matchers::Contains("not listed"));
  // The shipped cards: the reproduction model trained on all of train, and val is the
  // early-stopping split of its CNN; the deployed model trained on most of both.
  const std::string models = std::string(LIESERVO_SOURCE_DIR) + "/examples/gdn/models";
  CHECK_THAT(splitRole(models + "/model_card.json", "val"), Catch::Matchers::Contains("model selection"));
  CHECK_THAT(splitRole(models + "/model_card.json", "train"), Catch::Matchers::Contains("is what the network was trained on"));
  CHECK_THAT(splitRole(models + "/train_val/model_card.json", "val"),
             Catch::Matchers::Contains("trained on 1500 of its images (the other 500"));
}

TEST_CASE("replay: --unseen-only keeps the images the network did not train on", "[replay][data]") {
  const std::string data = LIESERVO_DATA_DIR;
  if (!haveTrainSplit(data)) return;
  const std::string models = tinyModelsDir("replay_unseen");
  ReplayOptions o = tinyTrainReplay(data, models);
  o.unseen_only = true;
  // The tiny card lists no training data: by convention its network saw all of train.
  CHECK_THROWS_WITH(runReplay(o), Catch::Matchers::Contains("trained on every image"));
  // A card that held two train images out: exactly those two are replayed, in file order.
  const std::vector<Sample> rows = readTargets(data + "/train/targets.csv");
  REQUIRE(rows.size() > 10);
  std::string card;
  {
    std::ifstream in(models + "/model_card.json");
    card.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  const std::size_t brace = card.find('{');
  REQUIRE(brace != std::string::npos);
  card.insert(brace + 1, "\"data\": {\"train\": " + std::to_string(rows.size()) + ", \"trained_on\": {\"train\": " +
                             std::to_string(rows.size() - 2) +
                             "}, \"held_out\": {\"train\": 2, \"file\": \"held_out.csv\"}}, ");
  std::ofstream(models + "/model_card.json") << card;
  std::ofstream(models + "/held_out.csv") << "split,sensor_image\ntrain," << rows[7].image << "\ntrain," << rows[3].image
                                          << "\n";
  const ReplayResults r = runReplay(o);
  CHECK(r.n == 2);
  CHECK(r.unseen_of == static_cast<int>(rows.size()));
  const std::string md = r.markdown(o, "lieservo_replay --split train --unseen-only");
  CHECK(md.find("`--unseen-only`") != std::string::npos);
  CHECK(md.find("the 2 of the " + std::to_string(rows.size()) + " images") != std::string::npos);
  // A held-out list that does not match the card is refused, naming the list.
  std::ofstream(models + "/held_out.csv") << "split,sensor_image\ntrain," << rows[7].image << "\n";
  CHECK_THROWS_WITH(runReplay(o), Catch::Matchers::Contains("held_out.csv"));
  file_test::removeTree(models);
}

TEST_CASE("replay: --split replays another split of the data", "[replay][data]") {
  const std::string data = LIESERVO_DATA_DIR;
  if (!haveTrainSplit(data)) return;
  const std::string models = tinyModelsDir("replay_split");
  ReplayOptions o = tinyTrainReplay(data, models);
  o.quick = 20;
  const ReplayResults r = runReplay(o);
  CHECK(r.n == 20);
  const std::string md = r.markdown(o, "lieservo_replay --split train --quick 20");
  CHECK(md.find("/train`") != std::string::npos);
  CHECK(md.find("trained on") != std::string::npos);
  CHECK(md.find("validation") == std::string::npos);
  o.split = "no_such_split";
  CHECK_THROWS_WITH(runReplay(o), Catch::Matchers::Contains("no_such_split/targets.csv"));
}

TEST_CASE("replay: the main job's files go into its results folder, none without one", "[replay]") {
  ReplayOptions opt;
  setDemoOutputs(opt, "results");
  CHECK(opt.cache_file == "results/replay_network_outputs.txt");
  CHECK(opt.plot_dir == "results/replay");
  // lieservo_demo --no-files: no folder, so no cache and no plots (not "/replay…" at the root).
  setDemoOutputs(opt, "");
  CHECK(opt.cache_file.empty());
  CHECK(opt.plot_dir.empty());
}
