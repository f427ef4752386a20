// A rehearsed calibration campaign (issue 33): the seeded truth draw, the reached-pose check, the
// campaign's comparison of before and after, and their files. References: the draw's sizes taken
// again by sampling the drawn functions; the pose check against eval's e = actual - nominal and a
// brute-force VA; probed deviations against -e of the truth at the readings.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <set>

#include "brute_force.hpp"
#include "input_errors.hpp"
#include "mtcal/evaluation/pose_check.hpp"
#include "mtcal/identification/campaign.hpp"
#include "mtcal/identification/error_draw.hpp"
#include "mtcal/io/instruments/probing_plan_file.hpp"
#include "mtcal/io/json/campaign_json.hpp"
#include "mtcal/io/json/identification_json.hpp"
#include "mtcal/io/model/drawn_parameters_file.hpp"
#include "mtcal/io/model/identification_result_file.hpp"
#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/io/points/reached_poses_file.hpp"
#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {
namespace {

using testing::error_at;

const std::string kMachines = std::string(MTCAL_EXAMPLES_DIR) + "/";
const std::string kPlans = std::string(MTCAL_EXAMPLES_DIR) + "/../plans/";

Machine hu40t() { return load_machine(kMachines + "hu40t-wCBXfYZt.yaml"); }

// The largest |value| of a drawn error over its axis' travel, sampled finely here (the draw's own
// sampling is coarser for polynomials, exact at a table's positions).
double size_of(const Machine& m, const ErrorName& e) {
  if (e.kind == ErrorKind::Mounting)
    return std::abs((e.body == 't' ? m.tool_mounting : m.workpiece_mounting)[index_of(e.component)]);
  const Axis& ax = m.axis(e.body);
  if (e.kind == ErrorKind::Location) return std::abs(ax.location[index_of(e.component)]);
  const MotionFunction& f = ax.motion[index_of(e.component)];
  double big = 0;
  // A table is linear between its positions: its largest |value| is at one of them.
  if (const auto* t = std::get_if<Table>(&f.form())) {
    for (double v : t->forward) big = std::max(big, std::abs(v));
    return big;
  }
  for (int i = 0; i <= 4000; ++i) {
    const double q = ax.travel->min + (ax.travel->max - ax.travel->min) * i / 4000.0;
    for (int dir : {-1, 0, 1}) big = std::max(big, std::abs(f.value(q, dir)));
  }
  return big;
}

TEST(ErrorDraw, SameSeedSameTruthOtherSeedAnother) {
  ErrorDrawOptions o;
  o.seed = 42;
  o.tables = {"ECC", "EXX"};
  const ErrorDraw a = draw_errors(hu40t(), o), b = draw_errors(hu40t(), o);
  o.seed = 43;
  const ErrorDraw c = draw_errors(hu40t(), o);
  const auto pa = a.truth.parameters(), pb = b.truth.parameters(), pc = c.truth.parameters();
  ASSERT_EQ(pa.size(), pb.size());
  std::size_t differ = 0;
  for (std::size_t i = 0; i < pa.size(); ++i) {
    EXPECT_EQ(pa[i].value, pb[i].value) << pa[i].name;  // bit for bit
    differ += pa[i].value != pc[i].value;
  }
  EXPECT_GT(differ, a.drawn.size());  // every drawn error changes with the seed
  // The text file too.
  EXPECT_EQ(truth_parameters_yaml(a, "x"), truth_parameters_yaml(b, "x"));
}

TEST(ErrorDraw, FixedValuesOfAFixedSeed) {
  // mt19937_64's output is fixed by the standard, and the draw computes its uniform numbers and
  // signs from the bits (not with std::uniform_real_distribution, whose algorithm each library
  // chooses): a location error's value is lo + (hi - lo) * (top 53 bits of the first output) / 2^53,
  // its sign the top bit of the second, on every platform.
  std::mt19937_64 g(1);
  const std::uint64_t first = g();
  const double u = static_cast<double>(first >> 11) * 0x1.0p-53;
  ErrorDrawOptions o;
  o.only = {"EX0C"};
  const ErrorDraw d = draw_errors(hu40t(), o);
  const double expected = (5e-3 + (50e-3 - 5e-3) * u) * ((g() >> 63) ? -1.0 : 1.0);
  EXPECT_EQ(d.truth.parameter(*d.truth.parameter_index("EX0C")), expected);
}

TEST(ErrorDraw, SizesWithinTheRanges) {
  ErrorDrawOptions o;
  o.tables = {"ECC", "EXX", "EBB"};
  o.only = {"EYX", "EAX.2", "EXt", "ECw"};  // polynomial errors, a parameter, mounting errors
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    o.seed = seed;
    o.only.push_back("EX0C");
    const ErrorDraw d = draw_errors(hu40t(), o);
    o.only.pop_back();
    ASSERT_FALSE(d.drawn.empty());
    for (const auto& e : d.drawn) {
      const double s = size_of(d.truth, e.error);
      const bool rot = is_rotation(e.error.component);
      EXPECT_EQ(e.rotational, rot);
      // The size the draw reports is what the function reaches (a polynomial's maximum between
      // the draw's 201 samples may exceed it by a little).
      EXPECT_NEAR(s, e.size, 1e-3 * e.size) << e.error.str() << " seed " << seed;
      EXPECT_GE(e.size, rot ? 10e-6 : 5e-3) << e.error.str();
      EXPECT_LE(e.size, rot ? 100e-6 : 50e-3) << e.error.str();
    }
  }
}

