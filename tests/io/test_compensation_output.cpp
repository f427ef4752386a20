// Compensation output directories appear whole or not at all; the summary's JSON keys.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "mtcal/io/compensation/output.hpp"
#include "mtcal/io/compensation/output_json.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {
namespace {

namespace fs = std::filesystem;

fs::path compensation_output_fresh_dir(const std::string& name) {
  const fs::path p = fs::temp_directory_path() / ("mtcal-comp-" + name + "-" + std::to_string(::getpid()));
  fs::remove_all(p);
  return p;
}

std::string compensation_output_slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(CompensationOutput, WritesEveryFile) {
  const fs::path dir = compensation_output_fresh_dir("ok");
  TargetOutput out;
  out.files = {{"X.comp", "0 0 0\n"}, {"load.ini", "[JOINT_0]\n"}};
  write_target_output(dir.string(), out);
  EXPECT_EQ(compensation_output_slurp(dir / "X.comp"), "0 0 0\n");
  EXPECT_EQ(compensation_output_slurp(dir / "load.ini"), "[JOINT_0]\n");
  // An existing, non-empty directory is refused and left as it is.
  EXPECT_THROW(write_target_output(dir.string(), out), Error);
  EXPECT_EQ(compensation_output_slurp(dir / "X.comp"), "0 0 0\n");
  fs::remove_all(dir);
}

TEST(CompensationOutput, TrailingSlashNamesTheDirectory) {
  const fs::path dir = compensation_output_fresh_dir("slash");
  TargetOutput out;
  out.files = {{"a.txt", "a"}};
  write_target_output(dir.string() + "/", out);
  EXPECT_EQ(compensation_output_slurp(dir / "a.txt"), "a");
  fs::remove_all(dir);
}

TEST(CompensationOutput, EmptyDirectoryIsFilled) {
  const fs::path dir = compensation_output_fresh_dir("empty");
  fs::create_directories(dir);
  TargetOutput out;
  out.files = {{"a.txt", "a"}};
  write_target_output(dir.string(), out);
  EXPECT_EQ(compensation_output_slurp(dir / "a.txt"), "a");
  fs::remove_all(dir);
}

TEST(CompensationOutput, BadFileNameLeavesNothing) {
  const fs::path dir = compensation_output_fresh_dir("bad");
  TargetOutput out;
  out.files = {{"ok.txt", "a"}, {"../escape.txt", "b"}};
  EXPECT_THROW(write_target_output(dir.string(), out), Error);
  EXPECT_FALSE(fs::exists(dir));
  for (const auto& e : fs::directory_iterator(dir.parent_path()))
    EXPECT_EQ(e.path().filename().string().find(dir.filename().string() + ".tmp-"), std::string::npos) << e.path();
}

TEST(CompensationOutput, UnknownTargetListsTheKnownOnes) {
  try {
    compensation_target("no-such-controller");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().field, "format");
    EXPECT_NE(std::string(e.what()).find("no-such-controller"), std::string::npos);
  }
}

TEST(CompensationOutput, JsonKeys) {
  TargetOutput out;
  out.files = {{"X.comp", ""}};
  out.summary.target = "linuxcnc";
  out.summary.quantity = TableQuantity::ActualPosition;
  out.summary.not_compensated = {{"EYX", 0.004, "mm"}};
  out.summary.residual.max_before = {0.01, 0.0, 0.0};
  const Json j = to_json(out);
  std::vector<std::string> keys;
  for (const auto& [k, v] : j.items()) keys.push_back(k);
  EXPECT_EQ(keys, (std::vector<std::string>{"target", "quantity", "sign_source", "files", "not_compensated", "warnings",
                                            "residual", "commanded_range"}));
  EXPECT_TRUE(j["commanded_range"].is_array() && j["commanded_range"].empty());  // a target that chooses none
  EXPECT_EQ(j["quantity"], "actual position");
  EXPECT_EQ(j["files"][0], "X.comp");
  EXPECT_DOUBLE_EQ(j["not_compensated"][0]["max_error"].get<double>(), 0.004);
  EXPECT_DOUBLE_EQ(j["residual"]["max_before_mm"][0].get<double>(), 0.01);
}

}  // namespace
}  // namespace mtcal
