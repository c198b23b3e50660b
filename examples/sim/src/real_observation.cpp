// The `real` observation mode (see lieservo_sim/real_observation.hpp).
#include "lieservo_sim/real_observation.hpp"

#include <cmath>
#include <exception>
#include <filesystem>
#include <mutex>
#include <optional>

#include <nanoflann.hpp>

#include <lieservo_adapters/onnx_pose_model.hpp>
#include <lieservo_adapters/preprocessing.hpp>
#include <lieservo_dataset/dataset_reader.hpp>
#include <lieservo_dataset/trained_on.hpp>

namespace lieservo::sim {

namespace {
using LabelMatrix = Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::RowMajor>;
using Tree = nanoflann::KDTreeEigenMatrixAdaptor<LabelMatrix, 6, nanoflann::metric_L2_Simple>;
using dataset::fileExists;
}  // namespace

bool RealObservationOptions::dataSetPresent() const {
  // There, readable or not: an unreadable data set is a set-up error, not a reason to fall back.
  std::error_code ec;
  for (const std::string& split : splits)
    if (std::filesystem::exists(data_dir + "/" + split + "/targets.csv", ec)) return true;
  return false;
}

struct RealGdnObservations::Impl {
  std::vector<Vec6> euler, xi;  // per image: label (mm, rad) and ξ_image
  std::vector<std::string> paths;
  Vec6 scale = Vec6::Ones();    // per-component standard deviation of the labels
  LabelMatrix scaled;           // labels / scale, one row per image (the tree's points)
  std::unique_ptr<Tree> tree;
  std::optional<adapters::Preprocessor> pre;
  std::optional<adapters::OnnxPoseModel> gdn;
  struct Cached {
    bool done = false;
    Vec6 mu, sigma;
  };
  std::vector<Cached> cache;
  std::size_t evaluated = 0;
  std::string source, last_error;
  std::mutex mutex;  // the cache and the network, for trials run on several threads

