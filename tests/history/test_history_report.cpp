// History analysis output: JSON keys and values, tolerance-file bands, and the trend report's parts.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "mtcal/io/instruments/acceptance_files.hpp"
#include "mtcal/io/json/history_json.hpp"
#include "mtcal/report/history.hpp"
#include "mtcal/util/errors.hpp"

using namespace mtcal;

namespace {

std::vector<SeriesSample> squareness() {
  // EC0Y of a machine over three yearly calibrations: 20, 26, 30 urad with u = 2, 2, 2.
  // Equal weights: tm = 2021-01-01 + 1 year, level 76/3 = 25.333, rate (30 - 20) / 2 = 5 urad/year.
  return {{"2021-01-01", 20, 2.0, "1", "urad"},
          {"2021-01-01T05:49:12Z", 26, 2.0, "2", "urad"},  // 2021-01-01 + 365.2425 days
          {"2022-01-01T11:38:24Z", 30, 2.0, "3", "urad"}};
}

}  // namespace

TEST(HistoryJson, TrendKeysAndValues) {
  // The second and third dates are 1 and 2 mean years after the first (31,556,952 s each).
  auto series = squareness();
  series[1].time = "2022-01-01T05:49:12Z";
  series[2].time = "2023-01-01T11:38:24Z";
  const auto q = trend_from_series("EC0Y", false, series, ToleranceBand::symmetric(40));
  const Json j = to_json(q);
  EXPECT_EQ(j["quantity"], "EC0Y");
  EXPECT_EQ(j["kind"], "parameter");
  EXPECT_EQ(j["unit"], "urad");
  ASSERT_EQ(j["samples"].size(), 3u);
  EXPECT_EQ(j["samples"][1]["measured_at"], "2022-01-01T05:49:12Z");
  const Json& t = j["trend"];
  EXPECT_EQ(t["fit"], "weighted");
  EXPECT_NEAR(t["rate_per_year"].get<double>(), 5.0, 1e-9);
  // Equal u = 2: u(rate) = 2 / sqrt(Sxx) with Sxx = 2; residuals -1/3, 2/3, -1/3 give chi2 = (6/9) / 4 = 1/6,
  // Birge ratio sqrt(1/6) < 1: not inflated.
  EXPECT_NEAR(t["u_rate_per_year"].get<double>(), std::sqrt(2.0), 1e-9);
  EXPECT_EQ(t["inflated"], false);
  EXPECT_EQ(t["t_ref"], "2022-01-01T05:49:12Z");
  EXPECT_EQ(t["tolerance"]["lo"], -40.0);
  EXPECT_DOUBLE_EQ(t["utilisation"].get<double>(), 0.75);
  // Reaches 40 at 1 + (40 - 76/3) / 5 = 3.9333 mean years after the first (1436.62 days): 2024-12-07,
  // 1.9333 years after the latest.
  EXPECT_EQ(t["crossing"]["status"], "predicted");
  EXPECT_EQ(t["crossing"]["date"].get<std::string>().substr(0, 10), "2024-12-07");
  EXPECT_NEAR(t["crossing"]["years_from_last"].get<double>(), 1.9333333, 1e-6);
  EXPECT_TRUE(t["note"].is_null());
  // Keys in their documented order.
  std::vector<std::string> keys;
  for (const auto& [k, v] : t.items()) keys.push_back(k);
  EXPECT_EQ(keys, (std::vector<std::string>{"n", "fit", "t_ref", "level", "u_level", "rate_per_year", "u_rate_per_year",
                                            "residual_sd", "birge_ratio", "inflated", "first", "last", "last_value",
                                            "tolerance", "utilisation", "crossing", "note"}));
}

TEST(HistoryJson, NoFitGivesNullsNotNumbers) {
  const auto q =
      trend_from_series("A_X", true, {{"2024-05-01", 7, std::nullopt, "9", "um"}}, ToleranceBand::at_most(10));
  const Json t = to_json(q)["trend"];
  EXPECT_EQ(t["fit"], "none");
  EXPECT_TRUE(t["rate_per_year"].is_null());
  EXPECT_TRUE(t["u_rate_per_year"].is_null());
  EXPECT_TRUE(t["tolerance"]["lo"].is_null());  // -inf: value <= 10
  EXPECT_EQ(t["tolerance"]["hi"], 10.0);
  EXPECT_EQ(t["crossing"]["status"], "no_fit");
  EXPECT_EQ(t["note"], "1 sample: no line (2 needed)");
}

TEST(HistoryJson, MixedUnitsInASeriesAreRefused) {
  try {
    trend_from_series("EXX", false, {{"2024-01-01", 1, 0.1, "4", "um"}, {"2025-01-01", 0.001, 0.1, "8", "mm"}});
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("record 4"), std::string::npos) << m;
    EXPECT_NE(m.find("record 8"), std::string::npos) << m;
    EXPECT_NE(m.find("one unit"), std::string::npos) << m;
  }
}