TEST(ErrorDraw, TablesAreTablesZeroAtTheAxisZero) {
  ErrorDrawOptions o;
  o.tables = {"ECC", "EXX"};
  o.table_points = 9;
  o.only = {"EX0C"};
  const ErrorDraw d = draw_errors(hu40t(), o);
  for (char axis : {'C', 'X'}) {
    const Axis& ax = d.truth.axis(axis);
    const auto& f = ax.motion[axis == 'C' ? index_of(Component::C) : index_of(Component::X)];
    const auto* t = std::get_if<Table>(&f.form());
    ASSERT_NE(t, nullptr);
    ASSERT_EQ(t->positions.size(), 9u);
    EXPECT_DOUBLE_EQ(t->positions.front(), ax.travel->min);
    EXPECT_DOUBLE_EQ(t->positions.back(), ax.travel->max);
    EXPECT_NEAR(f.value(0.0, 0), 0.0, 1e-18);
    // The nominal machine: the same table, zero.
    const auto& fn = d.nominal.axis(axis).motion[axis == 'C' ? index_of(Component::C) : index_of(Component::X)];
    const auto* tn = std::get_if<Table>(&fn.form());
    ASSERT_NE(tn, nullptr);
    EXPECT_EQ(tn->positions, t->positions);
    EXPECT_TRUE(fn.is_zero());
  }
  // An existing table keeps its positions.
  Machine m = hu40t();
  Table given{{-1.0, 0.0, 2.0}, {1e-3, 0, 1e-3}, {}};
  m.axes[*m.axis_index('B')].motion[index_of(Component::B)] = MotionFunction(given);
  o.tables = {"EBB"};
  const ErrorDraw e = draw_errors(m, o);
  EXPECT_EQ(std::get<Table>(e.truth.axis('B').motion[index_of(Component::B)].form()).positions, given.positions);
}

TEST(ErrorDraw, OnlyTheSelectionAndEveryOtherErrorZero) {
  ErrorDrawOptions o;
  const std::set<std::string> wanted{"EX0C", "EY0C", "EA0C", "EB0C", "EC0Y", "EXX.1"};
  o.only = {wanted.begin(), wanted.end()};
  const ErrorDraw d = draw_errors(hu40t(), o);  // hu40t has many non-zero errors: all go
  for (const auto& p : d.truth.parameters())
    if (wanted.count(p.name))
      EXPECT_NE(p.value, 0.0) << p.name;
    else
      EXPECT_EQ(p.value, 0.0) << p.name;
  EXPECT_EQ(d.drawn.size(), wanted.size());
  for (const auto& p : d.nominal.parameters()) EXPECT_EQ(p.value, 0.0) << p.name;
  // Default: every location error of every axis, nothing else.
  const ErrorDraw all = draw_errors(hu40t(), {});
  std::size_t locations = 0;
  for (const auto& p : all.truth.parameters()) {
    if (p.error.kind == ErrorKind::Location) {
      ++locations;
      EXPECT_NE(p.value, 0.0) << p.name;
    } else {
      EXPECT_EQ(p.value, 0.0) << p.name;
    }
  }
  EXPECT_EQ(all.drawn.size(), locations);
  EXPECT_EQ(locations, 19u);  // wCBXfYZt: 5 per rotary axis, 3 per linear axis
}

