// GDN-like observation model (see lieservo_sim/observation_model.hpp).
#include "lieservo_sim/observation_model.hpp"

#include <algorithm>
#include <cmath>
#include <exception>

#include <lieservo_dataset/json.hpp>
#include <lieservo_dataset/paper_tables.hpp>

namespace lieservo::sim {

GdnCalibration GdnCalibration::paperTable1() {
  const auto& m = dataset::PaperTables::gdn_mae;
  return fromValues((Vec6() << m[0], m[1], m[2], m[3], m[4], m[5]).finished(),
                    "paper Table 1 (tab:nn_pose_shear_estimate_results), GDN test MAE");
}

GdnCalibration GdnCalibration::fromValues(const Vec6& m, std::string source) {
  GdnCalibration c;
  c.mae << m[0], m[1], m[2], deg2rad(m[3]), deg2rad(m[4]), deg2rad(m[5]);
  c.source = std::move(source);
  c.validate();
  return c;
}

bool GdnCalibration::fromModelCard(const std::string& path, GdnCalibration& out) {
  // models.gdn.held_out.mae (a model trained on train + val: the rows it never saw), else
  // models.gdn.validation.mae (a model trained on train only: the other recording session).
  dataset::JsonDocument card;
  try {
    card = dataset::readJsonFile(path);
  } catch (const std::exception&) {
    return false;
  }
  using dataset::find;
  const dataset::JsonValue* models = find(card.root, "models");
  const dataset::JsonValue* gdn = models != nullptr ? find(*models, "gdn") : nullptr;
  if (gdn == nullptr || !gdn->IsObject()) return false;
  const char* measured_on = "held_out";
  const dataset::JsonValue* set = find(*gdn, measured_on);
  if (set == nullptr) set = find(*gdn, measured_on = "validation");
  const dataset::JsonValue* mae = set != nullptr ? find(*set, "mae") : nullptr;
  if (mae == nullptr || !mae->IsObject()) return false;
  const char* keys[6] = {"rho1_mm", "rho2_mm", "rho3_mm", "phi1_deg", "phi2_deg", "phi3_deg"};
  Vec6 m;
  for (int i = 0; i < 6; ++i) {
    const dataset::JsonValue* v = find(*mae, keys[i]);
    if (v == nullptr || !v->IsNumber() || !(std::isfinite(v->GetDouble()) && v->GetDouble() > 0)) return false;
    m[i] = v->GetDouble();
  }
  const dataset::JsonValue* count = find(*set, "n");
  const long n = count != nullptr && count->IsNumber() ? long(count->GetDouble()) : 0;
  out = fromValues(m, "project GDN model card (" + path + "), MAE on " +
                          (std::string(measured_on) == "held_out" ? "its held-out rows" : "the validation set") +
                          (n > 0 ? " (n = " + std::to_string(n) + ")" : std::string()));
  return true;
}

void GdnCalibration::validate() const {
  for (int i = 0; i < 6; ++i) requirePositive(mae[i], "GdnCalibration.mae component");
}

GdnObservationModel::GdnObservationModel(const GdnCalibration& calibration, const HeteroscedasticShape& shape,
                                         std::uint64_t seed)
    : calib_(calibration), shape_(shape), rng_(seed) {
  calib_.validate();
  for (int i = 0; i < 6; ++i) {
    requirePositive(shape_.a0[i], "HeteroscedasticShape.a0");
    requireNonNegative(shape_.a_shear[i], "HeteroscedasticShape.a_shear");
    requireNonNegative(shape_.a_depth[i], "HeteroscedasticShape.a_depth");
    requireNonNegative(shape_.a_tilt[i], "HeteroscedasticShape.a_tilt");
  }
  requirePositive(shape_.out_of_contact_factor, "HeteroscedasticShape.out_of_contact_factor");
  // E[h] over the training distribution: E[|s|/5] = 2/3, E[max(0, 1.5 − z)] = 1/11.
  const double sqrt_pi_2 = std::sqrt(kPi / 2);
  for (int i = 0; i < 6; ++i) {
    const double Eh = shape_.a0[i] + shape_.a_shear[i] * (2.0 / 3.0) + shape_.a_depth[i] / 11.0;
    sigma_bar_[i] = calib_.mae[i] * sqrt_pi_2 / Eh;
  }
}

Vec6 GdnObservationModel::sigmaFor(const ContactState& c) const {
  const double r = c.shear.norm();
  const double shallow = std::max(0.0, 1.5 - c.depth);
  const double tilt = std::max(0.0, c.tilt - deg2rad(25)) / deg2rad(10);
  Vec6 s;
  for (int i = 0; i < 6; ++i) {
    double h = shape_.a0[i] + shape_.a_shear[i] * r / 5.0 + shape_.a_depth[i] * std::min(shallow, 3.0) +
               shape_.a_tilt[i] * std::min(tilt, 5.0);
    if (!c.in_contact) h *= shape_.out_of_contact_factor;
    s[i] = sigma_bar_[i] * h;
  }
  return s;
}

GdnObservation GdnObservationModel::observe(const ContactState& c) {
  GdnObservation o;
  o.truth = c.X_fs.inverse().log();  // ξ = log(X_sf)^∨
  o.sigma = sigmaFor(c);
  for (int i = 0; i < 6; ++i) o.mu[i] = o.truth[i] + o.sigma[i] * lieservo::sampling::standardNormal(rng_);
  return o;
}

}  // namespace lieservo::sim
