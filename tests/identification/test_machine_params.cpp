// From measurements to model parameters: motion errors fitted to positioning runs (known
// polynomials, tables, Fourier series recovered; the form criterion), ballbar diagnostics as
// parameters (traces the model predicts for known errors), the parameter file read back.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "mtcal/evaluation/ballbar.hpp"
#include "mtcal/identification/machine_params.hpp"
#include "mtcal/identification/motion_fit.hpp"
#include "mtcal/io/model/estimated_parameters_file.hpp"
#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/util/errors.hpp"
#include "examples.hpp"

using namespace mtcal;

namespace {

using mtcal::testing::kPi;

// Runs of one axis whose deviation (um) is f(q, dir) plus Gaussian noise sigma (um), targets in mm.
template <class F>
PositioningRuns synthetic_runs(const std::vector<double>& targets, int runs, double sigma, F f, unsigned seed = 7,
                               const std::string& target_unit = "mm", const std::string& unit = "um") {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma);
  PositioningRuns r;
  r.source = "synthetic";
  r.deviations = true;
  r.unit = unit;
  r.target_unit = target_unit;
  r.targets = targets;
  for (double t : targets) {
    std::vector<double> up, down;
    for (int j = 0; j < runs; ++j) {
      up.push_back(f(t, 1) + (sigma > 0 ? noise(rng) : 0.0));
      down.push_back(f(t, -1) + (sigma > 0 ? noise(rng) : 0.0));
    }
    r.up.push_back(up);
    r.down.push_back(down);
  }
  return r;
}

std::vector<double> range(double lo, double hi, int n) {
  std::vector<double> v;
  for (int i = 0; i < n; ++i) v.push_back(lo + (hi - lo) * i / (n - 1));
  return v;
}

}  // namespace

TEST(FitMotion, RecoversAQuadraticWithReversalAndPicksThePolynomial) {
  // EXX(q) = 2 um + 12 um/m q - 20 um/m^2 q^2 (q in m) + 1.5 um * dir; 0.2 um noise, 5 runs.
  auto f = [](double q_mm, int dir) {
    const double q = q_mm * 1e-3;
    return 2 + 12 * q - 20 * q * q + 1.5 * dir;
  };
  const auto runs = synthetic_runs(range(0, 800, 17), 5, 0.2, f);
  MotionFit fit;
  const EstimatedError e = estimate_motion_error(runs, "EXX", {}, &fit);
  EXPECT_EQ(fit.form, "polynomial");
  EXPECT_EQ(fit.degree, 2) << fit.reason;
  const auto& p = std::get<Polynomial>(e.motion->form());
  // Internal units: mm, mm/mm, mm/mm^2. Within 4 standard uncertainties of the truth.
  const double truth[] = {2e-3, 12e-6, -20e-9};
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(p.coefficients[k], truth[k], 4 * e.uncertainty[k] + 1e-15) << k;
  EXPECT_NEAR(p.reversal, 1.5e-3, 4 * e.uncertainty[4]);
  // The uncertainties are those of 0.2 um noise over 170 runs, not zero and not huge.
  EXPECT_GT(e.uncertainty[4], 1e-6);
  EXPECT_LT(e.uncertainty[4], 5e-5);
}

TEST(FitMotion, NoiseFreeLinearErrorIsExactAndATableReproducesTheMeans) {
  auto f = [](double q, int dir) { return 0.01 * q + 0.5 * dir; };  // 10 um/m, Eb 0.5 um
  const auto runs = synthetic_runs(range(-300, 300, 7), 3, 0.0, f);
  MotionFitOptions o;
  o.form = "polynomial";
  o.max_degree = 1;
  const auto e = estimate_motion_error(runs, "EXX", o);
  const auto& p = std::get<Polynomial>(e.motion->form());
  EXPECT_NEAR(p.coefficients[0], 0, 1e-15);
  EXPECT_NEAR(p.coefficients[1], 10e-6, 1e-15);
  EXPECT_NEAR(p.reversal, 0.5e-3, 1e-15);
  o.form = "table";
  const auto t = estimate_motion_error(runs, "EXX", o);
  const auto& table = std::get<Table>(t.motion->form());
  ASSERT_EQ(table.positions.size(), 7u);
  EXPECT_NEAR(table.forward[0], (0.01 * -300 + 0.5) * 1e-3, 1e-15);
  EXPECT_NEAR(table.backward[6], (0.01 * 300 - 0.5) * 1e-3, 1e-15);
  // The model's motion function gives back the measured means in each direction.
  EXPECT_NEAR(t.motion->value(100, 1), (1.0 + 0.5) * 1e-3, 1e-15);
  EXPECT_NEAR(t.motion->value(100, -1), (1.0 - 0.5) * 1e-3, 1e-15);
}

