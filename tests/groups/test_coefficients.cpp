// Every closed-form/series coefficient of the groups against a long-double reference:
// relative error ≤ 1e-13 (double) and ≤ 1e-5 (float) on a dense grid θ ∈ [0, 3] that is
// log-spaced through [1e-12, 1e-2] and straddles every series cutoff.
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <lieservo/lieservo.hpp>

namespace {

using ld = long double;
namespace d = lieservo::detail;

ld factorial(int n) {
  ld f = 1;
  for (int i = 2; i <= n; ++i) f *= i;
  return f;
}

// Series Σ_{k=0}^{K} c(k) x^k in long double (many terms; used for θ < 1.5).
ld seriesLd(ld x, const std::function<ld(int)>& c, int K = 40) {
  ld sum = 0, p = 1;
  for (int k = 0; k <= K; ++k) {
    sum += c(k) * p;
    p *= x;
  }
  return sum;
}
ld sgn(int k) { return k % 2 ? -1.0L : 1.0L; }

struct Coefficient {
  std::string name;
  std::function<ld(ld)> reference;  // of x = θ²
  std::function<double(double)> eval_double;
  std::function<double(float)> eval_float;
};

template <class F>
Coefficient make(const std::string& name, std::function<ld(int)> series, std::function<ld(ld)> closed, F fn) {
  Coefficient c;
  c.name = name;
  c.reference = [series, closed](ld x) { return x < 2.25L ? seriesLd(x, series) : closed(std::sqrt(x)); };
  c.eval_double = [fn](double x) { return fn(d::AngleTerms<double>(x)); };
  c.eval_float = [fn](float x) { return static_cast<double>(fn(d::AngleTerms<float>(x))); };
  return c;
}

struct AnyCoeff {
  int which;
  template <class S>
  S operator()(const d::AngleTerms<S>& t) const {
    switch (which) {
      case 0: return d::coeffA(t);
      case 1: return d::coeffB(t);
      case 2: return d::coeffC(t);
      case 3: return d::coeffD(t);
      case 4: return d::coeffE(t);
      case 5: return d::coeffF(t);
      default: return d::coeffH(t);
    }
  }
};

std::vector<Coefficient> coefficients() {
  std::vector<Coefficient> v;
  v.push_back(make("A = sin(t)/t", [](int k) { return sgn(k) / factorial(2 * k + 1); },
                   [](ld t) { return std::sin(t) / t; }, AnyCoeff{0}));
  v.push_back(make("B = (1-cos t)/t^2", [](int k) { return sgn(k) / factorial(2 * k + 2); },
                   [](ld t) { return (1 - std::cos(t)) / (t * t); }, AnyCoeff{1}));
  v.push_back(make("C = (t-sin t)/t^3", [](int k) { return sgn(k) / factorial(2 * k + 3); },
                   [](ld t) { return (t - std::sin(t)) / (t * t * t); }, AnyCoeff{2}));
  v.push_back(make("D = (1 - t sin t/(2(1-cos t)))/t^2",
                   [](int k) { return sgn(k) * d::bernoulliOverFactorial(2 * k + 2); },
                   [](ld t) { return (1 - t * std::sin(t) / (2 * (1 - std::cos(t)))) / (t * t); }, AnyCoeff{3}));
  v.push_back(make("E = (t^2 + 2cos t - 2)/(2t^4)", [](int k) { return sgn(k) / factorial(2 * k + 4); },
                   [](ld t) { return (t * t + 2 * std::cos(t) - 2) / (2 * t * t * t * t); }, AnyCoeff{4}));
  v.push_back(make("F = (2t - 3sin t + t cos t)/(2t^5)",
                   [](int k) { return sgn(k) * (2 * (k + 2) - 2) / (2 * factorial(2 * (k + 2) + 1)); },
                   [](ld t) { return (2 * t - 3 * std::sin(t) + t * std::cos(t)) / (2 * t * t * t * t * t); },
                   AnyCoeff{5}));
  v.push_back(make("H = (t/2)cot(t/2)", [](int k) { return sgn(k) * d::bernoulliOverFactorial(2 * k); },
                   [](ld t) { return t * std::sin(t) / (2 * (1 - std::cos(t))); }, AnyCoeff{6}));
  return v;
}

std::vector<double> grid() {
  std::vector<double> g = {0.0};
  for (int i = 0; i <= 3000; ++i) g.push_back(1e-12 * std::pow(3e12, i / 3000.0));  // log-spaced [1e-12, 3]
  for (int i = 1; i <= 600; ++i) g.push_back(3.0 * i / 600);
  // both sides of every cutoff, for both scalar types
  const auto& cd = d::Cutoffs<double>::get();
  const auto& cf = d::Cutoffs<float>::get();
  for (double x : {cd.A, cd.B, cd.C, cd.D, cd.E, cd.F, cd.H, double(cf.A), double(cf.B), double(cf.C), double(cf.D),
                   double(cf.E), double(cf.F), double(cf.H)}) {
    for (double f : {0.999, 0.99999, 1.0, 1.00001, 1.001}) {
      const double t = std::sqrt(x) * f;
      if (t <= 3.0) g.push_back(t);
    }
  }
  return g;
}

}  // namespace

