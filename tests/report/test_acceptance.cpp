// Acceptance reports: metadata record and file, tolerance file and verdicts, the ISO 230-2 report
// in µm with its warnings. Expected values are hand calculations on small data.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "mtcal/evaluation/iso230_2.hpp"
#include "mtcal/evaluation/tolerance.hpp"
#include "mtcal/io/instruments/acceptance_files.hpp"
#include "mtcal/io/json/acceptance_json.hpp"
#include "mtcal/report/evaluation.hpp"
#include "mtcal/evaluation/metadata.hpp"
#include "mtcal/report/report.hpp"
#include "mtcal/util/errors.hpp"

using namespace mtcal;

namespace {
std::string acceptance_slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}
template <class F>
std::string acceptance_error_of(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}
}  // namespace

TEST(Metadata, KeepsFieldOrderRefusesUnknownKeysAndEmptyValues) {
  ReportMetadata m;
  m.set("date", "2026-11-24");
  m.set("machine", "HU40T");
  m.set("serial", "4711");
  m.set("machine", "HU40T-2");  // replaces
  ASSERT_EQ(m.entries().size(), 3u);
  EXPECT_EQ(m.entries()[0].first, "machine");  // metadata_fields() order, not insertion order
  EXPECT_EQ(m.entries()[0].second, "HU40T-2");
  EXPECT_EQ(m.entries()[1].first, "serial");
  EXPECT_EQ(m.entries()[2].first, "date");
  EXPECT_NE(acceptance_error_of([&] { m.set("sreial", "1", "--meta"); }).find("unknown metadata field 'sreial'"),
            std::string::npos);
  EXPECT_NE(acceptance_error_of([&] { m.set("owner", "  ", "f.yaml", 3); }).find("f.yaml:3"), std::string::npos);
  // A laser file's header fills only what the user did not type.
  ReportMetadata from_file;
  from_file.set("machine", "from file");
  from_file.set("temperature_air", "20.1 °C");
  m.fill_missing_from(from_file);
  EXPECT_EQ(*m.get("machine"), "HU40T-2");
  EXPECT_EQ(*m.get("temperature_air"), "20.1 °C");
  EXPECT_TRUE(m.has_temperature());
}

TEST(Metadata, NamesTheFieldsAnAcceptanceTestLacks) {
  ReportMetadata m;
  EXPECT_TRUE(missing_acceptance_fields(m, AcceptanceTest::None).empty());
  EXPECT_EQ(missing_acceptance_fields(m, AcceptanceTest::Iso230_2).size(), 5u);  // date machine temperature feed dwell
  m.set("date", "2026-11-24");
  m.set("machine", "M");
  m.set("temperature_machine", "20.3");
  m.set("feed", "1000 mm/min");
  m.set("dwell", "2 s");
  EXPECT_TRUE(missing_acceptance_fields(m, AcceptanceTest::Iso230_2).empty());
  // ISO 230-4 clause 6 asks for start, data capture, compensation and centre besides.
  EXPECT_EQ(missing_acceptance_fields(m, AcceptanceTest::Iso230_4).size(), 4u);
}

TEST(MetadataFile, ReadsKnownKeysAndLocatesErrors) {
  const ReportMetadata m = parse_report_metadata("machine: HU40T\nserial: 4711\ndate: 2026-11-24\n", "m.yaml");
  EXPECT_EQ(*m.get("serial"), "4711");
  EXPECT_EQ(to_json(m).dump(), R"({"machine":"HU40T","serial":"4711","date":"2026-11-24"})");
  EXPECT_NE(acceptance_error_of([] { parse_report_metadata("machine: M\nopertor: A\n", "m.yaml"); }).find("m.yaml:2"),
            std::string::npos);
  EXPECT_NE(acceptance_error_of([] { parse_report_metadata("machine: {a: 1}\n", "m.yaml"); }).find("expected text"),
            std::string::npos);
  EXPECT_NE(acceptance_error_of([] { parse_report_metadata("", "m.yaml"); }).find("found nothing"), std::string::npos);
  EXPECT_NE(acceptance_error_of([] { parse_report_metadata("machine: [\n", "m.yaml"); }).find("not valid YAML"),
            std::string::npos);
}

