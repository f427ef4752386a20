// Instrument files as published: tolerant ISO 230-2 tables and .dat logs, Renishaw .rtl/.rta
// exports (test files written from the published descriptions), unidirectional tests, n < 5,
// rotary targets one turn apart; every bad input located by file, line and field.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <fstream>
#include <sstream>

#include "mtcal/evaluation/iso230_2.hpp"
#include "mtcal/io/instruments/iso230_files.hpp"
#include "mtcal/io/instruments/laser_files.hpp"
#include "mtcal/report/evaluation.hpp"
#include "mtcal/util/errors.hpp"
#include "input_errors.hpp"

using namespace mtcal;

namespace {

std::string instrument_files_write_temp(const std::string& name, const std::string& text) {
  const auto p = std::filesystem::temp_directory_path() / name;
  std::ofstream(p, std::ios::binary) << text;
  return p.string();
}

using mtcal::testing::error_at;

// The hand case of test_iso230_2.cpp in um: targets 0 and 10 mm, deviations up {1, 3} {4, 6},
// down {-1, 1} {2, 2}. Hand figures (PRODUCT.md formulas): s = sqrt(2) for the spread pairs,
// B_i = 2 and 3, B = 3, B_mean = 2.5, E_up = 3, E_down = 2, E = 5, M = 2.5.
void expect_hand_case_um(const PositioningEvaluation& e) {
  const double s = std::sqrt(2.0);
  ASSERT_EQ(e.targets.size(), 2u);
  EXPECT_NEAR(e.targets[0].mean_up, 2, 1e-9);
  EXPECT_NEAR(e.targets[0].mean_down, 0, 1e-9);
  EXPECT_NEAR(e.targets[1].reversal, 3, 1e-9);
  EXPECT_NEAR(e.B, 3, 1e-9);
  EXPECT_NEAR(e.B_mean, 2.5, 1e-9);
  EXPECT_NEAR(e.E_up, 3, 1e-9);
  EXPECT_NEAR(e.E_down, 2, 1e-9);
  EXPECT_NEAR(e.E, 5, 1e-9);
  EXPECT_NEAR(e.M, 2.5, 1e-9);
  EXPECT_NEAR(e.R, 4 * s + 2, 1e-9);
  EXPECT_NEAR(e.A, (5 + 2 * s) - (0 - 2 * s), 1e-9);
}

const char* kRtl =
    "HEADER::\n"
    "Format: Renishaw ASCII (test file written from the published description)\n"
    "Type: Linear\n"
    "TARGET DATA::\n"
    "Target-count: 2\n"
    "Targets :\n"
    "0.000 10.000\n"
    "USER-TEXT::\n"
    "Machine: VMC 800\n"
    "Serial: SN-4711\n"
    "Date: 2026-11-20\n"
    "Axis: x\n"
    "RUNS::\n"
    "Run-count: 4\n"
    "DEVIATIONS::\n"
    "Run Target Data:\n"
    "1 1 1.0\n1 2 4.0\n"
    "2 1 -1.0\n2 2 2.0\n"
    "3 1 3.0\n3 2 6.0\n"
    "4 1 1.0\n4 2 2.0\n"
    "ENVIRONMENT::\n"
    "Air temperature: 20.3 C\n"
    "Air pressure: 1013.2 mbar\n"
    "Material temperature: 20.1 C\n"
    "EQUIPMENT::\n"
    "Laser: XL-80 s/n 123456\n";

}  // namespace