TEST(ErrorDraw, ParameterFileReadsBackToTheTruth) {
  ErrorDrawOptions o;
  o.seed = 9;
  o.tables = {"ECC"};
  const ErrorDraw d = draw_errors(hu40t(), o);
  // Applied to the example machine, whose own errors are not zero: every one is replaced.
  Machine m = hu40t();
  apply_parameters(m, truth_parameters_yaml(d, "test"), "truth.yaml");
  const auto a = m.parameters(), b = d.truth.parameters();
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].name, b[i].name);
    EXPECT_EQ(a[i].value, b[i].value) << a[i].name;  // full precision
  }
  Machine n = hu40t();
  apply_parameters(n, nominal_parameters_yaml(d, "test"), "nominal.yaml");
  EXPECT_EQ(n.parameter_count(), d.truth.parameter_count());
  for (const auto& p : n.parameters()) EXPECT_EQ(p.value, 0.0) << p.name;
  // The JSON names the drawn errors and their sizes.
  const Json j = to_json(d);
  EXPECT_EQ(j["seed"], 9);
  ASSERT_EQ(j["drawn"].size(), d.drawn.size());
  std::size_t tables = 0;
  for (const auto& e : j["drawn"]) {
    EXPECT_EQ(e["table"].get<bool>(), e["error"] == "ECC") << e["error"];
    tables += e["table"].get<bool>();
  }
  EXPECT_EQ(tables, 1u);
}

TEST(ErrorDraw, BadInput) {
  const Machine m = hu40t();
  ErrorDrawOptions o;
  o.only_source = "--draw-only";
  o.tables_source = "--draw-table";
  o.size_source = "--draw-length-um";
  o.only = {"EX0Q"};
  EXPECT_EQ(error_at([&] { draw_errors(m, o); }).file, "--draw-only");
  o.only = {"EXX.9"};
  EXPECT_EQ(error_at([&] { draw_errors(m, o); }).field, "EXX.9");
  o.only = {"EZ0C"};  // not a location error of C (along its own axis)
  EXPECT_EQ(error_at([&] { draw_errors(m, o); }).file, "--draw-only");
  o.only = {};
  o.tables = {"EX0C"};  // a location error is no table
  EXPECT_EQ(error_at([&] { draw_errors(m, o); }).file, "--draw-table");
  o.tables = {"ECA"};  // no A axis
  EXPECT_EQ(error_at([&] { draw_errors(m, o); }).file, "--draw-table");
  o.tables = {"ECC"};
  o.table_points = 1;
  EXPECT_EQ(error_at([&] { draw_errors(m, o); }).file, "--draw-table");
  o.table_points = 13;
  o.length_lo = 50e-3, o.length_hi = 5e-3;
  EXPECT_EQ(error_at([&] { draw_errors(m, o); }).file, "--draw-length-um");
  o.length_lo = -1e-3, o.length_hi = 5e-3;
  EXPECT_EQ(error_at([&] { draw_errors(m, o); }).file, "--draw-length-um");
  o.length_lo = 5e-3, o.angle_hi = std::nan("");
  EXPECT_EQ(error_at([&] { draw_errors(m, o); }).file, "--draw-length-um");
  // A table of an axis without a travel.
  Machine nt = m;
  nt.axes[*nt.axis_index('C')].travel.reset();
  o.angle_hi = 100e-6;
  EXPECT_EQ(error_at([&] { draw_errors(nt, o); }).file, "--draw-table");
}

// ---------------------------------------------------------------- reached poses

std::vector<ReachedPose> nominal_poses(const Machine& m, int n) {
  const CommandedJointSolver s(m);
  std::vector<ReachedPose> out;
  for (int i = 0; i < n; ++i) {
    const double t = i / static_cast<double>(n);
    CommandedPose p;
    p.point = Vec3(200 * std::sin(7 * t) - 20, 150 * std::cos(5 * t), 100 * std::sin(3 * t) + 50);
    p.rotary = {std::numbers::pi / 3 * std::sin(11 * t), std::numbers::pi / 2 * std::cos(2 * t)};
    out.push_back({p, s.nominal_inverse(p, m.tool.length), i + 2});
  }
  return out;
}