  void addSplit(const std::string& dir, const std::string& split, const dataset::TrainedOn& trained,
                std::size_t& skipped);
  void addPreprocessing(const std::string& params);
  void buildIndex();
  std::string first_params;  // the preprocessing that the first split's images had
};

// The split's labelled images that the network did not train on (`skipped` counts the others).
void RealGdnObservations::Impl::addSplit(const std::string& dir, const std::string& split,
                                         const dataset::TrainedOn& trained, std::size_t& skipped) {
  if (!fileExists(dir + "/targets.csv"))
    throw SceneError("real observations: data set missing: cannot read " + dir + "/targets.csv");
  std::vector<dataset::TargetRow> rows;
  try {
    rows = dataset::readTargetsCsv(dir + "/targets.csv");
  } catch (const std::exception& e) {
    throw SceneError(std::string("real observations: ") + e.what());
  }
  for (const dataset::TargetRow& r : rows) {
    if (trained.saw(split, r.sensor_image)) {
      ++skipped;
      continue;
    }
    Vec6 e = r.euler6Degrees();
    e.tail<3>() *= kPi / 180;
    euler.push_back(e);
    xi.push_back(r.label());
    paths.push_back(dir + "/processed_images/" + r.sensor_image);
  }
}

// Every split's images must have been processed alike: its params file is read and checked (a
// corrupted one is refused), and must agree with the first split's.
void RealGdnObservations::Impl::addPreprocessing(const std::string& params) {
  adapters::PreprocessParams p;
  try {
    if (fileExists(params)) p = adapters::PreprocessParams::fromJsonFile(params);
    p.validate();
  } catch (const std::exception& e) {
    throw SceneError(std::string("real observations: ") + e.what());
  }
  if (!pre) {
    pre.emplace(p);
    first_params = params;
    return;
  }
  const adapters::PreprocessParams& q = pre->params();
  if (p.processedSize() != q.processedSize() || p.gray != q.gray || p.threshold != q.threshold ||
      p.threshold_block != q.threshold_block || p.threshold_c != q.threshold_c ||
      p.circle_mask_radius != q.circle_mask_radius)
    throw SceneError("real observations: " + params + " processes images differently from " + first_params);
}

// Scale: each component's standard deviation over the data, so that a millimetre of depth and a
// degree of tilt weigh by how much the data set varies them; then the k-d tree over the labels.
void RealGdnObservations::Impl::buildIndex() {
  const std::size_t n = euler.size();
  Vec6 mean = Vec6::Zero(), sq = Vec6::Zero();
  for (const Vec6& e : euler) mean += e;
  mean /= double(n);
  for (const Vec6& e : euler) sq += (e - mean).cwiseAbs2();
  for (int j = 0; j < 6; ++j) {
    const double sd = std::sqrt(sq[j] / double(n - 1));
    scale[j] = sd > 0 ? sd : 1.0;
  }
  scaled.resize(Eigen::Index(n), 6);
  for (std::size_t i = 0; i < n; ++i) scaled.row(Eigen::Index(i)) = euler[i].cwiseQuotient(scale).transpose();
  tree = std::make_unique<Tree>(6, std::cref(scaled), 10);  // builds the index
  cache.resize(n);
}

RealGdnObservations::RealGdnObservations(const RealObservationOptions& o) : impl_(std::make_unique<Impl>()) {
  Impl& I = *impl_;
  if (o.data_dir.empty()) throw SceneError("real observations: data_dir is empty (the TacTip data set)");
  if (o.splits.empty()) throw SceneError("real observations: no splits given");
  if (!fileExists(o.model_card)) throw SceneError("real observations: cannot read the model card " + o.model_card);
  // Only images the network did not train on: their errors are what a new contact shows.
  dataset::TrainedOn trained;
  try {
    trained = dataset::readTrainedOn(o.model_card);
  } catch (const std::exception& e) {
    throw SceneError(std::string("real observations: ") + e.what());
  }
  std::size_t skipped = 0;
  for (const std::string& split : o.splits) {
    if (split != "train" && split != "val")
      throw SceneError("real observations: split '" + split + "' (only the shared train and val sets may be used)");
    const std::string dir = o.data_dir + "/" + split;
    I.addSplit(dir, split, trained, skipped);
    I.addPreprocessing(dir + "/processed_image_params.json");
  }
  if (I.euler.size() < 2)
    throw SceneError("real observations: fewer than two labelled images in " + o.data_dir + " that the model of " +
                     o.model_card + " did not train on (" + std::to_string(skipped) + " it did)");
  I.buildIndex();
  const std::size_t n = I.euler.size();
  try {
    I.gdn.emplace(adapters::OnnxPoseModel::fromCard(o.model_card, adapters::ModelKind::gdn));
  } catch (const std::exception& e) {
    throw SceneError(std::string("real observations: ") + e.what());
  }
  I.source = "the project's GDN on the nearest of " + std::to_string(n) + " labelled TacTip images it did not train on (" +
             o.data_dir + "; model card " + o.model_card + ")";
}

RealGdnObservations::~RealGdnObservations() = default;

std::size_t RealGdnObservations::size() const noexcept { return impl_->euler.size(); }
const Vec6& RealGdnObservations::labelEuler(std::size_t i) const { return impl_->euler.at(i); }
const Vec6& RealGdnObservations::labelXi(std::size_t i) const { return impl_->xi.at(i); }
const std::string& RealGdnObservations::imagePath(std::size_t i) const { return impl_->paths.at(i); }
std::size_t RealGdnObservations::evaluatedImages() const noexcept { return impl_->evaluated; }
const std::string& RealGdnObservations::lastError() const noexcept { return impl_->last_error; }
std::string RealGdnObservations::describe() const { return impl_->source; }

std::size_t RealGdnObservations::nearest(const Vec6& euler) const noexcept {
  const Vec6 q = euler.cwiseQuotient(impl_->scale);
  Eigen::Index index = 0;
  double d2 = 0;
  impl_->tree->query(q.data(), 1, &index, &d2);
  return std::size_t(index);
}

Status RealGdnObservations::prediction(std::size_t i, Vec6& mu, Vec6& sigma) noexcept {
  Impl& I = *impl_;
  if (i >= I.cache.size()) return Status::invalid_argument;
  const std::lock_guard<std::mutex> lock(I.mutex);
  Impl::Cached& c = I.cache[i];
  if (!c.done) {
    try {
      cv::Mat image;
      Status s = I.pre->loadProcessed(I.paths[i], image);
      if (s != Status::ok) {
        I.last_error = I.pre->lastError();  // names the file
        return s;
      }
      adapters::Prediction p;
      s = I.gdn->predict(image, p);
      if (s != Status::ok) {
        I.last_error = I.paths[i] + ": " + I.gdn->lastError();
        return s;
      }
      if (!p.sigma) {
        I.last_error = I.paths[i] + ": the model gives no sigma (a CNN, not a GDN)";
        return Status::invalid_argument;
      }
      c.mu = p.mu;
      c.sigma = *p.sigma;
      c.done = true;
      ++I.evaluated;
    } catch (const std::exception& e) {  // e.g. out of memory: the per-step path never throws
      I.last_error = I.paths[i] + ": " + e.what();
      return Status::invalid_argument;
    }
  }
  mu = c.mu;
  sigma = c.sigma;
  return Status::ok;
}

Status RealGdnObservations::observe(const ContactState& contact, GdnObservation& out) noexcept {
  const Vec6 e = contact.label();
  if (!e.allFinite()) return Status::non_finite_input;
  const std::size_t i = nearest(e);
  Vec6 mu, sigma;
  const Status s = prediction(i, mu, sigma);
  if (s != Status::ok) return s;
  out.truth = contact.X_fs.inverse().log();  // ξ_true = log(X_sf)^∨
  out.mu = out.truth + (mu - impl_->xi[i]);
  out.sigma = sigma;
  return Status::ok;
}

}  // namespace lieservo::sim
