// The identification formats: plan/measurement CSV written and read back through a file, scale
// bars as text, the identified parameter file and the JSON of identifiability.
#include <cstdio>
#include <filesystem>
#include <limits>
#include <string>

#include <unistd.h>

#include <gtest/gtest.h>

#include "mtcal/identification/identification.hpp"
#include "mtcal/io/system/files.hpp"
#include "mtcal/io/json/identification_json.hpp"
#include "mtcal/io/model/identified_parameters_file.hpp"
#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/io/instruments/probing_plan_file.hpp"
#include "mtcal/util/errors.hpp"
#include "examples.hpp"

namespace mtcal {
namespace {

using mtcal::testing::hu40t;

const std::string identification_io_kPlanPath = std::string(MTCAL_EXAMPLES_DIR) + "/../plans/hu40t-samba-tango.csv";

std::string identification_io_temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("mtcal-test-" + std::to_string(::getpid()) + "-" + name)).string();
}

// A simulated measurement written with a comment line and read back from the file: the same
// readings bit for bit, the same features and directions.
TEST(ProbingPlanFile, MeasurementsRoundTripThroughAFile) {
  const Machine m = hu40t();
  const ProbingPlan plan = read_probing_csv(m, identification_io_kPlanPath);
  SimulationOptions so;
  so.noise = 1e-3;
  so.seed = 3;
  const Simulation sim = simulate_probing(m, plan, so);
  const std::string path = identification_io_temp_path("meas.csv");
  write_probing_csv(path, m, sim.measurements, "simulated for a test");
  const std::string text = read_text_file(path);
  EXPECT_EQ(text.rfind("# simulated for a test\nindexation,C,B,feature,kind", 0), 0u) << text.substr(0, 80);
  const ProbingPlan back = read_probing_csv(m, path);
  std::remove(path.c_str());
  EXPECT_TRUE(back.measured);
  EXPECT_EQ(back.source, path);
  ASSERT_EQ(back.records.size(), sim.measurements.records.size());
  ASSERT_EQ(back.features.size(), sim.measurements.features.size());
  for (std::size_t i = 0; i < back.records.size(); ++i) {
    EXPECT_EQ(back.records[i].q, sim.measurements.records[i].q) << i;
    EXPECT_EQ(back.records[i].dir, sim.measurements.records[i].dir) << i;
    EXPECT_EQ(back.records[i].line, static_cast<int>(i) + 3);  // comment, header, then the rows
  }
}

TEST(ProbingPlanFile, BadRowNamesFileLineAndColumn) {
  const Machine m = hu40t();
  const std::string text =
      "indexation,B,C,feature,kind,x,y,z,nx,ny,nz,dirX,dirY,dirZ\n"
      "1,0,0,1,ball,0,0,0,,,,0,0,0\n"
      "2,0,0,2,cube,0,0,0,,,,0,0,0\n";
  try {
    parse_probing_csv(m, text, "plan.csv");
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, "plan.csv");
    EXPECT_EQ(e.where().line, 3);
    EXPECT_EQ(e.where().field, "kind");
  }
  EXPECT_THROW(read_probing_csv(m, "/nonexistent/plan.csv"), InputError);
}

TEST(ProbingPlanFile, ScaleBarTextNamesItsSource) {
  const ScaleBar b = parse_scale_bar("1: 2:304.8", "bars.txt");
  EXPECT_EQ(b.ball_a, "1");
  EXPECT_EQ(b.ball_b, "2");
  EXPECT_EQ(b.length, 304.8);
  EXPECT_EQ(b.source, "bars.txt");
  try {
    parse_scale_bar("1-2", "--scale-bar");
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, "--scale-bar");
    EXPECT_EQ(e.where().field, "1-2");
  }
  EXPECT_THROW(parse_scale_bar("1:2:0", "x"), InputError);
}

// The identified file holds the estimated errors, reads back into the machine, and says where
// the estimates came from.
TEST(IdentifiedParametersFile, ReadsBackWithItsProvenance) {
  const Machine truth = hu40t();
  Machine prior = truth;
  prior.set_parameter("EX0C", 0.0);
  const ProbingPlan plan = read_probing_csv(truth, identification_io_kPlanPath);
  SimulationOptions so;
  so.seed = 1;
  const Simulation sim = simulate_probing(truth, plan, so);
  IdentificationOptions o;
  o.estimate = {"EX0C"};
  o.scale_bars = {{"1", "2", 304.8}};
  const IdentificationResult r = identify(prior, sim.measurements, o);
  const std::string yaml = identified_parameters_yaml(prior, r, "meas.csv");
  EXPECT_NE(yaml.find("Identified by mtcal identify from meas.csv"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("EX0C = "), std::string::npos) << yaml;
  const std::string path = identification_io_temp_path("identified.yaml");
  write_identified_parameters(path, prior, r, "meas.csv");
  Machine back = prior;
  load_parameters(back, path);
  std::remove(path.c_str());
  const auto i = *back.parameter_index("EX0C");
  EXPECT_NEAR(back.parameter(i), truth.parameter(i), 1e-9);
}

TEST(IdentificationJson, IdentifiabilityKeysInOrder) {
  Identifiability id;
  id.columns = {"EX0C", "ball 1 x"};
  id.rank = 1;
  id.singular_values = {1.0, 0.0};
  id.condition = std::numeric_limits<double>::infinity();
  id.condition_identifiable = 1.0;
  id.identifiable = {"EX0C"};
  const Json j = to_json(id);
  std::vector<std::string> keys;
  for (const auto& [k, v] : j.items()) keys.push_back(k);
  EXPECT_EQ(keys,
            (std::vector<std::string>{"rank", "unknowns", "condition", "condition_identifiable", "singular_values",
                                      "identifiable", "unidentifiable", "null_directions", "columns"}));
  EXPECT_TRUE(j["condition"].is_null());
  EXPECT_EQ(j["unknowns"], 2);
}

}  // namespace
}  // namespace mtcal