TEST(FitMotion, APitchErrorNoCubicFollowsBecomesATable) {
  // A lead-screw pitch error: 3 um amplitude, 50 mm period, 0.1 um noise: far beyond a cubic.
  auto f = [](double q, int dir) { return 3 * std::sin(2 * kPi * q / 50) + 0.8 * dir; };
  const auto runs = synthetic_runs(range(0, 500, 41), 5, 0.1, f);
  MotionFit fit;
  const auto e = estimate_motion_error(runs, "EXX", {}, &fit);
  EXPECT_EQ(fit.form, "table");
  EXPECT_NE(fit.reason.find("no polynomial up to degree 3"), std::string::npos) << fit.reason;
  // u of each table value: s / sqrt(5), about 0.1 / sqrt(5) um.
  for (double u : e.uncertainty) EXPECT_LT(u, 0.1e-3);
}

TEST(FitMotion, StraightnessAndAngularTestsLoseTheirReference) {
  // EYX: a bow of 4 um over 600 mm on a tilted laser line (slope 30 um/m, offset 5 um).
  auto bow = [](double q, int) {
    const double x = (q - 300) / 300;
    return 5 + 0.03 * q + 4 * (x * x - 1.0 / 3);
  };
  const auto runs = synthetic_runs(range(0, 600, 13), 2, 0.0, bow);
  MotionFitOptions o;
  o.form = "polynomial";
  o.max_degree = 2;
  MotionFit fit;
  const auto e = estimate_motion_error(runs, "EYX", o, &fit);
  const auto& p = std::get<Polynomial>(e.motion->form());
  // The least-squares line of the 13 samples of the bow has no slope (symmetric targets) and the
  // offset mean(x^2) = (2/13) sum_{i=1..6} (i/6)^2 = 7/18, so what remains is 4 um (x^2 - 7/18).
  EXPECT_NEAR(e.motion->value(300, 0), -4.0 * 7 / 18 * 1e-3, 1e-12);
  EXPECT_NEAR(e.motion->value(0, 0), 4.0 * 11 / 18 * 1e-3, 1e-12);
  EXPECT_NEAR(p.reversal, 0, 1e-15);
  ASSERT_FALSE(fit.notes.empty());
  EXPECT_NE(fit.notes[0].find("line"), std::string::npos);
  // EBX in arcsec: the mean is removed.
  const auto ang = synthetic_runs(
      range(0, 600, 7), 2, 0.0, [](double q, int) { return 2 + q / 100; }, 7, "mm", "arcsec");
  const auto a = estimate_motion_error(ang, "EBX", o);
  EXPECT_NEAR(a.motion->value(300, 0), 0, 1e-15);
  EXPECT_NEAR(a.motion->value(600, 0), 3 * kPi / 648000, 1e-15);
}

TEST(FitMotion, RotaryAxisTakesAFourierSeries) {
  // ECC(q) = 3 arcsec cos q - 2 arcsec sin 2q + 1 arcsec dir, targets 0..345 deg.
  auto f = [](double deg, int dir) {
    const double q = deg * kPi / 180;
    return 3 * std::cos(q) - 2 * std::sin(2 * q) + dir;
  };
  const auto runs = synthetic_runs(range(0, 345, 24), 3, 0.05, f, 11, "deg", "arcsec");
  MotionFit fit;
  const auto e = estimate_motion_error(runs, "ECC", {}, &fit);
  EXPECT_EQ(fit.form, "fourier") << fit.reason;
  EXPECT_EQ(fit.degree, 2);
  const auto& s = std::get<Fourier>(e.motion->form());
  const double as = kPi / 648000;
  EXPECT_NEAR(s.cos_terms[0], 3 * as, 4 * e.uncertainty[1]);
  EXPECT_NEAR(s.sin_terms[1], -2 * as, 4 * e.uncertainty[4]);
  EXPECT_NEAR(s.reversal, as, 4 * e.uncertainty[5]);
  EXPECT_TRUE(e.rotary_argument);
}

TEST(FitMotion, UnitsAndNamesAreChecked) {
  const auto runs = synthetic_runs(range(0, 100, 3), 2, 0.0, [](double, int) { return 0.0; });
  EXPECT_THROW(estimate_motion_error(runs, "EX0C", {}), InputError);  // not a motion error
  EXPECT_THROW(estimate_motion_error(runs, "EAX", {}), InputError);   // um for an angle
  EXPECT_THROW(estimate_motion_error(runs, "ECC", {}), InputError);   // mm targets for a rotary axis
  MotionFitOptions o;
  o.form = "fourier";
  EXPECT_THROW(estimate_motion_error(runs, "EXX", o), InputError);
  std::vector<EstimatedError> two(2);
  two[0].name = two[1].name = *ErrorName::parse("EXX");
  two[0].source = "a.rtl", two[1].source = "b.rtl";
  try {
    check_distinct(two);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("a.rtl"), std::string::npos) << e.what();
  }
}