TEST(ToleranceFile, ConvertsToMicrometresAndPicksTheAxis) {
  const ToleranceFile f = parse_tolerance_file(
      "unit: mm\niso230-2:\n  X: {A: 0.016, R: 0.006}\n  any: {A: 0.025}\niso230-4: {G: 0.015}\nvolumetric: {VA: "
      "0.03}\n",
      "t.yaml");
  const Tolerances x = f.iso230_2_for("X");
  ASSERT_EQ(x.limits.size(), 2u);
  EXPECT_DOUBLE_EQ(x.limits[0].second, 16.0);
  EXPECT_DOUBLE_EQ(x.limits[1].second, 6.0);
  EXPECT_DOUBLE_EQ(f.iso230_2_for("Y").limits.at(0).second, 25.0);  // "any"
  EXPECT_DOUBLE_EQ(f.iso230_4.limits.at(0).second, 15.0);
  EXPECT_DOUBLE_EQ(f.volumetric.limits.at(0).second, 30.0);
  EXPECT_DOUBLE_EQ(parse_tolerance_file("iso230-4: {F: 7}\n", "t.yaml").iso230_4.limits.at(0).second,
                   7.0);  // µm default
  EXPECT_NE(acceptance_error_of([] { parse_tolerance_file("iso230-2:\n  X: {Q: 3}\n", "t.yaml"); }).find("t.yaml:2"),
            std::string::npos);
  EXPECT_NE(acceptance_error_of([] { parse_tolerance_file("iso230-4: {G: -1}\n", "t.yaml"); }).find(">= 0"), std::string::npos);
  EXPECT_NE(acceptance_error_of([] { parse_tolerance_file("unit: inch\n", "t.yaml"); }).find("expected um or mm"),
            std::string::npos);
  EXPECT_NE(acceptance_error_of([] { parse_tolerance_file("iso230-3: {}\n", "t.yaml"); }).find("unknown key 'iso230-3'"),
            std::string::npos);
}

TEST(Tolerance, PassesAtOrBelowTheLimit) {
  Tolerances t;
  t.set("A", 8);
  t.set("R", 7.66);
  t.set("A", 11);  // replaces
  const auto v = check_tolerances({{"A", 10.66}, {"R", 7.66}, {"B", 3}}, t);
  ASSERT_EQ(v.checks.size(), 2u);
  EXPECT_TRUE(v.checks[0].pass);  // 10.66 <= 11
  EXPECT_TRUE(v.checks[1].pass);  // equal passes
  EXPECT_TRUE(v.pass());
  t.set("B", 2.5);
  EXPECT_FALSE(check_tolerances({{"A", 10.66}, {"R", 7.66}, {"B", 3}}, t).pass());
  EXPECT_FALSE(ToleranceVerdict{}.pass());  // nothing checked is no pass
  Tolerances z;
  z.set("Z", 1);
  EXPECT_NE(acceptance_error_of([&] { check_tolerances({{"A", 1}}, z, "--tolerance"); }).find("it gives A"), std::string::npos);
  EXPECT_EQ(micrometres_per("mm"), 1000.0);
  EXPECT_EQ(micrometres_per("in"), 25400.0);
  EXPECT_FALSE(micrometres_per("furlong"));
}

TEST(AcceptanceReport, ShowsMetadataVerdictAndIso230_2InMicrometres) {
  // Three targets, two runs per direction (mm); hand calculation: at target 10 the up runs
  // deviate 4 and 6 µm (x̄↑ = 5, s↑ = 1.414), down 2 and 2 (x̄↓ = 2, s↓ = 0); A = max(x̄ + 2s) −
  // min(x̄ − 2s) = (5 + 2.828) − (0 − 2.828) = 10.66 µm over the targets below.
  const auto dir = std::filesystem::temp_directory_path();
  PositioningRuns runs;
  runs.source = (dir / "mtcal-acceptance-test.csv").string();
  std::ofstream(runs.source) << "(the report hashes its input)\n";
  runs.targets = {0, 10, 20};
  runs.up = {{0.001, 0.003}, {10.004, 10.006}, {20.002, 20.003}};
  runs.down = {{-0.001, 0.001}, {10.002, 10.002}, {19.999, 20.000}};
  const PositioningEvaluation e = evaluate_positioning(runs);
  EXPECT_NEAR(e.A * 1000, 10.657, 1e-3);
  ReportMetadata m;
  m.set("machine", "<HU40T>");
  m.set("serial", "4711");
  set_session_metadata(m);
  Tolerances t;
  t.set("A", 8);
  const auto v = check_tolerances({{"A", e.A * 1000}}, t);
  const std::string path = (dir / "mtcal-acceptance-test.html").string();
  write_positioning_report(path, "mtcal iso230-2 p.csv", runs, e, v);
  set_session_metadata({});
  const std::string html = acceptance_slurp(path);
  std::remove(path.c_str());
  std::remove(runs.source.c_str());
  EXPECT_NE(html.find("<div class=\"verdict fail\">FAIL"), std::string::npos);
  EXPECT_NE(html.find("<td>A</td><td>10.66</td><td>8.00</td><td>FAIL</td>"), std::string::npos);
  EXPECT_NE(html.find("<th>Serial number</th><td>4711</td>"), std::string::npos);
  EXPECT_NE(html.find("&lt;HU40T&gt;"), std::string::npos);
  EXPECT_NE(html.find("asks for 5 runs"), std::string::npos);       // 2 runs
  EXPECT_NE(html.find("no test date (date)"), std::string::npos);   // condition missing
  EXPECT_NE(html.find("deviation (um)"), std::string::npos);        // the plot in micrometres, not mm
  EXPECT_NE(html.find("\"text\":\"A 10.66\""), std::string::npos);  // A marked on the plot
}