TEST(InstrumentFiles, DatKeepsUnknownKeysAsMetadataAndEvaluatesAsWithout) {
  const std::string core =
      "UNIT=mm\nTGT_DATA[1]=0\nTGT_DATA[2]=10\nREF_DATA_FWD[1,1]=0.001\nREF_DATA_FWD[1,2]=0.003\n"
      "REF_DATA_FWD[2,1]=10.004\nREF_DATA_FWD[2,2]=10.006\nREF_DATA_BWD[1,1]=-0.001\nREF_DATA_BWD[1,2]=0.001\n"
      "REF_DATA_BWD[2,1]=10.002\nREF_DATA_BWD[2,2]=10.002\n";
  const std::string extra =
      "REF_PV=IOC:m1-Enc\nTEST_PV=IOC:m1.RBV\nTGT_SET_PV=IOC:m1.VAL\nDEC=3\nTEST_DATA[1,1]=0.0012\nTEST_DATA[1,2]=0."
      "0031\n";
  const auto plain = read_positioning_dat(instrument_files_write_temp("mtcal-inst-plain.dat", core));
  const auto tagged = read_positioning_dat(instrument_files_write_temp("mtcal-inst-tagged.dat", extra + core));
  EXPECT_TRUE(plain.warnings.empty());
  ASSERT_EQ(tagged.metadata.size(), 6u);
  EXPECT_EQ(tagged.metadata[0].first, "REF_PV");
  EXPECT_EQ(tagged.metadata[0].second, "IOC:m1-Enc");
  EXPECT_EQ(tagged.metadata[4].first, "TEST_DATA[1,1]");
  ASSERT_EQ(tagged.warnings.size(), 5u);  // one per key name: REF_PV TEST_PV TGT_SET_PV DEC TEST_DATA
  EXPECT_NE(tagged.warnings[4].find("TEST_DATA (2 lines)"), std::string::npos) << tagged.warnings[4];
  const auto a = evaluate_positioning(plain), b = evaluate_positioning(tagged);
  EXPECT_EQ(a.A, b.A);
  EXPECT_EQ(a.R, b.R);
  EXPECT_EQ(a.E, b.E);
}

TEST(InstrumentFiles, RealDatFilesWithOtherToolsKeysEvaluateExactlyAsTheFilesThemselves) {
  const std::string dir = std::string(MTCAL_SHARED_DATA_DIR) + "/iso230-2/";
  if (!std::filesystem::exists(dir)) GTEST_SKIP() << "no ../shared/data beside the checkout";
  for (const char* f : {"b02_x_axis.dat", "x_axis_ild50.dat", "z_axis_ild2300.dat"}) {
    SCOPED_TRACE(f);
    std::ifstream in(dir + f);
    std::stringstream text;
    text << in.rdbuf();
    const auto as_published = read_positioning_dat(dir + f);
    EXPECT_TRUE(as_published.warnings.empty());
    EXPECT_TRUE(as_published.metadata.empty());
    const auto with_keys =
        read_positioning_dat(instrument_files_write_temp("mtcal-inst-real.dat", "REF_PV=X\nDEC=4\n" + text.str() + "TEST_PV=Y\n"));
    const auto a = evaluate_positioning(as_published), b = evaluate_positioning(with_keys);
    EXPECT_EQ(a.runs, 5u);
    EXPECT_TRUE(a.notes.empty());
    for (auto [x, y] : {std::pair{a.A, b.A}, {a.B, b.B}, {a.R, b.R}, {a.E, b.E}, {a.M, b.M}}) EXPECT_EQ(x, y);
  }
}

