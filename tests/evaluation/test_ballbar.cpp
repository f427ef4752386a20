// ISO 230-4 circular deviations against hand-made traces, and predicted traces from machine
// models against the first-order effect of single errors.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "mtcal/evaluation/ballbar.hpp"
#include "mtcal/util/errors.hpp"
#include "synthetic.hpp"
#include "examples.hpp"

using namespace mtcal;

namespace {

using mtcal::testing::kPi;

constexpr double R = 150.0;

BallbarOptions nominal(double radius) {
  BallbarOptions o;
  o.nominal_radius = radius;
  return o;
}

// A trace whose bar length at angle a is f(a, direction), one sample per degree, both directions.
template <class F>
std::vector<TracePoint> trace(F&& f, int samples = 360) {
  std::vector<TracePoint> t;
  for (CircleDirection d : {CircleDirection::CW, CircleDirection::CCW})
    for (int k = 0; k < samples; ++k) {
      const double a = 2 * kPi * k / samples;
      t.push_back({d, d == CircleDirection::CCW ? a : 2 * kPi - a, f(d == CircleDirection::CCW ? a : 2 * kPi - a, d)});
    }
  return t;
}

}  // namespace

TEST(Ballbar, PerfectCircleHasNoDeviation) {
  const auto e = evaluate_ballbar(trace([](double, CircleDirection) { return R; }), nominal(R));
  EXPECT_NEAR(e.cw->G, 0.0, 1e-12);
  EXPECT_NEAR(e.ccw->G_minimum_zone, 0.0, 1e-12);
  EXPECT_NEAR(*e.G_b, 0.0, 1e-12);
  EXPECT_NEAR(*e.H, 0.0, 1e-12);
  EXPECT_NEAR(e.F_max, 0.0, 1e-12);
  EXPECT_NEAR(e.F_min, 0.0, 1e-12);
}

TEST(Ballbar, OffsetCircleHasNoCircularDeviationButRadialDeviation) {
  // The path is a true circle about (a, 0): G = 0 about the least-squares centre, while the
  // radial deviation from the instrument's centre swings from +a to -a.
  const double a = 0.01;
  std::vector<TracePoint> t;
  for (CircleDirection d : {CircleDirection::CW, CircleDirection::CCW})
    for (int k = 0; k < 360; ++k) {
      const double phi = 2 * kPi * k / 360;
      const double x = a + R * std::cos(phi), y = R * std::sin(phi);
      t.push_back({d, std::atan2(y, x), std::hypot(x, y)});
    }
  const auto e = evaluate_ballbar(t, nominal(R));
  EXPECT_NEAR(e.ccw->G, 0.0, 1e-9);
  EXPECT_NEAR(e.ccw->centre_x, a, 1e-9);
  EXPECT_NEAR(e.ccw->centre_y, 0.0, 1e-9);
  EXPECT_NEAR(e.F_max, a, 1e-9);
  EXPECT_NEAR(e.F_min, -a, 1e-9);
}

TEST(Ballbar, OvalAndReversalHandCalculation) {
  // Squareness-like oval e sin 2a (centred, so G = 2e about any near-centre) and a constant
  // difference h between the directions (H = G(b) = h).
  const double e = 0.004, h = 0.003;
  const auto oval =
      evaluate_ballbar(trace([&](double a, CircleDirection) { return R + e * std::sin(2 * a); }), nominal(R));
  EXPECT_NEAR(oval.ccw->G, 2 * e, 1e-9);
  EXPECT_NEAR(oval.ccw->G_minimum_zone, 2 * e, 1e-9);
  const auto rev = evaluate_ballbar(trace([&](double, CircleDirection d) {
                                      return R + (d == CircleDirection::CW ? h / 2 : -h / 2);
                                    }),
                                    nominal(R));
  EXPECT_NEAR(*rev.H, h, 1e-12);
  EXPECT_NEAR(*rev.G_b, h, 1e-9);
  EXPECT_NEAR(rev.cw->G, 0.0, 1e-12);
  EXPECT_NEAR(*rev.F_mean_bidirectional, 0.0, 1e-12);
}

