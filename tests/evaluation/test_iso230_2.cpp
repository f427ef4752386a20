// ISO 230-2 positioning evaluation against a hand calculation and the real runs of
// ../shared/data/iso230-2, with every bad input named.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "mtcal/evaluation/iso230_2.hpp"
#include "mtcal/io/instruments/iso230_files.hpp"
#include "mtcal/util/errors.hpp"

using namespace mtcal;

namespace {

// Two targets, two runs per direction: small enough to compute by hand (PRODUCT.md formulas).
PositioningRuns hand_case() {
  PositioningRuns r;
  r.targets = {0, 10};
  r.up = {{0.001, 0.003}, {10.004, 10.006}};
  r.down = {{-0.001, 0.001}, {10.002, 10.002}};
  return r;
}

std::string iso230_2_write_temp(const std::string& name, const std::string& text) {
  const auto p = std::filesystem::temp_directory_path() / name;
  std::ofstream(p) << text;
  return p.string();
}

}  // namespace

TEST(Iso230_2, HandCalculation) {
  const auto e = evaluate_positioning(hand_case());
  const double s = std::sqrt(2e-6);  // sample sd of {0.001, 0.003} etc. (n - 1)
  ASSERT_EQ(e.targets.size(), 2u);
  EXPECT_NEAR(e.targets[0].mean_up, 0.002, 1e-12);
  EXPECT_NEAR(e.targets[0].mean_down, 0.0, 1e-12);
  EXPECT_NEAR(e.targets[0].s_up, s, 1e-12);
  EXPECT_NEAR(e.targets[1].s_down, 0.0, 1e-12);
  EXPECT_NEAR(e.targets[0].reversal, 0.002, 1e-12);
  EXPECT_NEAR(e.targets[1].reversal, 0.003, 1e-12);
  EXPECT_NEAR(e.targets[0].R, 4 * s + 0.002, 1e-12);  // 2s + 2s + |B| beats 4s here
  EXPECT_NEAR(e.targets[1].R, 2 * s + 0.003, 1e-12);
  EXPECT_NEAR(e.B, 0.003, 1e-12);
  EXPECT_NEAR(e.B_mean, 0.0025, 1e-12);
  EXPECT_NEAR(e.R, 4 * s + 0.002, 1e-12);
  EXPECT_NEAR(e.R_up, 4 * s, 1e-12);
  EXPECT_NEAR(e.R_down, 4 * s, 1e-12);
  EXPECT_NEAR(e.E_up, 0.003, 1e-12);
  EXPECT_NEAR(e.E_down, 0.002, 1e-12);
  EXPECT_NEAR(e.E, 0.005, 1e-12);  // max over both directions minus min over both
  EXPECT_NEAR(e.M, 0.0025, 1e-12);
  EXPECT_NEAR(e.A_up, (0.005 + 2 * s) - (0.002 - 2 * s), 1e-12);
  EXPECT_NEAR(e.A_down, (0 + 2 * s) - (0 - 2 * s), 1e-12);
  EXPECT_NEAR(e.A, (0.005 + 2 * s) - (0 - 2 * s), 1e-12);
}

TEST(Iso230_2, MeansAreOverRunsNotTargetsAndDirectionsAreNotSwapped) {
  // Nine targets, five runs (as b02_x_axis.dat): a mean divided by the number of targets, or
  // forward and backward swapped, would change these.
  PositioningRuns r;
  for (int i = 0; i < 9; ++i) {
    r.targets.push_back(i * 5.0);
    r.up.push_back(std::vector<double>(5, i * 5.0 + 0.010));
    r.down.push_back(std::vector<double>(5, i * 5.0 - 0.004));
  }
  const auto e = evaluate_positioning(r);
  EXPECT_NEAR(e.targets[3].mean_up, 0.010, 1e-12);
  EXPECT_NEAR(e.targets[3].mean_down, -0.004, 1e-12);
  EXPECT_NEAR(e.B_mean, 0.014, 1e-12);
  EXPECT_NEAR(e.E, 0.014, 1e-12);
  EXPECT_NEAR(e.R, 0.014, 1e-12);  // R_i = |B_i| with zero spread, not R_up = 0
}