TEST(InstrumentFiles, TablesWithSemicolonsDecimalCommasAndOtherDirectionWords) {
  // ';' and decimal comma, FWD/BWD, a column the evaluation does not use.
  const auto semi = parse_positioning_csv(
      "Target [mm];Run;Direction;Deviation [um];Temperature\n0;1;FWD;1,0;20,1\n0;2;fwd;3,0;20,1\n"
      "0;1;BWD;\xE2\x88\x92"
      "1,0;20,2\n0;2;bwd;1;20,2\n10;1;FWD;4;20,1\n10;2;FWD;6;20,1\n10;1;BWD;2;20,2\n"
      "10;2;BWD;2;20,2\n",
      "semi.csv", "mm");
  EXPECT_TRUE(semi.deviations);
  EXPECT_EQ(semi.unit, "um");
  EXPECT_EQ(semi.target_unit, "mm");
  ASSERT_EQ(semi.warnings.size(), 1u);
  EXPECT_NE(semi.warnings[0].find("Temperature"), std::string::npos);
  expect_hand_case_um(evaluate_positioning(semi));
  // Tab-separated, arrows, no run column (runs numbered in file order), measured positions in um.
  const auto tab = parse_positioning_csv(
      "position\tdir\tactual\n0\t\xE2\x86\x91\t1\n0\t\xE2\x86\x91\t3\n0\t\xE2\x86\x93\t-1\n0\t\xE2\x86\x93\t1\n"
      "10000\t\xE2\x86\x91\t10004\n10000\t\xE2\x86\x91\t10006\n10000\t\xE2\x86\x93\t10002\n10000\t\xE2\x86\x93\t10002"
      "\n",
      "tab.tsv", "um");
  EXPECT_FALSE(tab.deviations);
  expect_hand_case_um(evaluate_positioning(tab));
  // ',' with +/- and up/down mixed, quoted header cells.
  const auto comma = parse_positioning_csv(
      "\"nominal\",\"cycle\",\"direction\",\"error\"\n0,1,+,1\n0,2,up,3\n0,1,-,-1\n0,2,down,1\n10,1,positive,4\n"
      "10,2,pos,6\n10,1,negative,2\n10,2,neg,2\n",
      "comma.csv", "um", "mm");
  expect_hand_case_um(evaluate_positioning(comma));
  // A spreadsheet's "sep=" line names the separator (here against a header that holds a ';').
  const auto sep = parse_positioning_csv(
      "sep=,\ntarget,direction,deviation,comment;remark\n0,up,1,a;b\n0,up,3,\n0,down,-1,\n0,down,1,\n10,up,4,\n"
      "10,up,6,\n10,down,2,\n10,down,2,\n",
      "sep.csv", "um", "mm");
  ASSERT_EQ(sep.warnings.size(), 1u);
  EXPECT_NE(sep.warnings[0].find("comment;remark"), std::string::npos);
  expect_hand_case_um(evaluate_positioning(sep));
}

TEST(InstrumentFiles, UnidirectionalTestsGiveOnlyTheirQuantities) {
  const auto r = parse_positioning_csv("target,run,deviation\n0,1,1\n0,2,3\n10,1,4\n10,2,6\n", "uni.csv", "um", "mm");
  ASSERT_EQ(r.warnings.size(), 1u);  // no direction column
  const auto e = evaluate_positioning(r);
  EXPECT_EQ(e.directions, TestDirections::UpOnly);
  const double s = std::sqrt(2.0);
  EXPECT_NEAR(e.E_up, 3, 1e-12);  // max x̄↑ - min x̄↑ = 5 - 2
  EXPECT_NEAR(e.R_up, 4 * s, 1e-12);
  EXPECT_NEAR(e.A_up, (5 + 2 * s) - (2 - 2 * s), 1e-12);
  for (double v : {e.A, e.B, e.B_mean, e.R, e.E, e.M, e.A_down, e.R_down, e.E_down}) EXPECT_TRUE(std::isnan(v)) << v;
  ASSERT_FALSE(e.notes.empty());
  EXPECT_NE(e.notes[0].find("unidirectional"), std::string::npos);
  // Down only.
  const auto d = evaluate_positioning(
      parse_positioning_csv("target,dir,deviation\n0,down,1\n0,down,3\n10,down,4\n10,down,6\n", "d.csv", "um"));
  EXPECT_EQ(d.directions, TestDirections::DownOnly);
  EXPECT_NEAR(d.E_down, 3, 1e-12);
  EXPECT_TRUE(std::isnan(d.E_up));
}