TEST(Ballbar, MinimumZoneIsTheSmallestZone) {
  // A lopsided trace: a bump on one side only; the minimum-zone centre must beat the
  // least-squares one and match a brute-force search of centres.
  const auto t = trace([](double a, CircleDirection) { return R + 0.005 * std::exp(-std::pow((a - 1.0) / 0.3, 2)); });
  const auto e = evaluate_ballbar(t, nominal(R));
  EXPECT_LT(e.ccw->G_minimum_zone, e.ccw->G);
  double best = INFINITY;
  for (int i = -60; i <= 60; ++i)
    for (int j = -60; j <= 60; ++j) {
      const double cx = e.ccw->centre_x + i * 5e-5, cy = e.ccw->centre_y + j * 5e-5;
      double lo = INFINITY, hi = -INFINITY;
      for (const auto& s : t) {
        if (s.direction != CircleDirection::CCW) continue;
        const double d = std::hypot(s.radius * std::cos(s.angle) - cx, s.radius * std::sin(s.angle) - cy);
        lo = std::min(lo, d), hi = std::max(hi, d);
      }
      best = std::min(best, hi - lo);
    }
  EXPECT_LE(e.ccw->G_minimum_zone, best + 1e-9);
}

TEST(Ballbar, OvershootIsIgnoredAndBadTracesAreRefused) {
  auto t = trace([](double, CircleDirection) { return R; });
  // 20 deg of wild samples at the start of the ccw run: dropped by a 20 deg start overshoot.
  std::vector<TracePoint> with;
  for (int k = 0; k < 20; ++k) with.push_back({CircleDirection::CCW, k * kPi / 180, R + 1.0});
  for (const auto& s : t) with.push_back(s);
  BallbarOptions o = nominal(R);
  o.overshoot_start = 20;
  EXPECT_NEAR(evaluate_ballbar(with, o).ccw->G, 0.0, 1e-12);
  EXPECT_GT(evaluate_ballbar(with, nominal(R)).ccw->G, 0.5);
  // Too few samples, a half circle, one direction only.
  EXPECT_THROW(evaluate_ballbar(trace([](double, CircleDirection) { return R; }, 6), nominal(R)), InputError);
  std::vector<TracePoint> half;
  for (const auto& s : t)
    if (s.angle < kPi) half.push_back(s);
  EXPECT_THROW(evaluate_ballbar(half, nominal(R)), InputError);
  std::vector<TracePoint> ccw_only;
  for (const auto& s : t)
    if (s.direction == CircleDirection::CCW) ccw_only.push_back(s);
  EXPECT_THROW(evaluate_ballbar(ccw_only, nominal(R)), InputError);
  BallbarOptions one = nominal(R);
  one.only = CircleDirection::CCW;
  const auto e = evaluate_ballbar(ccw_only, one);
  EXPECT_TRUE(e.ccw && !e.cw && !e.H);
}

TEST(Ballbar, PredictedTracesShowSingleErrorsAsTheyShould) {
  Machine m = mtcal::testing::nominal_machine("wXYfZt");
  const std::vector<double> centre{0.0, 0.0, -100.0};
  // Error-free: the bar keeps its length.
  for (const auto& s : predict_ballbar(m, "XY", centre, R, 1.0 * kPi / 180)) EXPECT_NEAR(s.radius, R, 1e-9);
  // Squareness EC0Y = g: x shifts by -g y, so r = R - (g R / 2) sin 2a: G = g R (first order).
  Machine sq = m;
  sq.set_parameter("EC0Y", 20e-6);
  const auto es = evaluate_ballbar(predict_ballbar(sq, "XY", centre, R, 1.0 * kPi / 180), nominal(R));
  EXPECT_NEAR(es.ccw->G, 20e-6 * R, 1e-6);
  EXPECT_NEAR(*es.H, 0.0, 1e-9);
  // Scale of X (EXX.1 = s): r = R + s R cos^2 a: G = s R, F from 0 to s R.
  Machine sc = m;
  sc.set_parameter("EXX.1", 10e-6);
  const auto ec = evaluate_ballbar(predict_ballbar(sc, "XY", centre, R, 1.0 * kPi / 180), nominal(R));
  EXPECT_NEAR(ec.ccw->G, 10e-6 * R, 1e-6);
  EXPECT_NEAR(ec.F_max, 10e-6 * R, 1e-6);
  // Reversal of X (EXX.b = b): the directions differ by up to 2b near the X reversals.
  Machine rv = m;
  rv.set_parameter("EXX.b", 2e-3);
  const auto er = evaluate_ballbar(predict_ballbar(rv, "XY", centre, R, 1.0 * kPi / 180), nominal(R));
  EXPECT_NEAR(*er.H, 4e-3, 1e-5);
  EXPECT_THROW(predict_ballbar(m, "XC", centre, R, 0.01), ModelError);
  EXPECT_THROW(predict_ballbar(mtcal::testing::nominal_machine("wCBfXYt"), "YZ", {0, 0, 0, 0}, R, 0.01), ModelError);
}