TEST_CASE("Bernoulli numbers B_n/n! from the recurrence", "[core][coefficients]") {
  CHECK(d::bernoulliOverFactorial(0) == 1.0L);
  CHECK(d::bernoulliOverFactorial(1) == -0.5L);
  CHECK(d::bernoulliOverFactorial(3) == 0.0L);
  const ld expect[] = {1.0L / 12, -1.0L / 720, 1.0L / 30240, -1.0L / 1209600, 1.0L / 47900160,
                       -691.0L / 1307674368000};
  for (int k = 1; k <= 6; ++k) {
    const ld got = d::bernoulliOverFactorial(2 * k);
    CHECK(std::abs(static_cast<double>((got - expect[k - 1]) / expect[k - 1])) <= 1e-17);
  }
}

TEST_CASE("Series tables match their defining formulas", "[core][coefficients]") {
  // Guards against a typo in the hand-written long-double tables.
  auto cmp = [](const auto& table, const std::function<ld(int)>& c) {
    const std::size_t K = sizeof(table.a) / sizeof(table.a[0]);
    for (std::size_t k = 0; k < K; ++k) {
      const ld want = c(static_cast<int>(k));
      INFO("term " << k);
      CHECK(std::abs(static_cast<double>((table.a[k] - want) / want)) <= 1e-17);
    }
  };
  cmp(d::kSeriesA, [](int k) { return sgn(k) / factorial(2 * k + 1); });
  cmp(d::kSeriesB, [](int k) { return sgn(k) / factorial(2 * k + 2); });
  cmp(d::kSeriesC, [](int k) { return sgn(k) / factorial(2 * k + 3); });
  cmp(d::kSeriesD, [](int k) { return sgn(k) * d::bernoulliOverFactorial(2 * k + 2); });
  cmp(d::kSeriesE, [](int k) { return sgn(k) / factorial(2 * k + 4); });
  cmp(d::kSeriesF, [](int k) { return sgn(k) * (2 * (k + 2) - 2) / (2 * factorial(2 * (k + 2) + 1)); });
  cmp(d::kSeriesAtan, [](int k) { return sgn(k) / (2 * k + 1); });
}

TEST_CASE("Every coefficient is accurate against a long-double reference for 0 <= theta <= 3", "[core][coefficients]") {
  const std::vector<double> g = grid();
  const auto& cd = d::Cutoffs<double>::get();
  const auto& cf = d::Cutoffs<float>::get();
  const double cut_d[] = {cd.A, cd.B, cd.C, cd.D, cd.E, cd.F, cd.H};
  const double cut_f[] = {cf.A, cf.B, cf.C, cf.D, cf.E, cf.F, cf.H};
  std::printf("coefficient                             theta_cut(double) theta_cut(float)  max rel err(double) "
              "max rel err(float)\n");
  int idx = 0;
  for (const Coefficient& c : coefficients()) {
    double worst_d = 0, worst_f = 0, at_d = 0, at_f = 0;
    for (double t : g) {
      const double xd = t * t;
      const ld ref_d = c.reference(static_cast<ld>(xd));
      const double ed = static_cast<double>(std::abs((c.eval_double(xd) - ref_d) / ref_d));
      if (ed > worst_d) worst_d = ed, at_d = t;
      const float tf = static_cast<float>(t);
      const float xf = tf * tf;
      const ld ref_f = c.reference(static_cast<ld>(xf));
      const double ef = static_cast<double>(std::abs((c.eval_float(xf) - ref_f) / ref_f));
      if (ef > worst_f) worst_f = ef, at_f = t;
    }
    std::printf("%-40s %14.4g %16.4g %12.2e @%-8.3g %10.2e @%-8.3g\n", c.name.c_str(), std::sqrt(cut_d[idx]),
                std::sqrt(cut_f[idx]), worst_d, at_d, worst_f, at_f);
    INFO(c.name << ": worst double " << worst_d << " at theta " << at_d << ", float " << worst_f << " at " << at_f);
    CHECK(worst_d <= 1e-13);
    CHECK(worst_f <= 1e-5);
    ++idx;
  }
}