TEST(HistoryJson, DiffAndRanking) {
  CalibrationRecord a, b;
  a.id = "5";
  b.id = "6";
  a.parameters = {{"EC0Y", 20, 2.0, "urad"}, {"EXX", 1, std::nullopt, "um"}};
  b.parameters = {{"EC0Y", 30, 2.0, "urad"}};
  const Json d = to_json(diff_records(a, b));
  EXPECT_EQ(d["first"], "5");
  EXPECT_EQ(d["coverage_factor"], 2.0);
  EXPECT_EQ(d["parameters"]["summary"]["significant"], 1);
  EXPECT_EQ(d["parameters"]["summary"]["removed"], 1);
  EXPECT_EQ(d["parameters"]["changes"][0]["verdict"], "significant");
  EXPECT_NEAR(d["parameters"]["changes"][0]["en"].get<double>(), 10 / (2 * std::sqrt(8.0)), 1e-12);
  EXPECT_TRUE(d["parameters"]["changes"][0]["reason"].is_null());
  EXPECT_TRUE(d["parameters"]["changes"][1]["after"].is_null());
  EXPECT_EQ(d["figures"]["changes"].size(), 0u);

  RankSeries s{"HU40T", "EC0Y", "urad", trend_samples(squareness()), ToleranceBand::symmetric(25)};
  const Json r = to_json(rank_fleet({s}));
  EXPECT_EQ(r["order"], "utilisation");
  EXPECT_EQ(r["machines"][0]["rank"], 1);
  EXPECT_EQ(r["machines"][0]["outside"], true);
  EXPECT_DOUBLE_EQ(r["machines"][0]["utilisation"].get<double>(), 30.0 / 25.0);
  EXPECT_EQ(r["machines"][0]["years_to_limit"], 0.0);
  EXPECT_EQ(r["machines"][0]["quantities"][0]["crossing"]["status"], "already_outside");
  EXPECT_EQ(r["machines"][0]["quantities"][0]["latest_at"], "2022-01-01T11:38:24Z");
}

TEST(HistoryJson, ToleranceFileBecomesFigureBands) {
  ToleranceFile f;
  f.iso230_2["X"].set("A", 16);
  f.iso230_2["any"].set("A", 20);
  f.iso230_2["any"].set("E", 12);
  f.iso230_4.set("G", 15);
  f.iso230_4.set("F", 10);
  f.iso230_4.set("H", 6);
  f.volumetric.set("VA", 30);
  f.volumetric.set("VAz", 12);
  const auto b = history_figure_bands(f, {"X", "Y"});
  EXPECT_EQ(b.at("A_X").hi, 16.0);  // the axis' own limit wins over "any"
  EXPECT_FALSE(b.count("E_X"));     // X lists its own quantities: "any" does not fill them in
  EXPECT_EQ(b.at("A_Y").hi, 20.0);
  EXPECT_EQ(b.at("E_Y").hi, 12.0);
  EXPECT_EQ(b.at("A").hi, 20.0);  // a result recorded without an axis
  EXPECT_EQ(b.at("E").hi, 12.0);
  // ISO 230-4: G(b) and each direction's G at most 15; |F max|, |F min| at most 10; H at most 6.
  for (const char* g : {"G_b", "G_cw", "G_ccw"}) {
    EXPECT_TRUE(b.at(g).one_sided()) << g;
    EXPECT_EQ(b.at(g).hi, 15.0) << g;
  }
  EXPECT_EQ(b.at("F_min").lo, -10.0);
  EXPECT_EQ(b.at("F_max").hi, 10.0);
  EXPECT_EQ(b.at("H").hi, 6.0);
  EXPECT_EQ(b.at("va").hi, 30.0);
  EXPECT_EQ(b.at("va_z").hi, 12.0);
  EXPECT_EQ(b.size(), 13u);
}

TEST(HistoryReport, TimelinesBandsEventsAndMetadata) {
  MachineTrends m;
  m.machine = "HU40T </script><b>";
  m.serial = "4711";
  m.series.push_back(trend_from_series("EC0Y", false, squareness(), ToleranceBand::symmetric(40)));
  m.series.push_back(
      trend_from_series("A_X", true,
                        {{"2021-01-01", 8, std::nullopt, "1", "um"}, {"2022-01-01", 9, std::nullopt, "3", "um"}},
                        ToleranceBand::at_most(16)));
  m.events.push_back({"e1", "HU40T", "2021-06-01", EventKind::Crash, "spindle crash <script>alert(1)</script>"});
  m.events.push_back({"e2", "HU40T", "2021-07-15T08:00:00Z", EventKind::CompensationLoaded, "new table"});
  std::vector<CalibrationRecord> records(3);
  for (std::size_t i = 0; i < 3; ++i) {
    records[i].id = std::to_string(i + 1);
    records[i].command = "identify";
    records[i].measured_at = squareness()[i].time;
    records[i].metadata = {{"operator", "J. Doe"}, {"temperature_air", "20.1 °C"}};
  }
  const auto path = (std::filesystem::temp_directory_path() / "mtcal-trend-report-test.html").string();
  write_trend_report(path, "mtcal history trend --machine HU40T", m, records, "sqlite:/tmp/h.db");
  std::stringstream ss;
  ss << std::ifstream(path).rdbuf();
  const std::string h = ss.str();
  std::filesystem::remove(path);
  for (const char* part :
       {"Calibration history: HU40T &lt;/script&gt;&lt;b&gt;", "serial 4711", "sqlite:/tmp/h.db",
        "Plotly.newPlot('plot-1'", "Plotly.newPlot('plot-2'", "±2u (k = 2)", "rate ± 2u(rate)", "predicted crossing",
        "tolerance |value| ≤ 40 urad", "tolerance ≤ 16 um", "spindle crash &lt;script&gt;", "compensation-loaded",
        "<th>Operator</th>", "<th>Air temperature</th>", "20.1 °C", "A_X: no sample states an uncertainty"})
    EXPECT_NE(h.find(part), std::string::npos) << part;
  EXPECT_EQ(h.find("Plotly.newPlot('plot-3'"), std::string::npos);
  EXPECT_EQ(h.find("<script>alert(1)"), std::string::npos);
  EXPECT_EQ(h.find("</script><b>"), std::string::npos);
}
