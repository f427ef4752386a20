// ISO 230-6 diagonal displacement simulation against hand calculations.
#include <gtest/gtest.h>

#include <cmath>

#include "mtcal/evaluation/diagonals.hpp"
#include "mtcal/io/text/joints.hpp"
#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/util/errors.hpp"
#include "synthetic.hpp"

namespace mtcal {
namespace {

Machine clean_vmc() {
  Machine m = load_machine(std::string(MTCAL_EXAMPLES_DIR) + "/vmc-3axis.yaml");
  m.clear_errors();
  return m;
}

const DiagonalProfile& find(const std::vector<DiagonalProfile>& d, const std::string& name) {
  for (const auto& p : d)
    if (p.name == name) return p;
  throw std::runtime_error("no diagonal " + name);
}

TEST(Diagonals, LinearScaleErrorHandCalculation) {
  // EXX = 1e-5 * x: along a diagonal with X travel 400 mm the laser reads u_x * 4 um at the end.
  Machine m = clean_vmc();
  m.set_parameter("EXX.1", 1e-5);
  const ErrorModel model(m);
  const auto lo = parse_joint_values(m, "X=0,Y=0,Z=-400", "test"),
             hi = parse_joint_values(m, "X=400,Y=300,Z=0", "test");
  const auto d = diagonal_displacements(model, lo, hi, {5, true});
  ASSERT_EQ(d.size(), 16u);
  const double L = std::sqrt(400.0 * 400 + 300 * 300 + 400 * 400);
  for (const char* name : {"body PPP", "body NPP", "body PNP", "body PPN"}) {
    const auto& p = find(d, name);
    EXPECT_NEAR(p.length, L, 1e-9) << name;
    ASSERT_EQ(p.deviation.size(), 5u);
    EXPECT_EQ(p.deviation[0], 0.0);
    EXPECT_NEAR(p.deviation[4], 400.0 / L * 0.004, 1e-12) << name;
    EXPECT_NEAR(p.deviation[2], 0.5 * 400.0 / L * 0.004, 1e-12) << name;
    EXPECT_NEAR(p.range, 400.0 / L * 0.004, 1e-12) << name;
    EXPECT_NEAR(p.position[4], L, 1e-9);
    EXPECT_NEAR(p.position[1], L / 4, 1e-9);
  }
  EXPECT_NEAR(find(d, "body NPP").direction.x(), -400.0 / L, 1e-12);
  // Face diagonals: XY 400 x 300 (u_x = 0.8), YZ (no X travel: nothing), ZX 400 x 400.
  EXPECT_NEAR(find(d, "face XY Z- PP").range, 0.8 * 0.004, 1e-12);
  EXPECT_NEAR(find(d, "face XY Z+ NP").range, 0.8 * 0.004, 1e-12);
  EXPECT_NEAR(find(d, "face YZ X+ PP").range, 0.0, 1e-15);
  EXPECT_NEAR(find(d, "face ZX Y- PP").range, std::sqrt(0.5) * 0.004, 1e-12);
  EXPECT_EQ(diagonal_displacements(model, lo, hi, {5, false}).size(), 4u);
}

TEST(Diagonals, SquarenessSeparatesTheBodyDiagonals) {
  // A squareness error adds +-c * dx * dy / L: opposite on PPP and NPP, which is why ISO 230-6
  // measures all four.
  Machine m = clean_vmc();
  const double c = 30e-6;
  m.set_parameter("EC0Y", c);
  const ErrorModel model(m);
  const auto lo = parse_joint_values(m, "X=0,Y=0,Z=-400", "test"),
             hi = parse_joint_values(m, "X=400,Y=300,Z=0", "test");
  const auto d = diagonal_displacements(model, lo, hi, {11, false});
  const double L = std::sqrt(400.0 * 400 + 300 * 300 + 400 * 400);
  const double ppp = find(d, "body PPP").deviation.back(), npp = find(d, "body NPP").deviation.back();
  // To first order; the exact rotation adds terms of c^2 * 300 mm (about 3e-7 mm).
  const double second = c * c * 300;
  // dx = -Y sin(EC0Y) (docs/conventions.md): along PPP (+X +Y +Z) the laser reads -c dx dy / L.
  EXPECT_NEAR(ppp, -400.0 * 300.0 * c / L, second);
  EXPECT_NEAR(ppp, -npp, second);
  EXPECT_NEAR(find(d, "body PNP").deviation.back(), npp, second);
  EXPECT_NEAR(find(d, "body PPN").deviation.back(), ppp, second);
}

TEST(Diagonals, BadInput) {
  const Machine m = clean_vmc();
  const ErrorModel model(m);
  const auto lo = parse_joint_values(m, "X=0,Y=0,Z=-400", "test"),
             hi = parse_joint_values(m, "X=400,Y=300,Z=0", "test");
  EXPECT_THROW(diagonal_displacements(model, lo, lo), InputError);  // zero-size box
  EXPECT_THROW(diagonal_displacements(model, lo, hi, {1, true}), InputError);
  const Machine two = ::mtcal::testing::nominal_machine("wXfYt");
  const std::vector<double> z(2, 0.0), o(2, 100.0);
  EXPECT_THROW(diagonal_displacements(ErrorModel(two), z, o), InputError);
}

}  // namespace
}  // namespace mtcal
