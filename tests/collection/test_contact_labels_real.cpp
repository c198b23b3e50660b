// The composition X_fs = X_par·X_perp against the real TacTip data set's labels
// (LIESERVO_DATA_DIR/train/targets.csv) and against the GDN engineer's numpy reference labels
// (examples/gdn/labels_reference.csv). Skips with a WARN when the files are absent.
#include <catch2/catch.hpp>

#include <lieservo/groups/se3.hpp>
#include <lieservo/sampling.hpp>
#include "contact_sampling.hpp"
#include <lieservo/units.hpp>

#include <lieservo_dataset/dataset_reader.hpp>
#include "goodness_of_fit.hpp"
#include "test_support.hpp"

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

using lieservo::SE3;
using namespace lieservo::sampling;
namespace col = lieservo::dataset;

namespace {

bool haveFile(const std::string& p) { return std::ifstream(p).good(); }

}  // namespace

TEST_CASE("real train rows: pose_* is X_perp, shear_* is X_par, X_par*X_perp is the label", "[sampling][real-data]") {
  const std::string csv = lieservo::test::dataDir() + "/train/targets.csv";
  if (!haveFile(csv)) {
    WARN("SKIPPED: real data not found at " << csv);
    return;
  }
  col::TargetsReadOptions opt;
  opt.max_rows = 50;
  const auto rows = col::readTargetsCsv(csv, opt);
  REQUIRE(rows.size() == 50);
  for (const auto& r : rows) {
    INFO(csv << ":" << r.line << " " << r.sensor_image);
    REQUIRE(r.componentsSeparated());
    const auto pose = SurfaceContactPose<double>::fromEuler6Degrees(r.euler6Degrees());
    const SE3<double> X_perp = SE3<double>::fromEulerXYZ6Degrees(r.poseEuler6Degrees());
    const SE3<double> X_par = SE3<double>::fromEulerXYZ6Degrees(r.shearEuler6Degrees());
    // our factors are the data set's factors
    REQUIRE(normalContactTransform(pose.z, pose.alpha, pose.beta).isApprox(X_perp, 1e-13));
    REQUIRE(shearTransform(pose.x, pose.y, pose.gamma).isApprox(X_par, 1e-13));
    // the product is the Euler 6-vector (shear_x, shear_y, pose_z, pose_Rx, pose_Ry, shear_Rz)
    const SE3<double> X_fs = surfaceContactTransform(pose);
    REQUIRE((X_fs.matrix() - (X_par * X_perp).matrix()).cwiseAbs().maxCoeff() < 1e-13);
    REQUIRE((X_fs.matrix() - SE3<double>::fromEulerXYZ6Degrees(r.euler6Degrees()).matrix()).cwiseAbs().maxCoeff() < 1e-13);
    REQUIRE((X_fs.toEulerXYZ6Degrees() - r.euler6Degrees()).cwiseAbs().maxCoeff() < 1e-10);
    // inside the paper's ranges
    REQUIRE(std::hypot(pose.x, pose.y) <= 5.0);
    REQUIRE(capPolar(pose.alpha, pose.beta)(0) <= lieservo::deg2rad(25.0) + 1e-9);
    REQUIRE(pose.z >= 0.5);
    REQUIRE(pose.z <= 6.0);
    REQUIRE(std::abs(r.shear[5]) <= 5.0);
  }
}

TEST_CASE("real data sets are consistent with the disk and cap distributions", "[sampling][real-data][statistics]") {
  // Evidence that we read eq. 1 (eqn:disk_random_sampling) / eq. 2 (eqn:sphere_random_sampling) as the authors
  // did: the collected (x, y) and (α, β) pass the same KS tests (α = 0.001; n = 6000 detects a
  // CDF deviation ≥ 0.033 with power ≥ 0.9).
  for (const char* split : {"train", "val"}) {
    const std::string csv = lieservo::test::dataDir() + "/" + split + "/targets.csv";
    if (!haveFile(csv)) {
      WARN("SKIPPED: real data not found at " << csv);
      continue;
    }
    const auto rows = col::readTargetsCsv(csv);
    std::vector<double> u_disk, u_cap, u_theta;
    const double c = 1 - std::cos(lieservo::deg2rad(25.0));
    for (const auto& r : rows) {
      const auto p = SurfaceContactPose<double>::fromEuler6Degrees(r.euler6Degrees());
      u_disk.push_back((p.x * p.x + p.y * p.y) / 25.0);
      const auto pol = capPolar(p.alpha, p.beta);
      u_cap.push_back((1 - std::cos(pol(0))) / c);
      u_theta.push_back((pol(1) + lieservo::pi<double>()) / (2 * lieservo::pi<double>()));
    }
    INFO(split << ": n = " << rows.size());
    CHECK(lieservo::test::ksPValue(lieservo::test::ksStatisticUniform(u_disk), rows.size()) > 0.001);
    CHECK(lieservo::test::ksPValue(lieservo::test::ksStatisticUniform(u_cap), rows.size()) > 0.001);
    CHECK(lieservo::test::ksPValue(lieservo::test::ksStatisticUniform(u_theta), rows.size()) > 0.001);
  }
}

TEST_CASE("C++ labels match examples/gdn/labels_reference.csv (numpy) to 1e-9", "[sampling][labels]") {
  const std::string ref = std::string(LIESERVO_SOURCE_DIR) + "/examples/gdn/labels_reference.csv";
  if (!haveFile(ref)) {
    WARN("SKIPPED: " << ref << " not found (written by examples/gdn/labels.py)");
    return;
  }
  std::ifstream f(ref);
  std::string line;
  std::getline(f, line);
  REQUIRE(line == "sensor_image,x_mm,y_mm,z_mm,alpha_deg,beta_deg,gamma_deg,rho1_mm,rho2_mm,rho3_mm,phi1_rad,phi2_rad,phi3_rad");
  // the val rows they came from, when the data is present
  std::vector<col::TargetRow> val;
  const std::string val_csv = lieservo::test::dataDir() + "/val/targets.csv";
  if (haveFile(val_csv)) {
    col::TargetsReadOptions o;
    o.max_rows = 20;
    val = col::readTargetsCsv(val_csv, o);
  }
  int n = 0;
  while (std::getline(f, line)) {
    if (line.empty()) continue;
    std::stringstream ss(line);
    std::string name, cell;
    std::getline(ss, name, ',');
    std::vector<double> v;
    while (std::getline(ss, cell, ',')) v.push_back(std::stod(cell));
    REQUIRE(v.size() == 12);
    Eigen::Matrix<double, 6, 1> e6, xi_ref;
    for (int i = 0; i < 6; ++i) {
      e6(i) = v[static_cast<std::size_t>(i)];
      xi_ref(i) = v[static_cast<std::size_t>(6 + i)];
    }
    const auto xi = surfaceContactLabel(SurfaceContactPose<double>::fromEuler6Degrees(e6));
    INFO(ref << " row " << n + 2 << " (" << name << "): C++ " << xi.transpose() << " vs numpy " << xi_ref.transpose());
    CHECK((xi - xi_ref).cwiseAbs().maxCoeff() < 1e-9);
    if (static_cast<std::size_t>(n) < val.size()) {
      CHECK(val[static_cast<std::size_t>(n)].sensor_image == name);
      CHECK((val[static_cast<std::size_t>(n)].euler6Degrees() - e6).cwiseAbs().maxCoeff() < 1e-12);
    }
    ++n;
  }
  CHECK(n == 20);
}
