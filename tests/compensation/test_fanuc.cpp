// FANUC target: fanuc-pitch.txt read back by the test's own reader, the documented rule applied
// (point n holds the increment over the section ending at (n - 3620) x 3624 from the reference
// position, in counts of detection unit x 3623; a rotary table's values sum to zero, FANUC 0i-PB
// Parameter Manual p. 100), the model's correction recovered; residual; bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <sstream>

#include "mtcal/compensation/fanuc.hpp"
#include "mtcal/io/compensation/fanuc.hpp"
#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/util/errors.hpp"
#include "examples.hpp"

namespace mtcal {
namespace {

using mtcal::testing::example;

struct Listing {
  std::map<int, std::vector<double>> parameter;  // number -> value per axis column
  std::map<int, int> pitch;                      // point number -> value
};
Listing read_listing(const std::string& text) {
  Listing l;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    line = line.substr(0, line.find(';'));
    std::istringstream ls(line);
    std::string kind;
    if (!(ls >> kind)) continue;
    int no = 0;
    EXPECT_TRUE(static_cast<bool>(ls >> no)) << line;
    if (kind == "PARAMETER") {
      for (double v; ls >> v;) l.parameter[no].push_back(v);
    } else {
      EXPECT_EQ(kind, "PITCH");
      int v = 0;
      EXPECT_TRUE(static_cast<bool>(ls >> v)) << line;
      EXPECT_FALSE(l.pitch.count(no)) << "point " << no << " twice";
      l.pitch[no] = v;
    }
  }
  return l;
}

// The control's rule: the absolute compensation at compensation position (n - R) x interval is the
// sum of the values from the reference point to n (counts x unit x magnification).
double absolute_at(const Listing& l, std::size_t col, int n, double unit) {
  const int r = static_cast<int>(l.parameter.at(3620)[col]);
  const double mag = l.parameter.at(3623)[col];
  long sum = 0;
  if (n > r)
    for (int i = r + 1; i <= n; ++i) sum += l.pitch.at(i);
  else
    for (int i = n + 1; i <= r; ++i) sum -= l.pitch.at(i);
  return static_cast<double>(sum) * unit * mag;
}

double fanuc_mean_error_along(const ErrorModel& model, std::size_t a, double p) {
  std::vector<double> q(model.axis_count(), 0.0);
  q[a] = p;
  const std::vector<std::int8_t> plus(q.size(), 1), minus(q.size(), -1);
  const Vec3 u = model.machine().axes[a].direction();
  return 0.5 * (model.evaluate(q, plus).translation.dot(u) + model.evaluate(q, minus).translation.dot(u));
}

TEST(FanucTarget, CountsRecoverAPositioningErrorOfWholeCountsExactly) {
  // EXX = 1 count (0.001 mm) per 16 mm interval: every node's correction is a whole number of counts.
  Machine m = example("vmc-3axis.yaml");
  m.keep_only({"EXX"});
  for (const char* p : {"EXX.0", "EXX.2", "EXX.3", "EXX.b"}) m.set_parameter(p, 0.0);
  m.set_parameter("EXX.1", 0.001 / 16.0);
  CompensationOptions o;
  o.points = 51;
  o.residual_points = 5;
  const TargetOutput out = fanuc_output(compensate_fanuc(m, o));
  EXPECT_EQ(out.summary.quantity, TableQuantity::Correction);
  const Listing l = read_listing(out.files.at(0).text);
  ASSERT_EQ(l.parameter.at(3620).size(), 1u);  // X only
  EXPECT_EQ(l.parameter.at(3624)[0], 16.0);    // 800 mm / 50
  EXPECT_EQ(l.parameter.at(3623)[0], 1.0);
  const int r = static_cast<int>(l.parameter.at(3620)[0]);
  const int lo = static_cast<int>(l.parameter.at(3621)[0]), hi = static_cast<int>(l.parameter.at(3622)[0]);
  EXPECT_EQ(lo, 0);
  EXPECT_EQ(r, 25 - 1);  // 25 sections below the reference position: points 0 ... 24
  EXPECT_EQ(hi, r + 25);
  const ErrorModel model(m);
  for (int n = lo - 1; n <= hi; ++n) {
    const double p = (n - r) * 16.0;
    const double c = -(fanuc_mean_error_along(model, 0, p) - fanuc_mean_error_along(model, 0, 0.0));
    EXPECT_NEAR(absolute_at(l, 0, n, 0.001), c, 1e-9) << "point " << n;
  }
  for (const auto& [n, v] : l.pitch) EXPECT_EQ(v, -1) << n;  // the error grows, the correction falls
}

TEST(FanucTarget, CountsFollowTheModelToHalfACount) {
  const Machine m = example("vmc-3axis.yaml");
  CompensationOptions o;
  o.points = 41;
  o.residual_points = 3;
  const auto c = compensate_fanuc(m, o);
  const Listing l = read_listing(fanuc_output(c).files.at(0).text);
  const ErrorModel model(m);
  ASSERT_EQ(l.parameter.at(3620).size(), 3u);
  std::size_t checked = 0;
  for (std::size_t col = 0; col < 3; ++col) {
    const int r = static_cast<int>(l.parameter.at(3620)[col]);
    const double interval = l.parameter.at(3624)[col], mag = l.parameter.at(3623)[col];
    const auto& ax = m.axes[col];
    for (int n = static_cast<int>(l.parameter.at(3621)[col]); n <= l.parameter.at(3622)[col]; ++n) {
      EXPECT_LE(std::abs(l.pitch.at(n)), kFanucMaxValue);
      const double p = (n - r) * interval;
      if (p < ax.travel->min - 1e-9 || p > ax.travel->max + 1e-9) continue;  // linear: mm
      const double e = -(fanuc_mean_error_along(model, col, p) - fanuc_mean_error_along(model, col, 0.0));
      EXPECT_NEAR(absolute_at(l, col, n, 0.001), e, 0.5 * 0.001 * mag + 1e-12) << ax.letter << " point " << n;
      ++checked;
    }
  }
  EXPECT_GT(checked, 100u);
  // Only the positioning is held; squareness, straightness and the reversal are listed.
  std::string listed;
  for (const auto& n : c.summary.not_compensated) listed += n.what + ";";
  for (const char* e : {"EC0Y", "EYX", "reversal", "rounding"}) EXPECT_NE(listed.find(e), std::string::npos) << e;
}

TEST(FanucTarget, RotaryTableSumsToZeroAndRecoversAPeriodicError) {
  Machine m = example("hu40t-wCBXfYZt.yaml");
  m.clear_errors();
  Fourier f;
  f.cos_terms = {2e-5};
  f.sin_terms = {0, -1e-5};
  m.axes[*m.axis_index('C')].motion[5] = MotionFunction(f);
  CompensationOptions o;
  o.points = 9;  // 8 sections of 45 deg, as the manual's example
  o.residual_points = 3;
  o.detection_unit = 1e-6;  // deg per count
  const Listing l = read_listing(fanuc_output(compensate_fanuc(m, o)).files.at(0).text);
  ASSERT_EQ(l.parameter.at(3620).size(), 1u);
  const int r = static_cast<int>(l.parameter.at(3620)[0]);
  EXPECT_EQ(l.parameter.at(3621)[0], r);
  EXPECT_EQ(l.parameter.at(3622)[0], r + 8);
  EXPECT_EQ(l.parameter.at(3624)[0], 45.0);
  EXPECT_EQ(l.parameter.at(3625)[0], 360.0);
  long sum = 0;
  for (int n = r + 1; n <= r + 8; ++n) sum += l.pitch.at(n);
  EXPECT_EQ(sum, 0);
  EXPECT_EQ(l.pitch.at(r), l.pitch.at(r + 8));
  const double mag = l.parameter.at(3623)[0];
  for (int n = r; n <= r + 8; ++n) {
    const double q = (n - r) * 45.0 * std::numbers::pi / 180.0;
    const double c_deg =
        -(f.cos_terms[0] * (std::cos(q) - 1.0) + f.sin_terms[1] * std::sin(2 * q)) * 180 / std::numbers::pi;
    EXPECT_NEAR(absolute_at(l, 0, n, 1e-6), c_deg, 0.5e-6 * mag + 1e-12) << n;
  }
}

TEST(FanucTarget, FineCountsLeaveOnlyInterpolation) {
  Machine m = example("vmc-3axis.yaml");
  m.keep_only({"EXX", "EZZ"});
  for (const char* p : {"EXX.0", "EXX.b", "EZZ.b"}) m.set_parameter(p, 0.0);  // no offset at the reference
  CompensationOptions o;
  o.points = 128;
  o.detection_unit = 1e-6;
  const auto c = compensate_fanuc(m, o);
  EXPECT_LT(c.summary.residual.max_norm_after, 0.01 * c.summary.residual.max_norm_before);
}

TEST(FanucTarget, BadInput) {
  Machine none = example("vmc-3axis.yaml");
  none.clear_errors();
  EXPECT_THROW(compensate_fanuc(none, {}), InputError);
  CompensationOptions o;
  o.detection_unit = 0.0;
  EXPECT_THROW(compensate_fanuc(example("vmc-3axis.yaml"), o), InputError);
  o.detection_unit = 0.001;
  o.points = 129;
  EXPECT_THROW(compensate_fanuc(example("vmc-3axis.yaml"), o), InputError);
  // A correction that changes by more than 127 counts x magnification 100 between two nodes: the
  // message says what to change in the data's words (the command adds its option).
  Machine steep = example("vmc-3axis.yaml");
  steep.set_parameter("EXX.1", 100e-6);  // 100 ppm: 0.08 mm over 800 mm
  o.points = 2;
  o.detection_unit = 1e-6;
  try {
    compensate_fanuc(steep, o);
    ADD_FAILURE() << "a change of 80000 counts per interval was accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("use a shorter interval: more table points"), std::string::npos) << what;
    EXPECT_EQ(what.find("--"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace mtcal