TEST(InstrumentFiles, OneRunEvaluatesWhatIsDefinedAndSaysWhatIsNot) {
  const auto e =
      evaluate_positioning(parse_positioning_csv("target,direction,deviation\n0,up,1\n0,down,-1\n10,up,4\n10,down,2\n",
                                                 "n1.csv", "um", "mm"));
  EXPECT_EQ(e.runs, 1u);
  EXPECT_NEAR(e.B, 2, 1e-12);  // B_i = 2 and 2
  EXPECT_NEAR(e.B_mean, 2, 1e-12);
  EXPECT_NEAR(e.E, 5, 1e-12);  // max(4) - min(-1)
  EXPECT_NEAR(e.M, 3, 1e-12);  // means 0 and 3
  for (double v : {e.A, e.A_up, e.A_down, e.R, e.R_up, e.R_down}) EXPECT_TRUE(std::isnan(v));
  ASSERT_EQ(e.notes.size(), 2u);
  EXPECT_NE(e.notes[0].find("R and accuracy A are not defined"), std::string::npos);
  EXPECT_NE(e.notes[1].find("5 runs"), std::string::npos);
  // Three runs: everything defined, the note on ISO 230-2's five runs stays.
  const auto three = evaluate_positioning(
      parse_positioning_csv("target,direction,deviation\n0,up,1\n0,up,2\n0,up,3\n0,down,0\n0,down,0\n0,down,0\n"
                            "10,up,1\n10,up,2\n10,up,3\n10,down,0\n10,down,0\n10,down,0\n",
                            "n3.csv", "um", "mm"));
  EXPECT_NEAR(three.R_up, 4.0, 1e-12);  // s = 1
  ASSERT_EQ(three.notes.size(), 1u);
  EXPECT_NE(three.notes[0].find("has 3"), std::string::npos);
}

TEST(InstrumentFiles, RotaryTargetsOneTurnApartArePooledWhenAsked) {
  // A 0..360 deg test: 0 and 360 are the same position of the table; so are -360 and 0.
  PositioningRuns r;
  r.unit = "deg";
  r.targets = {-360, 0, 180, 360};
  r.up = {{-359.999, -360.001}, {0.002, 0.004}, {180.001, 180.003}, {360.006, 360.008}};
  r.down = {{-360.000, -360.002}, {0.000, 0.002}, {180.000, 180.000}, {360.004, 360.004}};
  const auto merged = merge_wrapped_targets(r, 360);
  ASSERT_EQ(merged.targets.size(), 2u);
  EXPECT_EQ(merged.targets[0], 0);  // the representative nearest zero
  EXPECT_EQ(merged.targets[1], 180);
  ASSERT_EQ(merged.up[0].size(), 6u);
  EXPECT_TRUE(merged.deviations);
  ASSERT_EQ(merged.warnings.size(), 1u);
  EXPECT_NE(merged.warnings[0].find("-360, 360 and 0"), std::string::npos) << merged.warnings[0];
  const auto e = evaluate_positioning(merged);
  // Target 0: up deviations {0.001, -0.001, 0.002, 0.004, 0.006, 0.008}: mean 0.0033333.
  EXPECT_NEAR(e.targets[0].mean_up, 0.02 / 6, 1e-9);
  EXPECT_EQ(e.targets[0].n_up, 6u);
  EXPECT_EQ(e.runs, 2u);
  EXPECT_EQ(e.notes.size(), 2u);  // fewer than 5 runs; run counts differ between targets
}

