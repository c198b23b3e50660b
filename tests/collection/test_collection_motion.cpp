// The collection motion (Algorithm 1, alg:data_collection) on the kinematic stand-in arm, the synthetic
// image source and the PNG encoder — in process.
#include <catch2/catch.hpp>

#include "collector.hpp"
#include "image_io.hpp"
#include "image_source.hpp"
#include "kinematic_arm.hpp"

#include <lieservo/sampling.hpp>

#include <random>
#include <set>
#include <sstream>

using namespace lieservo::collection;
using lieservo::Status;

TEST_CASE("motion: start above, rotate, press along the normal, shear, lift off", "[collection][motion]") {
  Eigen::Matrix<double, 6, 1> wf;
  wf << 562, -9, 96, -179.5, 0.5, 180;  // the shared data's work frame
  const SE3d X_wf = SE3d::fromEulerXYZ6Degrees(wf);
  KinematicArm arm(SE3d(), true);
  lieservo::sampling::Rng rng(3);
  for (int k = 0; k < 50; ++k) {
    const auto p = lieservo::sampling::sampleSurfaceContactPose<double>(rng);
    arm.clearMoves();
    REQUIRE(moveToContactPose(arm, X_wf, p, 10.0) == Status::ok);
    REQUIRE(liftOff(arm, X_wf, p, 10.0) == Status::ok);
    const auto& m = arm.moves();
    REQUIRE(m.size() == 5);
    auto inF = [&](const SE3d& X_ws) { return (X_wf.inverse() * X_ws).toEulerXYZ6(); };
    Eigen::Matrix<double, 6, 1> e;
    e << 0, 0, -10, 0, 0, 0;
    CHECK((inF(m[0]) - e).cwiseAbs().maxCoeff() < 1e-9);  // 1. above the start point
    e << 0, 0, -10, p.alpha, p.beta, 0;
    CHECK((inF(m[1]) - e).cwiseAbs().maxCoeff() < 1e-9);  // 2. contact angle
    e << 0, 0, p.z, p.alpha, p.beta, 0;
    CHECK((inF(m[2]) - e).cwiseAbs().maxCoeff() < 1e-9);  // 3. depth z along the normal
    // steps 2→3 move along the surface normal only (same orientation, same x, y)
    const SE3d step3 = X_wf.inverse() * m[2], step2 = X_wf.inverse() * m[1];
    CHECK((step3.translation() - step2.translation()).head<2>().norm() < 1e-9);
    CHECK(step3.so3().isApprox(step2.so3(), 1e-12));
    CHECK((inF(m[3]) - p.euler6()).cwiseAbs().maxCoeff() < 1e-9);  // 4. shear: X_fs
    CHECK(m[3].isApprox(X_wf * lieservo::sampling::surfaceContactTransform(p), 1e-9));
    e << p.x, p.y, -10, p.alpha, p.beta, p.gamma;
    CHECK((inF(m[4]) - e).cwiseAbs().maxCoeff() < 1e-9);  // 6. lift off
  }
}

TEST_CASE("synthetic image source: pose dependent, binarised, valid PNG", "[collection][motion]") {
  KinematicArm arm;
  SyntheticTactileSource cam(arm, SE3d(), 96, 80);
  lieservo::sampling::Rng rng(9);
  std::set<std::vector<std::uint8_t>> seen;
  for (int k = 0; k < 30; ++k) {
    const auto p = lieservo::sampling::sampleSurfaceContactPose<double>(rng);
    REQUIRE(moveToContactPose(arm, SE3d(), p, 10.0) == Status::ok);
    GrayImage img;
    REQUIRE(cam.capture(img) == Status::ok);
    REQUIRE(img.valid());
    CHECK(img.width == 96);
    CHECK(img.height == 80);
    long white = 0;
    for (auto v : img.pixels) {
      REQUIRE((v == 0 || v == 255));
      white += v == 255;
    }
    CHECK(white > 100);
    seen.insert(img.pixels);
    const auto png = encodePngGray8(img);
    REQUIRE(png.size() > 57);
    CHECK(png[1] == 'P');
    // IHDR dimensions
    CHECK(((png[16] << 24) | (png[17] << 16) | (png[18] << 8) | png[19]) == 96);
    CHECK(((png[20] << 24) | (png[21] << 16) | (png[22] << 8) | png[23]) == 80);
  }
  CHECK(seen.size() == 30);
  CHECK_THAT(cam.paramsJson(), Catch::Matchers::Contains("\"type\":\"synthetic\""));
}

TEST_CASE("png encoder: libpng's reader gives the image back", "[collection][motion]") {
  GrayImage img(3, 2);
  img.at(0, 0) = 255;
  img.at(1, 2) = 7;
  const auto png = encodePngGray8(img);
  const GrayImage back = decodePngGray8(png);
  CHECK(back.width == 3);
  CHECK(back.height == 2);
  CHECK(back.pixels == img.pixels);
  CHECK(encodePngGray8(img) == png);  // deterministic
  CHECK_THROWS_AS(encodePngGray8(GrayImage()), DatasetError);
  CHECK_THROWS_AS(decodePngGray8(std::vector<std::uint8_t>(png.begin(), png.begin() + 20)), DatasetError);
}

TEST_CASE("runCollection in process: stop flag, progress, rows", "[collection][motion]") {
  const std::string dir = std::string(LIESERVO_TEST_WORK_DIR) + "/in_process";
  std::filesystem::remove_all(dir);
  CollectionConfig c;
  c.out_dir = dir;
  c.n_samples = 6;
  c.seed = 3;
  std::ostringstream log;
  c.log = &log;
  KinematicArm arm;
  SyntheticTactileSource cam(arm, SE3d(), 32, 32);
  volatile std::sig_atomic_t stop = 0;
  c.stop_requested = &stop;
  c.stop_after = 2;
  CollectionResult r = runCollection(c, arm, cam);
  CHECK(r.written == 2);
  CHECK_FALSE(r.complete);
  stop = 1;  // e.g. Ctrl-C before the next sample: nothing more is written
  c.stop_after = static_cast<std::size_t>(-1);
  r = runCollection(c, arm, cam);
  CHECK(r.rows_before == 2);
  CHECK(r.written == 0);
  stop = 0;
  r = runCollection(c, arm, cam);
  CHECK(r.written == 4);
  CHECK(r.complete);
  CHECK(readTargetsCsv(dir + "/targets.csv").size() == 6);
  CHECK_THAT(log.str(), Catch::Matchers::Contains("6/6 (100.0%)"));
}