TEST(PoseCheck, NominalJointsGiveTheErrorEvalGives) {
  Machine truth = hu40t();
  const auto poses = nominal_poses(truth, 40);
  const PoseCheck c = check_reached_poses(truth, poses);
  const ErrorModel model(truth);
  std::vector<Vec3> ref;
  double max = 0;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    // At the nominal joints the commanded point is the nominal one: actual - commanded = e.
    const Vec3 e = model.evaluate(poses[i].q).translation;
    EXPECT_LT((c.poses[i].error - e).norm(), 1e-10) << i;
    ref.push_back(e);
    max = std::max(max, e.norm());
  }
  EXPECT_NEAR(c.max_error, max, 1e-10);
  const auto bf = testing::brute_force_va(ref);
  EXPECT_NEAR(c.va.va.value, bf.va, 1e-10);
  EXPECT_GT(c.max_error, 1e-3);  // the example's errors are tens of um
}

TEST(PoseCheck, CompensatedJointsReachTheCommand) {
  const Machine truth = hu40t();
  const CommandedJointSolver s(truth);
  auto poses = nominal_poses(truth, 30);
  for (auto& p : poses) p.q = s.inverse(p.commanded, truth.tool.length).q;
  const PoseCheck c = check_reached_poses(truth, poses);
  EXPECT_LT(c.max_error, 1e-9);
  EXPECT_LT(c.va.va.value, 2e-9);
}

TEST(PoseCheck, ReaderAndBadInput) {
  const Machine m = hu40t();
  const auto poses = parse_reached_poses(m,
                                         "# commanded and reached\npose,X,Y,Z,B,C,qX,qY,qZ,qB,qC\n"
                                         "1,10,20,30,90,-45,1,2,3,90,-45\n",
                                         "r.csv");
  ASSERT_EQ(poses.size(), 1u);
  EXPECT_EQ(poses[0].line, 3);
  EXPECT_EQ(poses[0].commanded.point, Vec3(10, 20, 30));
  // chain order wCBXfYZt: C, B, X, Y, Z; rotary coordinates C then B
  EXPECT_DOUBLE_EQ(poses[0].q[0], -std::numbers::pi / 4);
  EXPECT_DOUBLE_EQ(poses[0].q[1], std::numbers::pi / 2);
  EXPECT_DOUBLE_EQ(poses[0].q[2], 1.0);
  EXPECT_DOUBLE_EQ(poses[0].commanded.rotary[0], -std::numbers::pi / 4);
  EXPECT_DOUBLE_EQ(poses[0].commanded.rotary[1], std::numbers::pi / 2);
  auto at = [&](const std::string& text) { return error_at([&] { parse_reached_poses(m, text, "r.csv"); }); };
  EXPECT_EQ(at("X,Y,Z,B,C,qX,qY,qZ,qB\n0,0,0,0,0,0,0,0,0\n").field, "qC");
  EXPECT_EQ(at("X,Y,Z,B,C,qX,qY,qZ,qB,qC,extra\n0,0,0,0,0,0,0,0,0,0,0\n").field, "extra");
  EXPECT_EQ(at("X,Y,Z,B,C,qX,qY,qZ,qB,qC\n0,0,0,0,0,0,0,0,0,x\n").line, 2);
  EXPECT_EQ(at("X,Y,Z,B,C,qX,qY,qZ,qB,qC\n").file, "r.csv");  // no pose
  const Machine rrttt = load_machine(kMachines + "rrttt-table-table.yaml");
  EXPECT_EQ(error_at([&] { parse_reached_poses(rrttt, "X,Y,Z,B,C,qX,qY,qZ,qB,qC\n0,0,0,0,0,0,0,0,0,0\n", "r.csv"); })
                .field,
            "A");
}

// ---------------------------------------------------------------- the campaign

Machine long_z(Machine m) {
  m.axes[*m.axis_index('Z')].travel = Travel{-500, 300};
  return m;
}

struct Rehearsal {
  Machine nominal, truth;
  ProbingPlan before, after;
  ArtefactState balls;  // the balls where the simulation put them (ball 2 on the 304.8 mm bar)
};