TEST(InstrumentFiles, RenishawLinearExportReadsRunsMetadataAndDirections) {
  const auto f = parse_laser_file(kRtl, "x.rtl", false);
  EXPECT_EQ(f.kind, "linear");
  EXPECT_EQ(f.axis, "X");
  EXPECT_TRUE(f.runs.warnings.empty());
  EXPECT_EQ(f.runs.unit, "um");
  EXPECT_EQ(f.runs.target_unit, "mm");
  // Odd runs go in the order of the targets (up here), even runs against it.
  ASSERT_EQ(f.runs.up.size(), 2u);
  EXPECT_EQ(f.runs.up[1], (std::vector<double>{4, 6}));
  EXPECT_EQ(f.runs.down[0], (std::vector<double>{-1, 1}));
  auto meta = [&](const std::string& k) {
    for (const auto& [key, value] : f.runs.metadata)
      if (key == k) return value;
    return std::string("(none)");
  };
  EXPECT_EQ(meta("USER-TEXT/Machine"), "VMC 800");
  EXPECT_EQ(meta("USER-TEXT/Serial"), "SN-4711");
  EXPECT_EQ(meta("USER-TEXT/Date"), "2026-11-20");
  EXPECT_EQ(meta("ENVIRONMENT/Air temperature"), "20.3 C");
  EXPECT_EQ(meta("EQUIPMENT/Laser"), "XL-80 s/n 123456");
  expect_hand_case_um(evaluate_positioning(f.runs));
  // The same through the file readers (extension decides).
  const auto path = instrument_files_write_temp("mtcal-inst.rtl", kRtl);
  EXPECT_TRUE(looks_like_laser(path));
  expect_hand_case_um(evaluate_positioning(read_positioning_file(path, "auto", "mm")));
  // Without the extension the HEADER:: line decides.
  const auto txt = instrument_files_write_temp("mtcal-inst-laser.txt", kRtl);
  const auto by_content = read_positioning_file(txt, "auto", "mm");
  EXPECT_TRUE(by_content.deviations);
  EXPECT_EQ(by_content.unit, "um");
}

TEST(InstrumentFiles, RenishawTargetsListedDownwardsAndRotaryExports) {
  // Targets listed from 10 to 0: run 1 moves down.
  std::string text = kRtl;
  text.replace(text.find("0.000 10.000"), 12, "10.000 0.000");
  const auto f = parse_laser_file(text, "down.rtl", false);
  EXPECT_EQ(f.runs.targets, (std::vector<double>{0, 10}));
  // run 1 at target 1 (10 mm) = 1.0 is a down run of target 10.
  EXPECT_EQ(f.runs.down[1][0], 1.0);
  const std::string rta =
      "HEADER::\nTARGET DATA::\nTarget-count: 3\nTargets :\n0 180 360\nUSER-TEXT::\nAxis: C\nRUNS::\nRun-count: 2\n"
      "DEVIATIONS::\nRun Target Data:\n1 1 0.0\n1 2 2.5\n1 3 1.0\n2 1 -1.0\n2 2 1.5\n2 3 0.0\n";
  const auto c = parse_laser_file(rta, "c.rta", true);
  EXPECT_EQ(c.kind, "rotary");
  EXPECT_EQ(c.runs.unit, "arcsec");
  EXPECT_EQ(c.runs.target_unit, "deg");
  const auto merged = merge_wrapped_targets(c.runs, 360);
  ASSERT_EQ(merged.targets.size(), 2u);
  EXPECT_EQ(merged.up[0], (std::vector<double>{0.0, 1.0}));
}