namespace {
double term(const TraceDiagnosis& d, const std::string& name) {
  for (const auto& t : d.terms)
    if (t.name == name) return t.value;
  ADD_FAILURE() << "no term " << name;
  return 0;
}
}  // namespace

TEST(Ballbar, DiagnosisRecoversTheErrorsBehindPredictedTraces) {
  // Traces predicted by the kinematic model (not by the diagnostic basis) for single errors:
  // each shows up in its own term, with the sign and size of first-order theory.
  const Machine m = mtcal::testing::nominal_machine("wXYfZt");
  const std::vector<double> centre{0.0, 0.0, -100.0};
  const double step = 0.5 * kPi / 180;
  auto diagnose = [&](const Machine& mm) {
    return diagnose_ballbar(predict_ballbar(mm, "XY", centre, R, step), nominal(R), "XY");
  };
  const auto clean = diagnose(m);
  for (const auto& t : clean.terms) EXPECT_NEAR(t.value, 0.0, 1e-6) << t.name;

  Machine sq = m;
  sq.set_parameter("EC0Y", 20e-6);  // Y leans towards -X: squareness +20 um/m
  const auto ds = diagnose(sq);
  EXPECT_NEAR(term(ds, "squareness XY"), 20.0, 0.05);
  EXPECT_NEAR(term(ds, "servo mismatch XY"), 0.0, 0.05);

  Machine bk = m;
  bk.set_parameter("EXX.b", 3e-3);  // X runs 3 um ahead in its direction: lost motion -6 um
  const auto db = diagnose(bk);
  EXPECT_NEAR(term(db, "backlash X"), -6.0, 0.1);
  EXPECT_NEAR(term(db, "backlash Y"), 0.0, 0.1);
  EXPECT_NEAR(term(db, "squareness XY"), 0.0, 0.05);

  Machine sc = m;
  sc.set_parameter("EXX.1", 10e-6);  // X scale +10 um/m: mismatch +10 um/m, mean radius +sR/2
  const auto dc = diagnose(sc);
  EXPECT_NEAR(term(dc, "scaling mismatch XY"), 10.0, 0.05);
  EXPECT_NEAR(term(dc, "radius offset"), 10e-6 * R / 2 * 1e3, 0.01);

  // Servo mismatch: a direction-dependent oval, built directly.
  const double mu = 15e-6;
  auto servo = trace([&](double a, CircleDirection d) {
    return R + (d == CircleDirection::CCW ? 1.0 : -1.0) * 0.5 * mu * R * std::sin(2 * a);
  });
  const auto dv = diagnose_ballbar(servo, nominal(R), "XY");
  EXPECT_NEAR(term(dv, "servo mismatch XY"), 15.0, 0.05);
  EXPECT_NEAR(term(dv, "squareness XY"), 0.0, 0.05);
}

TEST(Ballbar, DiagnosisUncertaintiesCoverTheTruthWithNoise) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> noise(0.0, 0.5e-3);
  Machine sq = mtcal::testing::nominal_machine("wXYfZt");
  sq.set_parameter("EC0Y", 20e-6);
  int inside = 0;
  for (int trial = 0; trial < 30; ++trial) {
    auto t = predict_ballbar(sq, "XY", {0.0, 0.0, -100.0}, R, 1.0 * kPi / 180);
    for (auto& s : t) s.radius += noise(rng);
    const auto d = diagnose_ballbar(t, nominal(R), "XY");
    for (const auto& tt : d.terms)
      if (tt.name == "squareness XY") inside += std::abs(tt.value - 20.0) <= 3 * tt.uncertainty;
  }
  EXPECT_GE(inside, 28);
  auto one = predict_ballbar(sq, "XY", {0.0, 0.0, -100.0}, R, 1.0 * kPi / 180);
  std::erase_if(one, [](const TracePoint& s) { return s.direction == CircleDirection::CW; });
  EXPECT_THROW(diagnose_ballbar(one, nominal(R), "XY"), InputError);
}