TEST_CASE("Cutoffs follow (eps |a0/aK|)^(1/K) and trig is needed below all of them", "[core][coefficients]") {
  const auto& c = d::Cutoffs<double>::get();
  const long double eps = std::numeric_limits<double>::epsilon();
  CHECK(c.C == Approx(static_cast<double>(std::pow(eps * (1.0L / 6) * 1307674368000.0L, 1.0L / 6))));
  for (double x : {c.A, c.B, c.C, c.D, c.E, c.F, c.H}) CHECK(c.trig <= x);
  // float cutoffs are larger (coarser epsilon)
  const auto& f = d::Cutoffs<float>::get();
  CHECK(f.C > c.C);
  CHECK(f.F > c.F);
}

TEST_CASE("Quaternion log factor 2 atan2(n, w)/n across the series cutoff", "[core][coefficients]") {
  // q = (cos(θ/2), sin(θ/2) e_x) → φ = θ e_x, checked in long double.
  for (int i = 0; i <= 400; ++i) {
    const double th = 1e-12 * std::pow(3e12, i / 400.0);
    const Eigen::Vector4d q(std::cos(th / 2), std::sin(th / 2), 0, 0);
    const double got = d::rotationVectorFromQuaternion(q)(0);
    const ld ref = 2 * std::atan2(static_cast<ld>(q(1)), static_cast<ld>(q(0)));
    INFO("theta " << th);
    CHECK(std::abs(static_cast<double>((got - ref) / ref)) <= 4e-16);
  }
}

TEST_CASE("Half-angle series of exp: terms, the three-term range and the packet evaluation", "[core][coefficients]") {
  // sin(θ/2)/θ and cos(θ/2) in x = θ²; three terms reach eps exactly at halfAngleShortMaxX
  // (the first omitted term equals eps·|a0| there).
  for (int n = 0; n < 12; ++n) {
    INFO("term " << n);
    const ld sinc = sgn(n) / (2 * std::pow(4.0L, n) * factorial(2 * n + 1));
    const ld cosn = sgn(n) / (std::pow(4.0L, n) * factorial(2 * n));
    CHECK(std::abs(static_cast<double>((d::halfSincTerm(n) - sinc) / sinc)) <= 1e-17);
    CHECK(std::abs(static_cast<double>((d::halfCosTerm(n) - cosn) / cosn)) <= 1e-17);
  }
  auto omitted = [&](int K, ld x) {  // relative to the first terms, 1/2 and 1
    return std::max(std::abs(d::halfSincTerm(K) / d::halfSincTerm(0)), std::abs(d::halfCosTerm(K))) *
           std::pow(x, static_cast<ld>(K));
  };
  const ld short_d = d::halfAngleShortMaxX<double>(), short_f = d::halfAngleShortMaxX<float>();
  INFO("short series up to x = " << static_cast<double>(short_d) << " (double), " << static_cast<double>(short_f)
                                  << " (float)");
  CHECK(static_cast<double>(std::abs(omitted(3, short_d) / std::numeric_limits<double>::epsilon() - 1)) <= 1e-12);
  CHECK(static_cast<double>(std::abs(omitted(3, short_f) / std::numeric_limits<float>::epsilon() - 1)) <= 1e-12);
  // The packet evaluation against the long-double functions over [0, halfAngleShortMaxX]:
  // within 2 ulp of the value (both are of order 1/2 to 1 there, no cancellation).
  double worst_d = 0, worst_f = 0;
  for (int i = 0; i <= 100000; ++i) {
    const double xs = static_cast<double>(short_d) * i / 100000;
    const ld hs = std::sqrt(static_cast<ld>(xs)) / 2;
    const auto es = d::lanesEval(d::kHalfAngleShortSeries<double>.a, xs);
    const ld ss_ref = xs == 0 ? 0.5L : std::sin(hs) / (2 * hs);
    worst_d = std::max({worst_d, static_cast<double>(std::abs(es(0) - ss_ref) / ss_ref),
                        static_cast<double>(std::abs(es(1) - std::cos(hs)) / std::cos(hs))});
    const float xsf = static_cast<float>(static_cast<double>(short_f) * i / 100000);
    const ld hsf = std::sqrt(static_cast<ld>(xsf)) / 2;
    const auto esf = d::lanesEval(d::kHalfAngleShortSeries<float>.a, xsf);
    const ld ssf_ref = xsf == 0 ? 0.5L : std::sin(hsf) / (2 * hsf);
    worst_f = std::max({worst_f, static_cast<double>(std::abs(esf(0) - ssf_ref) / ssf_ref),
                        static_cast<double>(std::abs(esf(1) - std::cos(hsf)) / std::cos(hsf))});
  }
  INFO("worst error: double " << worst_d << ", float " << worst_f);
  CHECK(worst_d <= 2 * std::numeric_limits<double>::epsilon());
  CHECK(worst_f <= 2 * std::numeric_limits<float>::epsilon());
}

