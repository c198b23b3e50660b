// The chi-square distribution of estimation/chi_square.hpp (the gates' and the consistency
// tests' thresholds) against standard tables and, over a grid, against Boost.Math's
// chi_squared_distribution: an implementation independent of the library's.
#include <catch2/catch.hpp>

#include <boost/math/distributions/chi_squared.hpp>

#include <cmath>

#include <lieservo/estimation/chi_square.hpp>

using namespace lieservo;

TEST_CASE("chi-square CDF and quantiles", "[estimation][chi2]") {
  // Reference values (standard χ² tables, 10+ digits).
  CHECK(chiSquareQuantile(0.95, 1) == Approx(3.841458820694124).epsilon(1e-10));
  CHECK(chiSquareQuantile(0.95, 6) == Approx(12.591587243743977).epsilon(1e-10));
  CHECK(chiSquareQuantile(0.999, 6) == Approx(22.457744484825323).epsilon(1e-10));
  CHECK(chiSquareQuantile(0.975, 3) == Approx(9.348403604496148).epsilon(1e-10));
  CHECK(chiSquareQuantile(0.025, 3) == Approx(0.215795282623898).epsilon(1e-9));
  CHECK(chiSquareQuantile(0.5, 2) == Approx(2.0 * std::log(2.0)).epsilon(1e-12));
  for (double dof : {1.0, 3.0, 6.0, 60.0, 6000.0, 60000.0})
    for (double p : {1e-6, 0.025, 0.5, 0.975, 0.999, 1 - 1e-9}) {
      const double x = chiSquareQuantile(p, dof);
      CHECK(chiSquareCdf(x, dof) == Approx(p).epsilon(1e-9));
    }
  // Wilson–Hilferty is good for many degrees of freedom.
  CHECK(chiSquareQuantileWilsonHilferty(0.975, 6000) ==
        Approx(chiSquareQuantile(0.975, 6000)).epsilon(1e-5));
  CHECK(std::isnan(chiSquareQuantile(1.0, 6)));
  CHECK(std::isnan(chiSquareQuantile(0.5, 0)));
}

TEST_CASE("chi-square CDF and quantiles agree with Boost.Math", "[estimation][chi2]") {
  // The quantile solves for the upper tail above the median, so it keeps its digits up to
  // p = 1 − 1e-9 (solving P(x) = p there lost 1e-9 relative); the CDF to 1e-9 here, its
  // measured accuracy is in chi_square.hpp.
  for (const double dof : {1.0, 2.0, 3.0, 6.0, 12.0, 60.0, 600.0, 6000.0, 60000.0}) {
    const boost::math::chi_squared_distribution<double> chi2(dof);
    for (const double p : {1e-9, 1e-6, 1e-3, 0.025, 0.1, 0.5, 0.9, 0.975, 0.999, 1 - 1e-6, 1 - 1e-9}) {
      INFO("dof " << dof << ", p " << p);
      CHECK(chiSquareQuantile(p, dof) == Approx(boost::math::quantile(chi2, p)).epsilon(1e-12));
    }
    for (const double x_over_dof : {0.01, 0.1, 0.5, 0.9, 1.0, 1.1, 2.0, 5.0}) {
      const double x = x_over_dof * dof;
      INFO("dof " << dof << ", x " << x);
      CHECK(chiSquareCdf(x, dof) == Approx(boost::math::cdf(chi2, x)).epsilon(1e-9).margin(1e-300));
    }
  }
}