TEST(InstrumentFiles, RenishawBadInputsAreLocated) {
  struct InstrumentFilesCase {
    std::string from, to;
    int line;
    const char* field;
  };
  const std::vector<InstrumentFilesCase> cases = {
      {"Target-count: 2\n", "", 0, "Target-count"},
      {"Run-count: 4\n", "", 0, "Run-count"},
      {"Target-count: 2\n", "Target-count: 3\n", 6, "Targets"},
      {"4 2 2.0\n", "", 23, "Run Target Data"},  // run 4 lacks target 2 (reported at run 4's last row)
      {"3 1 3.0\n", "3 1 three\n", 21, "Deviation"},
      {"3 1 3.0\n", "3 1 3.0 arcsec\n", 21, "Run Target Data"},  // 4 cells
      {"3 1 3.0\n", "3 1 3.0arcsec\n", 21, "Deviation"},         // mixed units
      {"0.000 10.000\n", "0.000 10.000deg\n", 7, "Targets"},     // mixed units
      {"3 1 3.0\n", "5 1 3.0\n", 21, "Run"},
      {"3 1 3.0\n", "3 3 3.0\n", 21, "Target"},
      {"3 1 3.0\n", "1 1 3.0\n", 21, "Run Target Data"},  // run 1 target 1 twice
      {"Run-count: 4\n", "Run-count: four\n", 14, "Run-count"},
      {"Type: Linear\n", "Type: Rotary\n", 0, "Target units"},  // a rotary test with mm targets
      {"HEADER::\n", "", 1, ""},                                // lines before any section
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.from + " -> " + c.to);
    std::string text = kRtl;
    const auto at = text.find(c.from);
    ASSERT_NE(at, std::string::npos);
    text.replace(at, c.from.size(), c.to);
    if (c.field == std::string("Target units")) text.insert(text.find("TARGET DATA::"), "Target units: mm\n");
    const auto w = error_at([&] { parse_laser_file(text, "bad.rtl", false); });
    EXPECT_EQ(w.file, "bad.rtl");
    if (c.field != std::string("Target units")) {
      EXPECT_EQ(w.line, c.line);
    }
    EXPECT_EQ(w.field, c.field);
  }
  // Unknown section and key: kept with a warning, not an error.
  std::string text = kRtl;
  text += "CALIBRATION::\nDue: 2027-01\n";
  text.insert(text.find("Run-count"), "Sample-rate: 10\n");
  const auto f = parse_laser_file(text, "more.rtl", false);
  ASSERT_EQ(f.runs.warnings.size(), 2u);
  EXPECT_NE(f.runs.warnings[0].find("Sample-rate"), std::string::npos);
  EXPECT_NE(f.runs.warnings[1].find("CALIBRATION"), std::string::npos);
  EXPECT_EQ(f.runs.metadata.back().first, "CALIBRATION/Due");
}

TEST(InstrumentFiles, TableBadInputsAreLocated) {
  struct InstrumentFilesCase {
    const char* text;
    int line;
    const char* field;
  };
  for (const InstrumentFilesCase c :
       {InstrumentFilesCase{"target;run;direction;deviation [um]\n0;1;sideways;1\n", 2, "direction"},
        InstrumentFilesCase{"target;run;direction;deviation\n0;1;up;1,2,3\n", 2, "deviation"},
        InstrumentFilesCase{"target [mm],measured [um]\n0,1\n", 1, "target [mm]"},                     // mixed units
        InstrumentFilesCase{"target,measured,deviation\n", 1, ""}, InstrumentFilesCase{"target,dir,error\n", 1, ""},  // no rows
        InstrumentFilesCase{"target,position,error\n0,0,1\n", 1, "position"}, InstrumentFilesCase{"target,dir,error\n0,up,1\n0,up\n", 3, ""}}) {
    SCOPED_TRACE(c.text);
    const auto w = error_at([&] { parse_positioning_csv(c.text, "t.csv", "um"); });
    EXPECT_EQ(w.line, c.line);
    EXPECT_EQ(w.field, c.field);
  }
}

