// The shipped thesis model against the thesis' own tables (Yaqoob 2017 Tables 5.7, 6.4-6.7),
// spindle-speed stages, and refusals of bad model files and points.
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "mtcal/io/model/prediction_model_file.hpp"
#include "mtcal/prediction/prediction_model.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {
namespace {

const std::string kModel = std::string(MTCAL_EXAMPLES_DIR) + "/../prediction/yaqoob2017-model.yaml";

struct Point {
  std::map<std::string, double> v;
  double operator()(const std::string& k) const {
    const auto it = v.find(k);
    if (it == v.end()) throw InputError({"points", 0, k}, "missing column " + k);
    return it->second;
  }
};

Point point(double t, double S, double F, double dx, double dy, double dz = 9) {
  return {{{"t", t}, {"S", S}, {"F", F}, {"dx", dx}, {"dy", dy}, {"dz", dz}, {"h_tt", 10}, {"h_spd", 9}}};
}

double value(const PredictionModel& m, const PointPrediction& p, const std::string& name, bool raw = false) {
  for (std::size_t i = 0; i < m.components.size(); ++i)
    if (m.components[i].name == name) return raw ? p.raw[i] : p.values[i];
  ADD_FAILURE() << "no component " << name;
  return NAN;
}

// Relative closeness to a table value printed with 6-7 significant digits.
#define EXPECT_TABLE(actual, printed, rel) EXPECT_NEAR(actual, printed, (rel)*std::abs(printed) + 1e-12)

// Table 5.7: components of W2 (feeds 200 400 800 1600) and W5 (100 200 400 800) at the four
// steps, 3500 rpm. The machining times are not printed; solving e_pt_x (eq. 5.6) for them gives
// whole minutes, W2: 2 36 74 114, W5: 4 40 73 105. With those times e_pt_y (eq. 5.5, a
// different model) reproduces its own column: the check that the times are the thesis' ones.
TEST(PredictionModelTest, ThesisModelReproducesTable57) {
  const PredictionModel m = read_prediction_model(kModel);
  const double d[4] = {29, 44, 79, 99};
  const double t2[4] = {2, 36, 74, 114}, t5[4] = {4, 40, 73, 105};
  const double f2[4] = {200, 400, 800, 1600}, f5[4] = {100, 200, 400, 800};
  // Columns of Table 5.7: e_pf_x W2, W5, e_pf_y W2, W5, e_pt_x W2, W5, e_pt_y W2, W5, e_pos_x, e_pos_y.
  const double table[4][10] = {{0.000191988, 1.13377e-05, 0.00097635, 4.12225e-05, 0.001235877, 0.002425937,
                                0.001950791, 0.001952618, 0.006423335, 0.009789383},
                               {0.002923753, 0.000191988, 0.005849463, 0.00097635, 0.016447688, 0.017676739,
                                0.003031592, 0.003386255, 0.009114022, 0.013855253},
                               {0.017652045, 0.002923753, 0.007162287, 0.005849463, 0.025097789, 0.024940679,
                                0.008246326, 0.008075374, 0.01371726, 0.020697125},
                               {0.025052323, 0.017652045, 0.007221811, 0.007162287, 0.02946674, 0.028749516,
                                0.014513989, 0.013288542, 0.015294803, 0.022944093}};
  for (int i = 0; i < 4; ++i) {
    SCOPED_TRACE(d[i]);
    const auto w2 = predict_point(m, point(t2[i], 3500, f2[i], d[i], d[i]), false);
    const auto w5 = predict_point(m, point(t5[i], 3500, f5[i], d[i], d[i]), false);
    // Table 5.7 lists the process errors of a dimension (both walls): the model's own value.
    EXPECT_TABLE(value(m, w2, "e_pf_x", true), table[i][0], 2e-6);
    EXPECT_TABLE(value(m, w5, "e_pf_x", true), table[i][1], 2e-5);
    EXPECT_TABLE(value(m, w2, "e_pf_y", true), table[i][2], 2e-6);
    EXPECT_TABLE(value(m, w5, "e_pf_y", true), table[i][3], 2e-5);
    EXPECT_TABLE(value(m, w2, "e_pt_x"), table[i][4], 1e-5);
    EXPECT_TABLE(value(m, w5, "e_pt_x"), table[i][5], 1e-5);
    EXPECT_TABLE(value(m, w2, "e_pt_y"), table[i][6], 1e-6);
    EXPECT_TABLE(value(m, w5, "e_pt_y"), table[i][7], 1e-6);
    EXPECT_TABLE(value(m, w2, "e_pos_x"), table[i][8], 1e-7);
    EXPECT_TABLE(value(m, w2, "e_pos_y"), table[i][9], 1e-7);
  }
  // The two quoted values.
  const auto p = predict_point(m, point(2, 3500, 200, 29, 29), false);
  EXPECT_NEAR(value(m, p, "e_pos_x"), 0.006423, 5e-7);
  EXPECT_NEAR(value(m, p, "e_pf_x", true), 0.000192, 5e-7);
}

// Table 6.4 (cylinder, 4500 rpm, Z points): with the times that solve e_splz (eq. 5.25) for
// its printed column (0.5, 0.85, 1.23, 1.59, 1.955 ... 5.24 min), the three other tilt columns computed by
// interpolating between the 3500 and 5500 rpm stages come out to all printed digits. e_spd_y does not: the table holds
// the 3500 rpm model (eq. 5.7) alone, not interpolated - a discrepancy of the thesis, kept visible.
TEST(PredictionModelTest, ThesisModelReproducesTable64And65) {
  const PredictionModel m = read_prediction_model(kModel);
  const double splz[14] = {7.09248E-05, 0.000120239, 0.000173471, 0.000223607, 0.000274149, 0.000324399, 0.00037436,
                           0.000424034, 0.000473422, 0.000522526, 0.000571348, 0.00061989,  0.000668152, 0.000716138};
  const double tty[14] = {-1.3743E-05,  -2.07342E-05, -2.67417E-05, -3.13453E-05, -3.52168E-05,
                          -3.84782E-05, -4.12652E-05, -4.36758E-05, -4.57831E-05, -4.76421E-05,
                          -4.92954E-05, -5.07764E-05, -5.21117E-05, -5.33224E-05};
  const double ttx[14] = {-6.63161E-05, -6.65992E-05, -6.69046E-05, -6.7192E-05,  -6.74815E-05,
                          -6.77691E-05, -6.80549E-05, -6.83387E-05, -6.86207E-05, -6.89008E-05,
                          -6.91791E-05, -6.94555E-05, -6.97301E-05, -7.00029E-05};
  const double spdx[14] = {-0.000408544, -0.000409144, -0.000409675, -0.000410062, -0.000410341,
                           -0.000410506, -0.00041056,  -0.000410502, -0.000410335, -0.000410058,
                           -0.000409674, -0.000409183, -0.000408585, -0.000407883};
  const double spdy[14] = {6.1541E-05,  8.21389E-05, 0.000100431, 0.000115486, 0.000129229, 0.000141843, 0.00015358,
                           0.000164609, 0.00017505,  0.000184994, 0.000194508, 0.000203648, 0.000212456, 0.000220968};
  const ErrorComponent* sy = m.find("e_spd_y");
  ASSERT_NE(sy, nullptr);
  for (int k = 0; k < 14; ++k) {
    SCOPED_TRACE(k);
    double lo = 0, hi = 10;
    for (int it = 0; it < 100; ++it) {
      const double mid = 0.5 * (lo + hi);
      (value(m, predict_point(m, point(mid, 4500, 100, 10, 10), false), "e_splz") < splz[k] ? lo : hi) = mid;
    }
    const double t = lo;
    const auto p = predict_point(m, point(t, 4500, 100, 10, 10), false);
    EXPECT_TABLE(value(m, p, "e_tt_y"), tty[k], 2e-5);
    EXPECT_TABLE(value(m, p, "e_tt_x"), ttx[k], 2e-6);
    EXPECT_TABLE(value(m, p, "e_spd_x"), spdx[k], 2e-6);
    EXPECT_TABLE(sy->stages[1].model(t), spdy[k], 2e-5);                    // the 3500 rpm stage alone
    EXPECT_GT(std::abs(value(m, p, "e_spd_y") - spdy[k]), 0.05 * spdy[k]);  // not the interpolation
    EXPECT_NEAR(value(m, p, "e_pos_z"), -0.001753, 1e-9);
    EXPECT_NEAR(value(m, p, "e_splf_z"), -0.0026296, 5e-8);
    // Table 6.5: tilts through 10 mm (table) and 9 mm (spindle) lever arms.
    EXPECT_TABLE(value(m, p, "e_z_tt_x"), 10 * ttx[k], 2e-6);
    EXPECT_TABLE(value(m, p, "e_z_tt_y"), 10 * tty[k], 2e-5);
    EXPECT_TABLE(value(m, p, "e_z_spd_x"), -9 * spdx[k], 2e-6);
  }
}

// Tables 6.6-6.7 (cylinder at 4500 rpm and 200 mm/min, 15 points of Table 6.2). The process
// errors are half the fitted ones; e_pos at the points' X / Y coordinates; e_cpr_x by eq. 5.56.
// The thermal times are not printed: those solving e_pt_x put e_pt_y within 0.5 %.
// e_ctrl_x / e_ctrl_y are NOT reproducible: eq. 5.55 is <= 0 for every distance and feed
// >= 100 while Table 6.7 prints +0.0070 - see docs/prediction.md.
TEST(PredictionModelTest, ThesisModelAgainstTables66And67) {
  const PredictionModel m = read_prediction_model(kModel);
  const double X[15] = {10.102, 15.546, 22.291, 25.56, 24.923, 18.255, 7.785, 0.839,
                        1.35,   6.447,  13.705, 17.28, 21.566, 25.512, 26.278};
  const double Y[15] = {1.161, 0.905, 4.383, 9.375, 19.656, 25.827, 25.618, 17.72,
                        8.252, 2.694, 0.769, 1.373, 3.719,  9.192,  14.747};
  const double posx[15] = {0.002420265, 0.003643546, 0.005080473, 0.005745554, 0.005617561,
                           0.004231126, 0.001882417, 0.000208449, 0.000334746, 0.001567144,
                           0.003236218, 0.004021268, 0.0049302,   0.005735937, 0.005888892};
  const double posy[15] = {0.000440767, 0.000343928, 0.001642634, 0.003442767, 0.00691279,
                           0.008842157, 0.008778696, 0.006283775, 0.003044377, 0.001016519,
                           0.000292402, 0.000520811, 0.001397517, 0.003378107, 0.005295775};
  const double ptx[15] = {0.000129393, 0.000322412, 0.000577789, 0.000788888, 0.001008878,
                          0.001227177, 0.001443801, 0.001658763, 0.001872078, 0.002083759,
                          0.002293821, 0.002502276, 0.00270914,  0.002914425, 0.003118144};
  const double pty[15] = {0.001098012, 0.001276625, 0.001504983, 0.001687246, 0.001871247,
                          0.002048137, 0.002218329, 0.002382207, 0.002540128, 0.002692422,
                          0.002839395, 0.002981332, 0.003118499, 0.003251142, 0.003379493};
  for (int k = 0; k < 15; ++k) {
    SCOPED_TRACE(k);
    // Solve e_pt_x(t) = printed by bisection (monotonic), then check e_pt_y there.
    double lo = 0, hi = 10;
    for (int it = 0; it < 100; ++it) {
      const double mid = 0.5 * (lo + hi);
      const auto p = predict_point(m, point(mid, 4500, 200, X[k], Y[k]), false);
      (value(m, p, "e_pt_x") < ptx[k] ? lo : hi) = mid;
    }
    const auto p = predict_point(m, point(lo, 4500, 200, X[k], Y[k]), false);
    EXPECT_TABLE(value(m, p, "e_pt_y"), pty[k], 5e-3);
    EXPECT_TABLE(value(m, p, "e_pf_x"), 9.5994E-05, 2e-5);
    EXPECT_TABLE(value(m, p, "e_pf_y"), 0.000488175, 2e-6);
    EXPECT_TABLE(value(m, p, "e_pos_x"), posx[k], 2e-6);
    EXPECT_TABLE(value(m, p, "e_pos_y"), posy[k], 2e-5);
    EXPECT_TABLE(value(m, p, "e_cpr_x"), 0.001662412, 2e-6);
    EXPECT_TABLE(value(m, p, "e_cpr_y"), -4.1528E-05, 1e-9);
    EXPECT_LE(value(m, p, "e_ctrl_x"), 0.0);  // Table 6.7: +0.0070 (not reproducible)
  }
  // Eq. 5.55 at 200 mm/min by hand: (200 - 100) / 2300 * (-0.036 + 0.036 / (1 + (dx / 77.1779)^7.60716)):
  // dx = 29: -9.1318e-7, dx = 99: -0.00136055; bounded by 0.036 * 100 / 2300 = 0.00156522 in size
  // for every distance, against Table 6.7's +0.0070.
  const auto at29 = predict_point(m, point(10, 4500, 200, 29, 29), false);
  const auto at99 = predict_point(m, point(10, 4500, 200, 99, 99), false);
  EXPECT_NEAR(value(m, at29, "e_ctrl_x"), -9.1318e-7, 1e-10);
  EXPECT_NEAR(value(m, at99, "e_ctrl_x"), -0.00136055, 1e-8);
}

TEST(PredictionModelTest, StagesAreContinuousAtTheStageSpeeds) {
  const PredictionModel m = read_prediction_model(kModel);
  for (const auto& c : m.components) {
    if (c.stages.empty()) continue;
    SCOPED_TRACE(c.name);
    for (double t : {1.0, 30.0, 90.0}) {
      // A speed change eps moves the value by at most eps (|f_lo| + |f_hi|) / (stage gap >= 1000
      // rpm): the bound below; the thesis' printed weights would jump by |f_lo - f_hi|.
      double big = 1e-6;
      for (const auto& s : c.stages) big = std::max(big, std::abs(s.model(t)));
      for (const auto& s : c.stages) {
        const double at = evaluate_stages(c.stages, s.speed, t);
        EXPECT_DOUBLE_EQ(at, s.model(t));
        for (double eps : {1e-6, -1e-6}) EXPECT_NEAR(evaluate_stages(c.stages, s.speed + eps, t), at, 1e-8 * big);
      }
      // Halfway between two stages: their mean (eq. 3.7 with equal weights); proportional below
      // and above (eq. 3.9, 3.10).
      EXPECT_NEAR(evaluate_stages(c.stages, 4500, t), 0.5 * (c.stages[1].model(t) + c.stages[2].model(t)), 1e-15);
      EXPECT_NEAR(evaluate_stages(c.stages, 400, t), 0.4 * c.stages[0].model(t), 1e-15);
      EXPECT_NEAR(evaluate_stages(c.stages, 6600, t), 1.2 * c.stages[2].model(t), 1e-15);
    }
  }
}

TEST(PredictionModelTest, ValidityRangeWarnsOrRefuses) {
  const PredictionModel m = read_prediction_model(kModel);
  const auto p = predict_point(m, point(150, 3500, 200, 29, 29), false);
  ASSERT_FALSE(p.warnings.empty());
  EXPECT_NE(p.warnings[0].find("e_pt_x: t = 150 is outside the validity range [0, 130]"), std::string::npos)
      << p.warnings[0];
  EXPECT_THROW(predict_point(m, point(150, 3500, 200, 29, 29), true), InputError);
  EXPECT_TRUE(predict_point(m, point(100, 3500, 200, 29, 29), true).warnings.empty());
  // e_pt_y's logistic in ln t is undefined for t < 0: refused even without --strict.
  EXPECT_THROW(predict_point(m, point(-1, 3500, 200, 29, 29), false), InputError);
  Point missing = point(10, 3500, 200, 29, 29);
  missing.v.erase("F");
  EXPECT_THROW(predict_point(m, missing, false), InputError);
}

// Spindle speed <= 0 has no thermal stage (eq. 3.7-3.10 scale by S / S_stage): refused.
TEST(PredictionModelTest, SpindleSpeedMustBePositive) {
  const PredictionModel m = read_prediction_model(kModel);
  for (double S : {0.0, -3500.0}) {
    try {
      predict_point(m, point(10, S, 200, 29, 29), false, "p.csv:2");
      ADD_FAILURE() << "no error for S = " << S;
    } catch (const InputError& e) {
      EXPECT_EQ(e.where().field, "S");
      EXPECT_NE(std::string(e.what()).find("expected a spindle speed S > 0 rpm"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(std::isnan(evaluate_stages(m.find("e_pt_x")->stages, S, 10)));
  }
}

// evaluate_component follows predict_point: scale, ramp and validity. e_pf_x at 200 mm/min by
// hand (the unnumbered e_pf_x equation between eq. 5.47 and 5.48): 0.0257241 - 0.0257241 /
// (1 + (200 / 660.765)^4.09199) = 0.000191988 (Table 5.7), halved by scale 0.5; e_ctrl_x at
// dx = 79 with its ramp at one_at (F = 2400): -0.0195934157 (eq. 5.53).
TEST(PredictionModelTest, EvaluateComponentIsThePredictPath) {
  const PredictionModel m = read_prediction_model(kModel);
  const Point p = point(10, 3500, 200, 79, 79);
  const auto pf = evaluate_component(m, "e_pf_x", p, false);
  EXPECT_NEAR(pf.raw, 0.000191988, 5e-10);
  EXPECT_NEAR(pf.value, 0.000191988 / 2, 5e-10);
  Point q = p;
  q.v["F"] = 2400;
  EXPECT_NEAR(evaluate_component(m, "e_ctrl_x", q, false).value, -0.0195934157, 1e-9);
  // 'of' with times: e_z_spd_x = -9 e_spd_x.
  EXPECT_NEAR(evaluate_component(m, "e_z_spd_x", p, false).value, -9 * value(m, predict_point(m, p, false), "e_spd_x"),
              1e-15);
  Point far = p;
  far.v["F"] = 3000;
  EXPECT_FALSE(evaluate_component(m, "e_pf_x", far, false).warnings.empty());
  EXPECT_THROW(evaluate_component(m, "e_pf_x", far, true), InputError);
  EXPECT_THROW(evaluate_component(m, "e_nothing", p, false), InputError);
}

// The error message names the file, the line and the key.
std::string prediction_model_error_of(const std::string& text) {
  try {
    parse_prediction_model(text, "m.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(PredictionModelTest, BadModelFilesAreRefused) {
  const std::string head = "mtcal_prediction_model: 1\ncomponents:\n";
  EXPECT_NE(prediction_model_error_of(head + "  - {name: a, axis: x, variable: t, form: cubic, coefficients: [1]}\n")
                .find("unknown model form 'cubic'"),
            std::string::npos);
  EXPECT_NE(prediction_model_error_of(head + "  - {name: a, axis: x, variable: t, form: cubic}\n").find("m.yaml:3"), std::string::npos);
  EXPECT_NE(prediction_model_error_of(head + "  - {name: a, axis: x, variable: t, form: saturation, parameters: {a: 1}}\n")
                .find("missing parameter 'b'"),
            std::string::npos);
  EXPECT_NE(prediction_model_error_of(head + "  - {name: a, axis: w, variable: t, form: power, parameters: {a: 1, b: 1}}\n")
                .find("expected x, y, z or none"),
            std::string::npos);
  EXPECT_NE(prediction_model_error_of(head + "  - {name: a, axis: x, of: b}\n").find("'b' is not a component defined above"),
            std::string::npos);
  EXPECT_NE(prediction_model_error_of(head + "  - {name: a, axis: x, variable: t, form: power, parameters: {a: 1, b: 1}}\n"
                            "  - {name: a, axis: y, variable: t, form: power, parameters: {a: 1, b: 1}}\n")
                .find("defined twice"),
            std::string::npos);
  EXPECT_NE(prediction_model_error_of(head + "  - name: a\n    axis: x\n    variable: t\n    stages:\n"
                            "      - {speed: 3500, form: power, parameters: {a: 1, b: 1}}\n"
                            "      - {speed: 1000, form: power, parameters: {a: 1, b: 1}}\n")
                .find("increasing speed"),
            std::string::npos);
  EXPECT_NE(prediction_model_error_of("mtcal_prediction_model: 2\ncomponents: []\n").find("format version"), std::string::npos);
  EXPECT_NE(prediction_model_error_of(head + "  - {name: a, axis: x, variable: t, form: power, parameters: {a: 1, b: 1}, bogus: 1}\n")
                .find("unknown key 'bogus'"),
            std::string::npos);
  EXPECT_NE(prediction_model_error_of("mtcal_prediction_model: 1\nunits: {time: s}\ncomponents: []\n").find("expected 'min'"),
            std::string::npos);
  EXPECT_THROW(read_prediction_model("/nonexistent/model.yaml"), InputError);
}

// Parameters outside a form's domain are refused with file, line and key; a power with b = 0
// is the constant a, also at x = 0.
TEST(PredictionModelTest, ParametersOutsideTheDomainAreRefused) {
  const std::string head = "mtcal_prediction_model: 1\ncomponents:\n";
  const std::string logistic = prediction_model_error_of(
      head + "  - {name: a, axis: x, variable: t, form: logistic_ln, parameters: {a: 1, b: 1, k: 2, x0: -3}}\n");
  EXPECT_NE(logistic.find("m.yaml:3"), std::string::npos) << logistic;
  EXPECT_NE(logistic.find("a.parameters"), std::string::npos) << logistic;
  EXPECT_NE(logistic.find("x0 > 0"), std::string::npos) << logistic;
  EXPECT_NE(prediction_model_error_of(head + "  - {name: a, axis: x, variable: t, form: power, parameters: {a: 1, b: -0.5}}\n")
                .find("undefined at x = 0"),
            std::string::npos);
  EXPECT_NE(prediction_model_error_of(
                head +
                "  - {name: a, axis: x, variable: t, form: stretched_exp, parameters: {a: 1, b: 1, c: 1, d: -1}}\n")
                .find("d > 0"),
            std::string::npos);
  EXPECT_NE(prediction_model_error_of(head + "  - {name: a, axis: x, variable: t, form: saturation, parameters: {a: 1, b: -28}}\n")
                .find("b > 0"),
            std::string::npos);
  // A stage's parameters name the stage.
  const std::string stage =
      prediction_model_error_of(head +
               "  - name: a\n    axis: x\n    variable: t\n    stages:\n"
               "      - {speed: 1000, form: power, parameters: {a: 1, b: 1}}\n"
               "      - {speed: 3500, form: logistic_ln, parameters: {a: 1, b: 1, k: 2, x0: 0}}\n");
  EXPECT_NE(stage.find("m.yaml:8"), std::string::npos) << stage;
  EXPECT_NE(stage.find("a.stages.1.parameters"), std::string::npos) << stage;
  // b < 0 with a validity range above 0 is accepted.
  EXPECT_EQ(prediction_model_error_of(head +
                     "  - {name: a, axis: x, variable: t, form: power, parameters: {a: 1, b: -0.5}, valid: [1, 10]}\n"),
            "no error");
  const PredictionModel m =
      parse_prediction_model(head + "  - {name: a, axis: x, variable: t, form: power, parameters: {a: 2.5, b: 0}}\n",
                             "m.yaml");
  const auto p = predict_point(m, Point{{{"t", 0.0}}}, true);
  EXPECT_EQ(p.e[0], 2.5);
}

}  // namespace
}  // namespace mtcal

namespace mtcal {
namespace {

// Compensation per step (Table 6.1 style) against hand values: minus the mean error of the
// step's points, steps in the order they first appear.
TEST(PredictionModelTest, CompensationOffsetsPerStep) {
  PredictionPoints pts{{"step"}, {{2}, {1}, {2}}, {2, 3, 4}, "p.csv"};
  std::vector<PointPrediction> pred(3);
  pred[0].e[0] = 0.010, pred[0].e[1] = -0.004, pred[0].e[2] = 0.001;
  pred[1].e[0] = 0.003, pred[1].e[1] = 0.002, pred[1].e[2] = 0.0;
  pred[2].e[0] = 0.020, pred[2].e[1] = 0.000, pred[2].e[2] = 0.003;
  const auto c = compensation_offsets(pts, pred);
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c[0].step, 2);
  EXPECT_NEAR(c[0].offset[0], -0.015, 1e-15);
  EXPECT_NEAR(c[0].offset[1], 0.002, 1e-15);
  EXPECT_NEAR(c[0].offset[2], -0.002, 1e-15);
  EXPECT_EQ(c[1].step, 1);
  EXPECT_NEAR(c[1].offset[0], -0.003, 1e-15);
  EXPECT_NEAR(c[1].offset[1], -0.002, 1e-15);
  pts.columns = {"t"};
  EXPECT_THROW(compensation_offsets(pts, pred), InputError);
}

}  // namespace
}  // namespace mtcal
