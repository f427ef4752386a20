// The prediction formats: separation tables into records (located errors), their CSV, points
// from G-code and CSV files, the predict outputs and the JSON of a fit.
#include <cstdio>
#include <filesystem>
#include <string>

#include <unistd.h>

#include <gtest/gtest.h>

#include "mtcal/io/text/csv.hpp"
#include "mtcal/io/system/files.hpp"
#include "mtcal/io/gcode/reader.hpp"
#include "mtcal/io/json/prediction_json.hpp"
#include "mtcal/io/model/prediction_model_file.hpp"
#include "mtcal/io/points/prediction_points.hpp"
#include "mtcal/io/instruments/separation_file.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {
namespace {

std::string prediction_io_temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("mtcal-test-" + std::to_string(::getpid()) + "-" + name)).string();
}

TEST(SeparationFile, PositionObservationsPerFilledPair) {
  const std::string text =
      "step,d_x,d_z,cmm_X1,probe_X1,cmm_Z1,probe_Z1\n"
      "1,30,9,30.01,30.0,9.003,9.004\n"
      "1,,,30.02,30.0,,\n";
  const auto obs = read_position_observations(parse_text_csv(text, "t.csv"), "t.csv");
  ASSERT_EQ(obs.size(), 3u);
  EXPECT_EQ(obs[0].axis, 'X');
  EXPECT_EQ(obs[0].feature, "X1");
  EXPECT_EQ(obs[0].distance, 30);
  EXPECT_EQ(obs[1].axis, 'Z');
  EXPECT_EQ(obs[2].line, 3);
  const auto steps = separate_position(obs);
  ASSERT_EQ(steps.size(), 2u);
  EXPECT_NEAR(steps[0].e_pos, (0.01 + 0.02) / 2, 1e-12);  // X, hand: mean of 30.01-30 and 30.02-30
  EXPECT_EQ(steps[0].count, 2);
  EXPECT_EQ(steps[0].distance, 30);
  EXPECT_EQ(separation_csv(PositionSeparation{steps, {}}),
            "axis,step,distance,e_pos,count\nX,1,30,0.015,2\nZ,1,9,-0.001,1\n");
}

TEST(SeparationFile, BadCellsNameFileLineAndColumn) {
  try {
    read_dimension_table(parse_text_csv("workpiece,step,axis,nominal,measured,e_pf,e_pt,e_pos\nW2,1,X,29,abc,0,0,0\n",
                                        "d.csv"),
                         "d.csv");
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, "d.csv");
    EXPECT_EQ(e.where().line, 2);
    EXPECT_EQ(e.where().field, "measured");
  }
  EXPECT_THROW(read_dimension_table("/nonexistent/d.csv"), InputError);
}

TEST(PredictionPoints, FromGcodeTimesAndDistances) {
  // 100 mm at F500 after a 30 mm rapid at 10000 mm/min: t = 1 + 0.003 + 0.2 minutes.
  const GcodeProgram prog = parse_gcode("G0 X30\nG1 X-70 F500\n", "p.nc", GcodeOptions{"XYZ", {}, {}});
  const PredictionPoints t = points_from_gcode(prog, "p.nc", 1.0, 3500, 10000);
  ASSERT_EQ(t.rows.size(), 1u);
  EXPECT_EQ(t.lines, std::vector<int>{2});
  EXPECT_NEAR(t.rows[0][static_cast<std::size_t>(t.column("t"))], 1.203, 1e-12);
  EXPECT_EQ(t.rows[0][static_cast<std::size_t>(t.column("dx"))], 70);
  EXPECT_EQ(t.rows[0][static_cast<std::size_t>(t.column("S"))], 3500);
  try {
    points_from_gcode(parse_gcode("G0 X30\n", "r.nc", GcodeOptions{"XYZ", {}, {}}), "r.nc", 0, 3500, 10000);
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, "r.nc");
  }
}

TEST(PredictionPoints, EmptyPointsFileIsRefused) {
  const std::string path = prediction_io_temp_path("points.csv");
  write_file_atomically(path, "t,S\n");
  try {
    read_prediction_points(path);
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, path);
  }
  write_file_atomically(path, "t,S\n1,3500\n");
  const PredictionPoints p = read_prediction_points(path);
  std::remove(path.c_str());
  EXPECT_EQ(p.lines, std::vector<int>{2});
  EXPECT_EQ(p.source, path);
}

TEST(PredictionPoints, OutputsOfARun) {
  const PredictionModel m = parse_prediction_model(
      "mtcal_prediction_model: 1\ncomponents:\n"
      "  - {name: a, axis: x, variable: t, form: polynomial, coefficients: [0, 2]}\n",
      "m.yaml");
  const PredictionPoints pts{{"t", "step"}, {{1, 1}, {3, 1}, {5, 2}}, {2, 3, 4}, "p.csv"};
  const PredictionRun run = predict_points(m, pts, {}, false, true);
  EXPECT_EQ(prediction_csv(run, m), "t,step,a,ex,ey,ez\n1,1,2,2,0,0\n3,1,6,6,0,0\n5,2,10,10,0,0\n");
  EXPECT_EQ(compensation_csv(run), "step,offset_x,offset_y,offset_z\n1,-4,-0,-0\n2,-10,-0,-0\n");
  const Json j = to_json(run, m);
  EXPECT_EQ(j["model"], "m.yaml");
  EXPECT_EQ(j["compensation"][0]["offset_x"], -4.0);
  EXPECT_EQ(j["points"][2]["components"]["a"], 10.0);
}

TEST(PredictionJson, FitKeysInOrder) {
  const std::vector<double> x{1, 2, 3, 4}, y{2.1, 3.9, 6.2, 7.8};
  const FitResult f = fit_model({ModelForm::Polynomial, 1, std::nullopt}, x, y);
  const Json j = to_json(f);
  std::vector<std::string> keys;
  for (const auto& [k, v] : j.items()) keys.push_back(k);
  EXPECT_EQ(keys, (std::vector<std::string>{"model", "form", "parameters", "identifiable", "rss", "sigma", "dof",
                                            "r_squared", "aicc", "backward", "loocv_rmse", "loocv_method"}));
  EXPECT_EQ(j["form"], "polynomial");
  EXPECT_EQ(j["dof"], 2);
  EXPECT_EQ(j["loocv_method"], "refit");
}

}  // namespace
}  // namespace mtcal