Rehearsal rehearsal() {
  Rehearsal r;
  ErrorDrawOptions o;
  o.seed = 5;
  o.only = {"EC0Y", "EB0Z", "EA0Z", "EX0C", "EY0C", "EA0C", "EB0C"};
  const ErrorDraw d = draw_errors(long_z(hu40t()), o);
  r.nominal = d.nominal;
  r.truth = d.truth;
  const ProbingPlan plan = read_probing_csv(r.nominal, kPlans + "hu40t-samba-tango.csv");
  SimulationOptions so;  // no noise; the scale bar's balls exactly as identify is told
  so.scale_bars = {{"1", "2", 304.8}};
  const Simulation sim = simulate_probing(r.truth, plan, so);
  r.before = sim.measurements;
  r.balls = sim.truth;
  r.after = simulate_probing(r.nominal, plan, so).measurements;  // a perfect compensation
  return r;
}

TEST(Campaign, DeviationsAreMinusTheTruthsErrorAtTheReadings) {
  const Rehearsal h = rehearsal();
  const CampaignResult r = campaign_report(h.nominal, h.before, h.after, nullptr, nullptr, nullptr, nullptr);
  const ErrorModel truth(h.truth);
  std::size_t balls = 0;
  for (const auto& rec : h.before.records) balls += h.before.features[rec.feature].kind == ProbeFeature::Kind::Ball;
  ASSERT_EQ(r.probed.size(), balls);
  EXPECT_EQ(r.facets, h.before.records.size() - balls);
  double shifted = 0;
  for (const auto& d : r.probed) {
    // The probe centre is on the true ball: actual(q) = true centre, so nominal(q) - nominal centre
    // = -(actual - nominal) + (true centre - nominal centre); only the scale bar's ball 2 moved.
    const ProbingRecord& rec = h.before.records[d.record];
    const Vec3 e = truth.evaluate(rec.q).translation;
    const Vec3 moved = h.balls.ball[rec.feature] - h.before.features[rec.feature].position;
    shifted = std::max(shifted, moved.norm());
    EXPECT_LT((d.before + e - moved).norm(), 1e-9) << d.record;
    EXPECT_LT((d.after - moved).norm(), 1e-9) << d.record;
  }
  EXPECT_GT(r.before.max, 5e-3);
  EXPECT_LT(shifted, 1e-3);  // 304.8003 -> 304.8 mm
  EXPECT_LT(r.after.max, 1e-3);
  EXPECT_FALSE(r.residual_goal.has_value());
  // About each ball's mean: the deviations of a ball sum to zero, and differ from the nominal ones
  // by that ball's mean.
  CampaignOptions mo;
  mo.reference = BallReference::Mean;
  const CampaignResult rm = campaign_report(h.nominal, h.before, h.after, nullptr, nullptr, nullptr, nullptr, mo);
  std::map<std::string, Vec3> sum, mean;
  std::map<std::string, int> n;
  for (const auto& d : r.probed) {  // Eigen leaves a default-constructed vector uninitialised
    mean.try_emplace(d.feature, Vec3::Zero()).first->second += d.before;
    sum.try_emplace(d.feature, Vec3::Zero());
    n[d.feature] += 1;
  }
  for (auto& [id, v] : mean) v /= n[id];
  for (std::size_t i = 0; i < rm.probed.size(); ++i) {
    sum[rm.probed[i].feature] += rm.probed[i].before;
    EXPECT_LT((rm.probed[i].before - (r.probed[i].before - mean[rm.probed[i].feature])).norm(), 1e-12);
  }
  for (const auto& [id, v] : sum) EXPECT_LT(v.norm(), 1e-12) << id;
  EXPECT_LT(rm.before.rms, r.before.rms);
  CampaignOptions o;
  o.probing_noise = 1e-3;
  EXPECT_TRUE(*campaign_report(h.nominal, h.before, h.after, nullptr, nullptr, nullptr, nullptr, o).residual_goal);
  EXPECT_FALSE(*campaign_report(h.nominal, h.after, h.before, nullptr, nullptr, nullptr, nullptr, o).residual_goal);
}

