// Milling forces against the closed-form tooth-period averages, deflection against DeVor's
// eq. 2.6 and hand beam formulas, and the calibration of e_prog (Yaqoob 2017 sec. 3.7).
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "mtcal/prediction/process_error.hpp"
#include "mtcal/util/errors.hpp"
#include "examples.hpp"

namespace mtcal {
namespace {

using mtcal::testing::kPi;

// Mean Fy over a tooth period by hand: (N ap / 2 pi) integral over the immersion of
// [(Ktc fz sin + Kte) sin - (Krc fz sin + Kre) cos] dphi.
double mean_fy_closed_form(const EndMill& t, const CuttingCoefficients& k, const CutConditions& c, double st,
                           double ex) {
  const double fz = c.feed / (t.teeth * c.spindle_speed);
  auto F = [&](double p) {
    return k.ktc * fz * (p / 2 - std::sin(2 * p) / 4) - k.kte * std::cos(p) -
           k.krc * fz * std::sin(p) * std::sin(p) / 2 - k.kre * std::sin(p);
  };
  return t.teeth * c.axial_depth / (2 * kPi) * (F(ex) - F(st));
}

TEST(ProcessErrorTest, MeanForceMatchesClosedForm) {
  EndMill t;
  CuttingCoefficients k;
  for (bool down : {true, false})
    for (double helix : {0.0, 30.0}) {
      CutConditions c{2.0, 5.0, 400.0, 3500.0, down};
      t.helix_deg = helix;
      const auto f = milling_forces(t, k, c, 3600, 200);
      const double sweep = std::acos(1 - 2 * c.radial_depth / t.diameter);
      const double st = down ? kPi - sweep : 0, ex = down ? kPi : sweep;
      // The helix spreads the force over the rotation but leaves its mean unchanged.
      EXPECT_NEAR(f.mean_y, mean_fy_closed_form(t, k, c, st, ex), 2e-3 * std::abs(f.mean_y)) << down << helix;
      EXPECT_GE(f.peak_y, std::abs(f.mean_y));
    }
}

// A full-immersion slot with one straight tooth and no edge forces: Fy = Ktc ap fz sin^2 phi -
// Krc ap fz sin phi cos phi at phi = theta, checked at a quarter turn.
TEST(ProcessErrorTest, SingleToothForceByHand) {
  EndMill t;
  t.teeth = 1;
  CuttingCoefficients k{800, 200, 0, 0};
  CutConditions c{t.diameter, 4.0, 350.0, 3500.0, false};
  const auto f = milling_forces(t, k, c, 360, 1);
  const double fz = 0.1;
  EXPECT_NEAR(f.fy[90], 800 * 4 * fz, 1e-9);   // phi = 90 deg
  EXPECT_NEAR(f.fx[90], -200 * 4 * fz, 1e-9);  // -Fr sin(phi)
  EXPECT_NEAR(f.fy[45], 800 * 4 * fz * 0.5 - 200 * 4 * fz * 0.5, 1e-9);
}

TEST(ProcessErrorTest, UniformCantileverIsDeVorEq26) {
  EndMill t;
  t.flute_diameter_ratio = 1.0;  // one section
  const double I = kPi * std::pow(t.diameter, 4) / 64, E = t.young_modulus, L = t.overhang, F = 100;
  EXPECT_NEAR(cantilever_deflection(t, F, 0, 0), F * L * L * L / (3 * E * I), 1e-15);
  for (double zf : {0.0, 2.5, 10.0})
    for (double z : {0.0, 1.0, 2.5}) {
      if (z > zf) continue;
      const double eq26 =
          F / (6 * E * I) * (std::pow(zf - z, 3) - std::pow(L - z, 3) + 3 * std::pow(L - z, 2) * (L - zf));
      EXPECT_NEAR(cantilever_deflection(t, F, zf, z), eq26, 1e-12 * eq26 + 1e-18) << zf << " " << z;
      // Maxwell-Betti reciprocity.
      EXPECT_NEAR(cantilever_deflection(t, F, zf, z), cantilever_deflection(t, F, z, zf), 1e-15);
    }
}

// Two sections, tip load, tip deflection: F/(3E) [(L^3 - L1^3)/I2 + L1^3/I1] by hand.
TEST(ProcessErrorTest, TwoSectionTipDeflectionByHand) {
  EndMill t;
  const double L = t.overhang, L1 = t.flute_length, E = t.young_modulus, F = 50;
  const double I2 = kPi * std::pow(t.diameter, 4) / 64, I1 = kPi * std::pow(0.8 * t.diameter, 4) / 64;
  const double hand = F / (3 * E) * ((L * L * L - L1 * L1 * L1) / I2 + L1 * L1 * L1 / I1);
  EXPECT_NEAR(cantilever_deflection(t, F, 0, 0), hand, 1e-12 * hand);
  // Stiffer than all-flute, softer than all-shank.
  EXPECT_GT(hand, F * L * L * L / (3 * E * I2));
  EXPECT_LT(hand, F * L * L * L / (3 * E * I1));
}

// e_prog grows with feed (Fig. 5.30) and a calibration recovers a synthetic mapping measured =
// 0.5 e_prog / (2e-3 + e_prog) (a saturation, the form of eq. 5.51).
TEST(ProcessErrorTest, CalibrationRecoversSyntheticMapping) {
  EndMill t;
  CuttingCoefficients k;
  CutConditions c;
  const std::vector<double> feeds = {100, 200, 400, 800, 1600};
  std::vector<double> e, measured;
  for (double F : feeds) {
    c.feed = F;
    e.push_back(program_generated_error(t, k, c));
    measured.push_back(0.5 * e.back() / (2e-3 + e.back()));
  }
  for (std::size_t i = 1; i < e.size(); ++i) EXPECT_GT(e[i], e[i - 1]);
  const auto cal =
      calibrate_process_error(t, k, CutConditions{}, feeds, measured, {ModelForm::Saturation, 1, std::nullopt});
  ASSERT_TRUE(cal.fit.converged);
  EXPECT_NEAR(cal.fit.model.p[0], 0.5, 1e-6);
  EXPECT_NEAR(cal.fit.model.p[1], 2e-3, 1e-8);
}

TEST(ProcessErrorTest, BadInputsAreRefused) {
  EndMill t;
  CuttingCoefficients k;
  EXPECT_THROW(milling_forces(t, k, CutConditions{11.0, 5, 200, 3500, true}), InputError);
  EXPECT_THROW(milling_forces(t, k, CutConditions{1.0, 30, 200, 3500, true}), InputError);
  EXPECT_THROW(milling_forces(t, k, CutConditions{1.0, 5, 0, 3500, true}), InputError);
  t.teeth = 0;
  EXPECT_THROW(milling_forces(t, k, CutConditions{}), InputError);
  EndMill u;
  EXPECT_THROW(cantilever_deflection(u, 1, 50, 0), InputError);
}

}  // namespace
}  // namespace mtcal