TEST(InstrumentFiles, ResultsAreShownInMicrometresWithThePrecisionOfTheData) {
  // Values in mm with 3 decimals (1 um resolution), s = sqrt(2) um: shown in um with 1 decimal.
  PositioningRuns r;
  r.targets = {0, 10};
  r.up = {{0.001, 0.003}, {10.004, 10.006}};
  r.down = {{-0.001, 0.001}, {10.002, 10.002}};
  const auto e = evaluate_positioning(r);
  const auto d = positioning_display(r, e);
  EXPECT_EQ(d.unit, "um");
  EXPECT_EQ(d.decimals, 1);
  EXPECT_EQ(d.format(e.B_mean), "2.5");
  EXPECT_EQ(d.format(std::nan("")), "n/a");
  const std::string text = positioning_text(r, e);
  EXPECT_NE(text.find("B 3.0 (mean 2.5)"), std::string::npos) << text;
  // 16-digit values (the real logs) with a 1.5 um spread: two significant digits of s, not 16.
  PositioningRuns fine = r;
  fine.up = {{0.0012345678901234, 0.0031234567890123}, {10.0041234567890123, 10.0061234567890123}};
  const auto f = positioning_display(fine, evaluate_positioning(fine));
  EXPECT_EQ(f.decimals, 1);
  // A file in arcsec keeps its unit.
  PositioningRuns as = r;
  as.unit = "arcsec";
  as.deviations = true;
  as.target_unit = "deg";
  as.up = {{1.25, 3.5}, {4, 6}};
  as.down = {{-1, 1}, {2, 2}};
  const auto a = positioning_display(as, evaluate_positioning(as));
  EXPECT_EQ(a.unit, "arcsec");
  // 1.25 needs 2 decimals (3 for the means), but the median s is 1.41 arcsec: two significant
  // digits of it are 1 decimal.
  EXPECT_EQ(a.decimals, 1);
}

TEST(InstrumentFiles, LaserHeaderFillsTheReportMetadata) {
  const std::string text =
      "HEADER::\nType: Linear\nDate: 2026-01-02\nTARGET DATA::\nTarget-count: 2\nTargets : 0 100\n"
      "USER-TEXT::\nmachine: HU40T\nDate: 2026-11-20\nCustomer: ACME\nSerial number: 99\nOperator:\nAxis: y\n"
      "a free line\nRUNS::\nRun-count: 2\nDEVIATIONS::\nRun Target Data:\n1 1 0\n1 2 1\n2 1 0\n2 2 1\n"
      "ENVIRONMENT::\nAir Temperature: 20.4 C\nMachine temperature: 20.9 C\nPressure: 1013 mbar\n"
      "EQUIPMENT::\nLaser: XL-80\nSerial: L123\nCalibration date: 2026-03-01\nCompensator: XC-80\n"
      "Air sensor: S1\n";
  const LaserFile f = parse_laser_file(text, "t.rtl", false);
  const ReportMetadata m = laser_report_metadata(f.runs);
  auto v = [&](const char* key) { return m.get(key) ? *m.get(key) : std::string("(none)"); };
  EXPECT_EQ(v("machine"), "HU40T");    // keys without regard to case
  EXPECT_EQ(v("date"), "2026-01-02");  // the first Date (HEADER before USER-TEXT)
  EXPECT_EQ(v("owner"), "ACME");       // Customer
  EXPECT_EQ(v("serial"), "99");        // machine serial from USER-TEXT
  EXPECT_EQ(v("operator"), "(none)");  // empty value skipped
  EXPECT_EQ(v("axis"), "y");           // as written
  EXPECT_EQ(v("temperature_air"), "20.4 C");
  EXPECT_EQ(v("temperature_machine"), "20.9 C");
  EXPECT_EQ(v("instrument_serial"), "L123");  // EQUIPMENT Serial is the instrument's
  EXPECT_EQ(v("calibration_date"), "2026-03-01");
  EXPECT_EQ(v("instrument"), "XL-80; Compensator XC-80; Air sensor S1");
  EXPECT_EQ(v("humidity"), "(none)");  // Pressure has no field: stays in the file's own table only

  // What the user typed wins, field by field (fill_missing_from).
  ReportMetadata user;
  user.set("machine", "typed");
  user.fill_missing_from(m);
  EXPECT_EQ(*user.get("machine"), "typed");
  EXPECT_EQ(*user.get("date"), "2026-01-02");

  // A .dat or CSV file's keys have no section: nothing is mapped.
  PositioningRuns dat;
  dat.metadata = {{"UNIT", "mm"}, {"CYCLES", "5"}};
  EXPECT_TRUE(laser_report_metadata(dat).empty());
}