TEST(Campaign, ParametersAgainstTheTruth) {
  const Rehearsal h = rehearsal();
  IdentifiedSummary id;
  id.source = "id.json";
  id.converged = true;
  const double t = h.truth.parameter(*h.truth.parameter_index("EX0C"));
  const double ty = h.truth.parameter(*h.truth.parameter_index("EY0C"));
  id.parameters = {{"EX0C", t + 2e-4, 1e-4, "mm"},   // 2 u: within
                   {"EY0C", ty - 4e-4, 1e-4, "mm"}};  // 4 u: beyond
  const CampaignResult r = campaign_report(h.nominal, h.before, h.after, &id, &h.truth, nullptr, nullptr);
  ASSERT_EQ(r.parameters.size(), 2u);
  EXPECT_NEAR(r.parameters[0].ratio, 2.0, 1e-9);
  EXPECT_NEAR(r.parameters[1].ratio, 4.0, 1e-9);
  EXPECT_NEAR(r.parameters[1].deviation, -4e-4, 1e-15);
  EXPECT_EQ(r.beyond_3u, 1u);
  EXPECT_FALSE(*r.parameter_goal);
  // The other five drawn parameters were not estimated.
  EXPECT_EQ(r.not_estimated.size(), 5u);
  const Json j = to_json(r, h.nominal);
  for (const char* k : {"before", "after", "probed", "identification", "parameters", "not_estimated", "max_ratio",
                        "beyond_3u", "random_poses", "goals", "improvement", "reference"})
    EXPECT_TRUE(j.contains(k)) << k;
  EXPECT_TRUE(j["random_poses"]["before"].is_null());
  EXPECT_EQ(j["parameters"][1]["name"], "EY0C");
}

TEST(Campaign, IdentifiedCentresAndTheIdentifyJsonReadBack) {
  const Rehearsal h = rehearsal();
  IdentificationOptions io;
  io.estimate = {"EC0Y", "EB0Z", "EA0Z", "EX0C", "EY0C", "EA0C", "EB0C"};
  io.scale_bars = {{"1", "2", 304.8}};
  const IdentificationRun run = identify_and_assess(h.nominal, h.before, io, {});
  const IdentifiedSummary id = parse_identification_json(to_json(run).dump(), "id.json");
  ASSERT_EQ(id.parameters.size(), run.result.parameters.size());
  for (std::size_t i = 0; i < id.parameters.size(); ++i) {
    EXPECT_EQ(id.parameters[i].name, run.result.parameters[i].name);
    EXPECT_EQ(id.parameters[i].value, run.result.parameters[i].value);
  }
  EXPECT_EQ(id.converged, run.result.converged);
  EXPECT_NEAR(id.rms_ball, run.result.rms_ball, 1e-15);
  EXPECT_FALSE(id.balls.empty());
  // Noise-free readings: the identification reaches the truth and every parameter is within 3 u
  // (u is tiny but so is the deviation).
  const CampaignResult r = campaign_report(h.nominal, h.before, h.after, &id, &h.truth, nullptr, nullptr);
  for (const auto& p : r.parameters) EXPECT_NEAR(p.value, *p.truth, 1e-7) << p.name;
  EXPECT_TRUE(r.not_estimated.empty());
  CampaignOptions o;
  o.reference = BallReference::Identified;
  const CampaignResult ri = campaign_report(h.nominal, h.before, h.after, &id, &h.truth, nullptr, nullptr, o);
  EXPECT_EQ(ri.probed.size(), r.probed.size());
  // Bad JSON.
  auto at = [](const std::string& t) { return error_at([&] { parse_identification_json(t, "id.json"); }); };
  EXPECT_EQ(at("{").file, "id.json");
  EXPECT_EQ(at("{\"converged\": true}").field, "residuals");
  Json j = to_json(run);
  j["parameters"]["EX0C"]["value"] = "x";
  EXPECT_EQ(at(j.dump()).field, "parameters.EX0C.value");
}

TEST(Campaign, NotTheSamePlan) {
  const Rehearsal h = rehearsal();
  ProbingPlan other = h.after;
  other.records.pop_back();
  EXPECT_EQ(error_at([&] { campaign_report(h.nominal, h.before, other, nullptr, nullptr, nullptr, nullptr); }).file,
            "after");
  other = h.after;
  std::swap(other.records[0], other.records[1]);
  const auto where = error_at([&] { campaign_report(h.nominal, h.before, other, nullptr, nullptr, nullptr, nullptr); });
  EXPECT_EQ(where.line, other.records[0].line);
  const ProbingPlan plan = read_probing_csv(h.nominal, kPlans + "hu40t-samba-tango.csv");
  EXPECT_EQ(error_at([&] { campaign_report(h.nominal, plan, h.after, nullptr, nullptr, nullptr, nullptr); }).file,
            "before");
  CampaignOptions o;
  o.reference = BallReference::Identified;
  EXPECT_EQ(error_at([&] { campaign_report(h.nominal, h.before, h.after, nullptr, nullptr, nullptr, nullptr, o); }).file,
            "before");
}

}  // namespace
}  // namespace mtcal