TEST(AcceptanceReport, Iso230_2TablePerTargetInTheStandardsLayout) {
  // The runs of the test above (µm): target 0 up 1, 3 / down -1, 1; target 10 up 4, 6 / down 2, 2;
  // target 20 up 2, 3 / down -1, 0. By hand: x̄↑ = 2, 5, 2.5; x̄↓ = 0, 2, -0.5; s↑ = 1.414, 1.414,
  // 0.707; s↓ = 1.414, 0, 0.707; B_i = 2, 3, 3; R↑ = 4 s↑ = 5.657, 5.657, 2.828; R_i = max(2s↑ +
  // 2s↓ + |B_i|, R↑, R↓) = 7.657, 5.828, 5.828; x̄_i = 1, 3.5, 1. Shown in um with one decimal
  // (integer µm inputs: one more; median s 1.414: two significant digits).
  PositioningRuns runs;
  runs.targets = {0, 10, 20};
  runs.up = {{0.001, 0.003}, {10.004, 10.006}, {20.002, 20.003}};
  runs.down = {{-0.001, 0.001}, {10.002, 10.002}, {19.999, 20.000}};
  const PositioningEvaluation e = evaluate_positioning(runs);
  const PositioningDisplay shown = positioning_display(runs, e);
  ASSERT_EQ(shown.unit, "um");
  ASSERT_EQ(shown.decimals, 1);
  const auto blocks = positioning_target_table(runs, e, shown);
  ASSERT_EQ(blocks.size(), 1u);
  const auto& b = blocks[0];
  EXPECT_EQ(b.columns, (std::vector<std::string>{"target i", "1", "2", "3"}));
  auto row = [&](const std::string& label) {
    for (const auto& r : b.rows)
      if (r.at(0) == label) return std::vector<std::string>(r.begin() + 1, r.end());
    ADD_FAILURE() << "no row " << label;
    return std::vector<std::string>{};
  };
  using V = std::vector<std::string>;
  EXPECT_EQ(row("target position P_i (mm)"), (V{"0", "10", "20"}));
  EXPECT_EQ(row("x_i1↑ (run 1 ↑)"), (V{"1.0", "4.0", "2.0"}));
  EXPECT_EQ(row("x_i2↓ (run 2 ↓)"), (V{"1.0", "2.0", "0.0"}));
  EXPECT_EQ(row("x̄_i↑ mean deviation ↑"), (V{"2.0", "5.0", "2.5"}));
  EXPECT_EQ(row("x̄_i↓ mean deviation ↓"), (V{"0.0", "2.0", "-0.5"}));
  EXPECT_EQ(row("s_i↑ standard uncertainty ↑"), (V{"1.4", "1.4", "0.7"}));
  EXPECT_EQ(row("s_i↓ standard uncertainty ↓"), (V{"1.4", "0.0", "0.7"}));
  EXPECT_EQ(row("2s_i↑"), (V{"2.8", "2.8", "1.4"}));
  EXPECT_EQ(row("x̄_i↑ + 2s_i↑"), (V{"4.8", "7.8", "3.9"}));
  EXPECT_EQ(row("x̄_i↓ − 2s_i↓"), (V{"-2.8", "2.0", "-1.9"}));
  EXPECT_EQ(row("R_i↑ = 4s_i↑ repeatability ↑"), (V{"5.7", "5.7", "2.8"}));
  EXPECT_EQ(row("R_i↓ = 4s_i↓ repeatability ↓"), (V{"5.7", "0.0", "2.8"}));
  EXPECT_EQ(row("B_i = x̄_i↑ − x̄_i↓ reversal"), (V{"2.0", "3.0", "3.0"}));
  EXPECT_EQ(row("R_i bidirectional repeatability"), (V{"7.7", "5.8", "5.8"}));
  EXPECT_EQ(row("x̄_i = (x̄_i↑ + x̄_i↓)/2"), (V{"1.0", "3.5", "1.0"}));
  // The target row, 2 run rows per direction, 15 statistics rows.
  EXPECT_EQ(b.rows.size(), 1u + 4u + 15u);

  // A long axis is split so that the table fits a page: at most max_columns targets a block.
  const auto split = positioning_target_table(runs, e, shown, 2);
  ASSERT_EQ(split.size(), 2u);
  EXPECT_EQ(split[1].columns, (std::vector<std::string>{"target i", "3"}));
  EXPECT_NE(split[1].caption.find("targets 3 to 3 of 3"), std::string::npos);

  // A unidirectional test (up only) has no ↓ rows, no B_i, R_i or x̄_i; a target with a run
  // fewer (the tolerant reader) shows "-" there.
  PositioningRuns one = runs;
  one.down = {{}, {}, {}};
  one.up[1].pop_back();
  const PositioningEvaluation e1 = evaluate_positioning(one);
  const auto t1 = positioning_target_table(one, e1, positioning_display(one, e1));
  for (const auto& r : t1[0].rows) {
    EXPECT_EQ(r[0].find("↓"), std::string::npos) << r[0];
    EXPECT_EQ(r[0].find("B_i"), std::string::npos) << r[0];
  }
  bool dash = false;
  for (const auto& r : t1[0].rows)
    if (r[0] == "x_i2↑ (run 2 ↑)") dash = r.at(2) == "-";
  EXPECT_TRUE(dash);

  // In the HTML report: the table, row by row, and the axis results below it.
  const auto dir = std::filesystem::temp_directory_path();
  runs.source = (dir / "mtcal-acceptance-table.csv").string();
  std::ofstream(runs.source) << "(the report hashes its input)\n";
  const std::string path = (dir / "mtcal-acceptance-table.html").string();
  write_positioning_report(path, "mtcal iso230-2 p.csv", runs, e);
  const std::string html = acceptance_slurp(path);
  std::remove(path.c_str());
  std::remove(runs.source.c_str());
  EXPECT_NE(html.find("<tr><td>B_i = x̄_i↑ − x̄_i↓ reversal</td><td>2.0</td><td>3.0</td><td>3.0</td></tr>"),
            std::string::npos);
  EXPECT_NE(html.find("<th>target i</th><th>1</th><th>2</th><th>3</th>"), std::string::npos);
  // A = max(x̄ + 2s) − min(x̄ − 2s) = 7.83 − (−2.83) = 10.66; A↑ = 7.83 − (−0.83) = 8.66;
  // A↓ = 2.83 − (−2.83) = 5.66.
  EXPECT_NE(html.find("<tr><td>accuracy A</td><td>10.7</td><td>8.7</td><td>5.7</td></tr>"), std::string::npos);
  EXPECT_LT(html.find("Deviations and statistics per target"), html.find("Axis results"));
  EXPECT_NE(html.find("<tr><td>reversal value B</td><td>3.0</td><td>-</td><td>-</td></tr>"), std::string::npos);

  // Eleven targets in blocks of at most 10: two blocks of 6 and 5, not 10 and 1.
  PositioningRuns eleven;
  for (int i = 0; i <= 10; ++i) {
    eleven.targets.push_back(10.0 * i);
    eleven.up.push_back({10.0 * i + 0.001, 10.0 * i + 0.002});
    eleven.down.push_back({10.0 * i - 0.001, 10.0 * i});
  }
  const PositioningEvaluation e11 = evaluate_positioning(eleven);
  const auto b11 = positioning_target_table(eleven, e11, positioning_display(eleven, e11));
  ASSERT_EQ(b11.size(), 2u);
  EXPECT_EQ(b11[0].columns.size(), 1u + 6u);
  EXPECT_EQ(b11[1].columns.size(), 1u + 5u);
  EXPECT_EQ(b11[1].columns.at(1), "7");
}