TEST(FitMotion, TheParameterFileLoadsIntoAMachineAndGivesTheFittedErrors) {
  auto f = [](double q, int dir) { return 0.02 * q + 0.7 * dir; };
  const auto runs = synthetic_runs(range(0, 500, 6), 3, 0.0, f);
  MotionFitOptions o;
  o.form = "table";
  std::vector<EstimatedError> errors = {estimate_motion_error(runs, "EXX", o)};
  o.form = "polynomial";
  o.max_degree = 1;
  errors.push_back(estimate_motion_error(runs, "EZX", o));  // straightness: line removed, reversal kept
  const std::string yaml = estimated_parameters_yaml(errors, "test");
  Machine m = parse_machine("mtcal_machine: 1\ntopology: wXYfZt\naxes: {X: {}, Y: {}, Z: {}}\n", "m.yaml");
  apply_parameters(m, yaml, "params.yaml");
  const auto& exx = m.axes[*m.axis_index('X')].motion[0];
  EXPECT_NEAR(exx.value(250, 1), (5 + 0.7) * 1e-3, 1e-15);
  EXPECT_NEAR(exx.value(250, -1), (5 - 0.7) * 1e-3, 1e-15);
  const auto& ezx = m.axes[*m.axis_index('X')].motion[2];
  EXPECT_NEAR(ezx.value(250, 0), 0, 1e-15);
  EXPECT_NEAR(ezx.value(400, 1), 0.7e-3, 1e-15);
  EXPECT_NEAR(ezx.value(400, -1), -0.7e-3, 1e-15);
}

TEST(BallbarParams, DiagnosticsOfAPredictedTraceGiveBackTheModelsErrors) {
  // Forward: the model predicts the trace of known squareness, scales and backlash; inverse:
  // the diagnostic fit and its conversion to parameters must give them back, in every plane.
  Machine m = parse_machine(
      "mtcal_machine: 1\ntopology: wXYfZt\naxes: {X: {}, Y: {}, Z: {}}\nerrors:\n  EC0Y: 20 urad\n  EA0Z: -12 urad\n"
      "  EB0Z: 15 urad\n  EXX: {unit: um, argument_unit: m, polynomial: [0, 10], reversal: 2}\n"
      "  EYY: {unit: um, argument_unit: m, polynomial: [0, -4], reversal: -1}\n"
      "  EZZ: {unit: um, argument_unit: m, polynomial: [0, 6], reversal: 1.5}\n",
      "bb.yaml");
  struct MachineParamsCase {
    const char* plane;
    const char* squareness;
    double value;
    double slope1, slope2;  // the two axes' scales, um/m
    double rev1, rev2;      // um
  };
  for (const MachineParamsCase c : {MachineParamsCase{"XY", "EC0Y", 20e-6, 10, -4, 2, -1}, MachineParamsCase{"YZ", "EA0Z", -12e-6, -4, 6, -1, 1.5},
                       MachineParamsCase{"ZX", "EB0Z", 15e-6, 6, 10, 1.5, 2}}) {
    SCOPED_TRACE(c.plane);
    BallbarOptions bo;
    bo.nominal_radius = 150;
    const auto trace = predict_ballbar(m, c.plane, {0, 0, 0}, 150, kPi / 180);
    const auto d = diagnose_ballbar(trace, bo, c.plane);
    const auto p = ballbar_parameters(d, c.plane, {}, "trace.csv");
    ASSERT_EQ(p.size(), 3u);
    EXPECT_EQ(p[0].name.str(), c.squareness);
    EXPECT_NEAR(p[0].value, c.value, 0.05e-6);
    const double half = 0.5 * (c.slope1 - c.slope2) * 1e-6;  // only the mismatch is seen
    const auto& p1 = std::get<Polynomial>(p[1].motion->form());
    const auto& p2 = std::get<Polynomial>(p[2].motion->form());
    EXPECT_NEAR(p1.coefficients[1], half, 0.05e-6);
    EXPECT_NEAR(p2.coefficients[1], -half, 0.05e-6);
    EXPECT_NEAR(p1.reversal, c.rev1 * 1e-3, 0.01e-3);
    EXPECT_NEAR(p2.reversal, c.rev2 * 1e-3, 0.01e-3);
    EXPECT_EQ(p[1].name.str(), std::string("E") + c.plane[0] + c.plane[0]);
  }
  // Squareness only, and a bad plane.
  BallbarOptions bo;
  const auto d = diagnose_ballbar(predict_ballbar(m, "XY", {0, 0, 0}, 150, kPi / 180), bo, "XY");
  EXPECT_EQ(ballbar_parameters(d, "XY", {true, false, false}, "t").size(), 1u);
  EXPECT_THROW(ballbar_parameters(d, "XZ", {}, "t"), InputError);
}