TEST(Iso230_2, ReadsTheRealDatFiles) {
  const std::string dir = std::string(MTCAL_SHARED_DATA_DIR) + "/iso230-2/";
  if (!std::filesystem::exists(dir)) GTEST_SKIP() << "no ../shared/data beside the checkout";
  const auto b02 = read_positioning_dat(dir + "b02_x_axis.dat");
  EXPECT_EQ(b02.unit, "mm");
  ASSERT_EQ(b02.targets.size(), 9u);
  EXPECT_EQ(b02.targets.front(), -20);
  EXPECT_EQ(b02.up[0].size(), 5u);
  EXPECT_EQ(b02.down[8].size(), 5u);
  EXPECT_DOUBLE_EQ(b02.up[0][0], -20.0492258741434944);  // REF_DATA_FWD[1,1]
  const auto e = evaluate_positioning(b02);
  EXPECT_EQ(e.runs, 5u);
  for (const char* f : {"x_axis_ild50.dat", "z_axis_ild2300.dat"})
    EXPECT_EQ(evaluate_positioning(read_positioning_dat(dir + f)).targets.size(), 5u) << f;
}

TEST(Iso230_2, CsvFormMatchesTheRunsItDescribes) {
  const std::string path = iso230_2_write_temp("mtcal-iso-good.csv",
                                      "# hand case\ntarget,run,direction,measured\n0,1,up,0.001\n0,2,+,0.003\n"
                                      "0,1,down,-0.001\n0,2,-,0.001\n10,1,up,10.004\n10,2,up,10.006\n"
                                      "10,1,down,10.002\n10,2,down,10.002\n");
  const auto r = read_positioning_csv(path, "um");
  EXPECT_EQ(r.unit, "um");
  const auto a = evaluate_positioning(r), b = evaluate_positioning(hand_case());
  EXPECT_DOUBLE_EQ(a.A, b.A);
  EXPECT_DOUBLE_EQ(a.R, b.R);
}

TEST(Iso230_2, BadInputsAreNamed) {
  PositioningRuns no_down = hand_case();
  no_down.down[0].clear();
  try {
    no_down.source = "f.csv";
    evaluate_positioning(no_down);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("down"), std::string::npos) << e.what();
  }
  PositioningRuns one_target = hand_case();
  one_target.targets.resize(1);
  one_target.up.resize(1);
  one_target.down.resize(1);
  EXPECT_THROW(evaluate_positioning(one_target), InputError);

  struct Iso2302Case {
    const char* text;
    int line;
    const char* field;
  };
  for (const Iso2302Case c : {Iso2302Case{"x,run,dir,measured\n", 1, ""}, Iso2302Case{"target,run,direction\n", 1, ""},
                       Iso2302Case{"target,run,direction,measured\n0,1,sideways,0\n", 2, "direction"},
                       Iso2302Case{"target,run,direction,measured\n0,1,up,abc\n", 2, "measured"},
                       Iso2302Case{"target,run,direction,measured\n0,1.5,up,0\n", 2, "run"},
                       Iso2302Case{"target,run,direction,measured\n0,1,up,0\n0,1,up,0\n", 3, "run"},
                       Iso2302Case{"target,run,direction,measured\n0,1,up\n", 2, ""}}) {
    SCOPED_TRACE(c.text);
    try {
      read_positioning_csv(iso230_2_write_temp("mtcal-iso-bad.csv", c.text), "mm");
      ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
      EXPECT_EQ(e.where().line, c.line) << e.what();
      EXPECT_EQ(e.where().field, c.field) << e.what();
    }
  }
  for (const char* text : {"TGT_DATA[1]=0\nREF_DATA_FWD[1,1]=x\n", "FOO=1\n", "TGT_DATA[1]=0\nTGT_DATA[1]=1\n",
                           "TGT_DATA[1,2]=0\n", "REF_DATA_FWD[1]=0\n", "TGT_DATA[1]=0\nA B=1\n", "TGT_DATA[1]\n",
                           "REF_DATA_FWD[2,1]=1\n", "TGT_DATA[1]=0\nREF_DATA_FWD[1,1]=0\nREF_DATA_FWD[1,1]=0\n"})
    EXPECT_THROW(read_positioning_dat(iso230_2_write_temp("mtcal-iso-bad.dat", text)), InputError) << text;
}