TEST_CASE("Piecewise series of exp: term counts and the packet evaluation", "[core][coefficients]") {
  // Rodrigues' A = sinθ/θ and B = (1 − cosθ)/θ² over x = θ² ∈ [0, π²], as SO3::exp takes them:
  // series about the centre of one of kExpPieces equal pieces, or about π² within
  // expHalfTurnMaxD of it. Term count: the first K whose omitted term (A absolute, B relative
  // to B(c)) stays below eps/8 at half a piece's width on every piece, and K − 1 would not do.
  // Values against long double sin/cos over 1e5 points, the slot picked as exp picks it: A
  // within an absolute 2 eps (it falls from 1 to 0: the matrix's entries need its absolute
  // accuracy), B within a relative 2 eps.
  const int P = d::kExpPieces;
  auto omitted = [&](int K) {
    ld worst = 0;
    for (int i = 0; i < P; ++i)
      worst = std::max(worst, d::expPieceOmitted(d::rodriguesTermsAbout(d::expPieceCentre<double>(i)), K));
    return worst;
  };
  auto omitted_f = [&](int K) {
    ld worst = 0;
    for (int i = 0; i < P; ++i)
      worst = std::max(worst, d::expPieceOmitted(d::rodriguesTermsAbout(d::expPieceCentre<float>(i)), K));
    return worst;
  };
  const int Kd = d::ExpPieces<double>::K, Kf = d::ExpPieces<float>::K;
  INFO("K double " << Kd << ", float " << Kf);
  CHECK(omitted(Kd) < std::numeric_limits<double>::epsilon() / 8);
  CHECK(omitted(Kd - 1) >= std::numeric_limits<double>::epsilon() / 8);
  CHECK(omitted_f(Kf) < std::numeric_limits<float>::epsilon() / 8);
  CHECK(omitted_f(Kf - 1) >= std::numeric_limits<float>::epsilon() / 8);
  CHECK(static_cast<double>(std::abs(d::kHalfTurnTerms.A[0])) <= 1e-19);  // sin π = 0
  CHECK(static_cast<double>(std::abs(d::kHalfTurnTerms.B[0] * lieservo::pi<ld>() * lieservo::pi<ld>() / 2 - 1)) <=
        1e-18);  // B(π²) = 2/π²
  const auto ref = [](ld x, ld& A, ld& B) {
    const ld th = std::sqrt(x);
    A = std::sin(th) / th;
    B = (1 - std::cos(th)) / x;
  };
  // The slot and its argument, as SO3::exp computes them.
  const auto eval = [](auto x) {
    using S = decltype(x);
    const auto& p = d::kExpPieceSeries<S>;
    constexpr int h = d::ExpPieces<S>::kHalfTurn;
    int i = std::min(int(x * p.inv_width), d::kExpPieces - 1);
    if ((x - p.hi[h]) - p.lo[h] > -p.half_turn_max_d) i = h;
    return d::lanesEval(p.a[i], (x - p.hi[i]) - p.lo[i]);
  };
  double worst_d = 0, worst_f = 0;
  int half_turn_d = 0, half_turn_f = 0;
  for (int i = 0; i <= 100000; ++i) {
    const double x = static_cast<double>(d::kHalfAngleSeriesMaxX * i / 100000);
    if (x == 0) continue;
    const auto e = eval(x);
    ld A, B;
    ref(x, A, B);
    worst_d = std::max({worst_d, static_cast<double>(std::abs(e(0) - A)), static_cast<double>(std::abs(e(1) - B) / B)});
    half_turn_d += (x - d::kPiSquared<double>.hi) - d::kPiSquared<double>.lo > -d::kExpPieceSeries<double>.half_turn_max_d;
    const float xf = static_cast<float>(x);
    const auto ef = eval(xf);
    ref(xf, A, B);
    worst_f = std::max({worst_f, static_cast<double>(std::abs(ef(0) - A)), static_cast<double>(std::abs(ef(1) - B) / B)});
    half_turn_f += (xf - d::kPiSquared<float>.hi) - d::kPiSquared<float>.lo > -d::kExpPieceSeries<float>.half_turn_max_d;
  }
  INFO("worst error: double " << worst_d / std::numeric_limits<double>::epsilon() << " eps, float "
                              << worst_f / std::numeric_limits<float>::epsilon() << " eps; about pi^2: " << half_turn_d
                              << " and " << half_turn_f << " points");
  CHECK(half_turn_d > 5000);  // both kinds of slot are exercised
  CHECK(half_turn_f > 5000);
  CHECK(worst_d <= 2 * std::numeric_limits<double>::epsilon());
  CHECK(worst_f <= 2 * std::numeric_limits<float>::epsilon());
}
