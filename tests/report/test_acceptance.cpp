// Acceptance reports: metadata record and file, tolerance file and verdicts, the ISO 230-2 report
// in µm with its warnings. Expected values are hand calculations on small data.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "mtcal/evaluation/iso230_2.hpp"
#include "mtcal/evaluation/tolerance.hpp"
#include "mtcal/io/acceptance_files.hpp"
#include "mtcal/report/evaluation.hpp"
#include "mtcal/evaluation/metadata.hpp"
#include "mtcal/report/report.hpp"
#include "mtcal/util/errors.hpp"

using namespace mtcal;

namespace {
std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}
template <class F>
std::string error_of(F&& f) {
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
  EXPECT_NE(error_of([&] { m.set("sreial", "1", "--meta"); }).find("unknown metadata field 'sreial'"),
            std::string::npos);
  EXPECT_NE(error_of([&] { m.set("owner", "  ", "f.yaml", 3); }).find("f.yaml:3"), std::string::npos);
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
  EXPECT_NE(error_of([] { parse_report_metadata("machine: M\nopertor: A\n", "m.yaml"); }).find("m.yaml:2"),
            std::string::npos);
  EXPECT_NE(error_of([] { parse_report_metadata("machine: {a: 1}\n", "m.yaml"); }).find("expected text"),
            std::string::npos);
  EXPECT_NE(error_of([] { parse_report_metadata("", "m.yaml"); }).find("found nothing"), std::string::npos);
  EXPECT_NE(error_of([] { parse_report_metadata("machine: [\n", "m.yaml"); }).find("not valid YAML"),
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
  EXPECT_NE(error_of([] { parse_tolerance_file("iso230-2:\n  X: {Q: 3}\n", "t.yaml"); }).find("t.yaml:2"),
            std::string::npos);
  EXPECT_NE(error_of([] { parse_tolerance_file("iso230-4: {G: -1}\n", "t.yaml"); }).find(">= 0"), std::string::npos);
  EXPECT_NE(error_of([] { parse_tolerance_file("unit: inch\n", "t.yaml"); }).find("expected um or mm"),
            std::string::npos);
  EXPECT_NE(error_of([] { parse_tolerance_file("iso230-3: {}\n", "t.yaml"); }).find("unknown key 'iso230-3'"),
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
  EXPECT_NE(error_of([&] { check_tolerances({{"A", 1}}, z, "--tolerance"); }).find("it gives A"), std::string::npos);
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
  const std::string html = slurp(path);
  std::remove(path.c_str());
  std::remove(runs.source.c_str());
  EXPECT_NE(html.find("<div class=\"verdict fail\">FAIL"), std::string::npos);
  EXPECT_NE(html.find("<td>A</td><td>10.66</td><td>8.00</td><td>FAIL</td>"), std::string::npos);
  EXPECT_NE(html.find("<th>Serial number</th><td>4711</td>"), std::string::npos);
  EXPECT_NE(html.find("&lt;HU40T&gt;"), std::string::npos);
  EXPECT_NE(html.find("asks for 5 runs"), std::string::npos);                            // 2 runs
  EXPECT_NE(html.find("no test date (date)"), std::string::npos);                        // condition missing
  EXPECT_NE(html.find("deviation (um)"), std::string::npos);  // the plot in micrometres, not mm
  EXPECT_NE(html.find("\"text\":\"A 10.66\""), std::string::npos);  // A marked on the plot
}
