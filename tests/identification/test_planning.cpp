// Probing plan design: reach constraints, predicted covariance against an independent normal-matrix
// inverse and against simulate -> identify, the designs' budgets, time by hand, bad inputs.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <limits>
#include <numbers>

#include <Eigen/Cholesky>

#include "mtcal/evaluation/volumetric.hpp"
#include "mtcal/identification/fit_check.hpp"
#include "mtcal/identification/planning.hpp"
#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/io/instruments/probing_plan_file.hpp"
#include "mtcal/kinematics/error_model.hpp"
#include "input_errors.hpp"
#include "mtcal/util/errors.hpp"
#include "examples.hpp"

namespace mtcal {
namespace {

using mtcal::testing::hu40t;
using mtcal::testing::kPlans;

const std::vector<std::string> kLocation{"EC0Y", "EB0Z", "EA0Z", "EX0C", "EY0C",  "EA0C",  "EB0C",
                                         "EX0B", "EZ0B", "EA0B", "EC0B", "EXX.1", "EYY.1", "EZZ.1"};

// The example with Z's travel opened to -500 mm: the paper's plan within reach.
Machine hu40t_long_z() {
  Machine m = hu40t();
  m.axes[*m.axis_index('Z')].travel = Travel{-500, 300};
  return m;
}

IdentificationOptions options(const std::vector<std::string>& names) {
  IdentificationOptions o;
  o.estimate = names;
  o.scale_bars = {{"1", "2", 304.8}};
  return o;
}

using testing::error_message;

TEST(Planning, ThePapersPlansAreWithinReach) {
  // The papers' configurations were measured on real machines: the default reach must allow them.
  const Machine m = hu40t();
  const ProbingPlan p = plan_targets(m, read_probing_csv(m, kPlans + "hu40t-samba-tango.csv"));
  // The example machine file's Z travel (+-300 mm) is an assumption: the paper's plan needs Z down
  // to -445 mm at its larger B tilts. With the travel of Z opened to -500 mm every record passes.
  std::size_t travel = 0;
  for (const auto& r : p.records) {
    const std::string why = reach_violation(m, p, r, {});
    EXPECT_TRUE(why.empty() || why == "travel") << "line " << r.line << ": " << why;
    travel += why == "travel";
  }
  EXPECT_GT(travel, 0u);
  // With the travel of Z opened to -500 mm, every record passes but the four facet touches of
  // indexation 18 (B = -90): in the example file's B direction (+y, ISO 841: the table turns the
  // workpiece by -B) the facet's normal +x then points away from the spindle (-z), so the probe
  // would be behind it. The thesis' machine turns B the other way; the plan copies its angles.
  for (const auto& r : p.records) {
    const std::string why = reach_violation(hu40t_long_z(), p, r, {});
    if (r.indexation == 18)
      EXPECT_EQ(why, "facet side") << "line " << r.line;
    else
      EXPECT_EQ(why, "") << "line " << r.line;
  }
  const Machine v = load_machine(std::string(MTCAL_EXAMPLES_DIR) + "/rrttt-table-table.yaml");
  const ProbingPlan pv = plan_targets(v, read_probing_csv(v, kPlans + "rrttt-viprey-sphere.csv"));
  for (const auto& r : pv.records) EXPECT_EQ(reach_violation(v, pv, r, {}), "") << "line " << r.line;
}

TEST(Planning, ConstraintsByHand) {
  const Machine m = hu40t();
  ProbingPlan p = read_probing_csv(m, kPlans + "hu40t-samba-tango.csv");
  const std::size_t B = *m.axis_index('B');
  ProbingRecord r = p.records.front();  // ball 3 at (160, 160, 177.835)
  // HU40T: tool along machine +z, B about +y. B = 100 deg turns the tool axis seen from the
  // workpiece 100 deg away from the pallet normal: past horizontal, towards the stem.
  r.q[*m.axis_index('C')] = 0;
  r.q[B] = 100 * std::numbers::pi / 180;
  p.records = {r};
  p = plan_targets(m, p);
  EXPECT_EQ(reach_violation(m, p, p.records[0], {}), "stem");
  // 80 deg: allowed with the default 90 deg, refused with 75.
  p.records[0].q[B] = 80 * std::numbers::pi / 180;
  p = plan_targets(m, p);
  EXPECT_EQ(reach_violation(m, p, p.records[0], {}), "");
  ProbeReach tight;
  tight.max_tilt_deg = 75;
  EXPECT_EQ(reach_violation(m, p, p.records[0], tight), "stem");
  // Holder: at 80 deg the holder centre is 50 sin(10 deg) = 8.68 mm above the ball and its rim
  // 20 cos(10 deg) = 19.70 mm below that: 177.835 + 8.68 - 19.70 = 166.8 mm above the table; a
  // table 170 mm up is hit, 160 mm is not.
  ProbeReach table;
  table.table_z = 170;
  EXPECT_EQ(reach_violation(m, p, p.records[0], table), "table");
  table.table_z = 160;
  EXPECT_EQ(reach_violation(m, p, p.records[0], table), "");
  // Travel: X of 160 mm and more is outside when the travel ends at 100 mm.
  Machine short_x = m;
  short_x.axes[*m.axis_index('X')].travel = Travel{-100, 100};
  p.records[0].q[B] = 0;
  p = plan_targets(m, p);
  EXPECT_EQ(reach_violation(short_x, p, p.records[0], {}), "travel");
}

TEST(Planning, CandidatesCountWhatEachConstraintRemoved) {
  const Machine m = hu40t();
  const ProbingPlan art = read_probing_csv(m, kPlans + "hu40t-samba-tango.csv");
  const CandidateGrid g = rotary_grid(m, 30 * std::numbers::pi / 180);
  ASSERT_EQ(g.rotary.size(), 2u);
  EXPECT_EQ(g.rotary[0].size(), 12u);  // C over one turn of its two: -180 ... 150
  EXPECT_EQ(g.rotary[1].size(), 12u);  // B's travel -180 ... 180 is one turn: -180 ... 150
  const CandidateSet c = candidate_configurations(m, art.features, g, {});
  // 144 indexations x (6 balls + 1 facet x 4 pre-move patterns).
  EXPECT_EQ(c.considered, 144u * 10);
  std::size_t removed = 0;
  for (const auto& [name, n] : c.removed) removed += n;
  EXPECT_EQ(removed + c.plan.records.size(), c.considered);
  // B beyond +-90 deg turns the pallet away from the spindle: balls there are refused by the stem
  // rule where the travel does not refuse them first (5 B values x 12 C values x 6 balls = 360).
  EXPECT_EQ(c.removed[0].first, "travel");
  EXPECT_EQ(c.removed[1].first, "stem");
  EXPECT_GE(c.removed[0].second + c.removed[1].second, 360u);
  EXPECT_GT(c.removed[1].second, 0u);
  for (const auto& r : c.plan.records) EXPECT_EQ(reach_violation(m, c.plan, r, {}), "");
  Machine nowhere = m;
  nowhere.axes[*m.axis_index('X')].travel = Travel{1000, 1001};
  const std::string msg = error_message([&] { candidate_configurations(nowhere, art.features, g, {}); });
  EXPECT_NE(msg.find("no candidate configuration is left"), std::string::npos) << msg;
  EXPECT_NE(msg.find("1440 by travel"), std::string::npos) << msg;
}

TEST(Planning, PredictionIsTheInverseNormalMatrix) {
  // Independent of analyse_jacobian's SVD: the Schur complement of the normal matrix, with the
  // Jacobian from numeric differences of the nominal tool point.
  const Machine m = hu40t();
  const ProbingPlan plan = read_probing_csv(m, kPlans + "hu40t-samba-tango.csv");
  IdentificationOptions o = options(kLocation);
  o.sigma_ball = o.sigma_facet = o.sigma_scale_bar = 2e-3;
  const PlanPrediction pred = predict_plan(m, plan, o);
  ASSERT_EQ(pred.parameters.size(), kLocation.size());
  EXPECT_EQ(pred.poses, 76u);

  Machine nominal = m;
  nominal.clear_errors();
  const ProbingPlan t = plan_targets(nominal, plan);
  // Unknowns: 14 parameters, 3 per ball (6 balls), 1 facet offset. Rows: ball 3, facet 1, bar 1.
  const std::size_t p = kLocation.size(), n = p + 6 * 3 + 1;
  std::vector<std::size_t> col(t.features.size());
  std::size_t next = p;
  for (std::size_t f = 0; f < t.features.size(); ++f) {
    col[f] = next;
    next += t.features[f].kind == ProbeFeature::Kind::Ball ? 3 : 1;
  }
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(t.residual_count() + 1), static_cast<Eigen::Index>(n));
  Eigen::Index row = 0;
  const double h = 1e-7;
  for (const auto& r : t.records) {
    const auto& f = t.features[r.feature];
    for (std::size_t k = 0; k < p; ++k) {
      Machine a = nominal, b = nominal;
      a.set_parameter(kLocation[k], h);
      b.set_parameter(kLocation[k], -h);
      const Vec3 d = (ErrorModel(a).actual_pose(r.q, r.dir).t - ErrorModel(b).actual_pose(r.q, r.dir).t) / (2 * h);
      if (f.kind == ProbeFeature::Kind::Ball)
        J.block(row, static_cast<Eigen::Index>(k), 3, 1) = d;
      else
        J(row, static_cast<Eigen::Index>(k)) = f.normal.dot(d);
    }
    if (f.kind == ProbeFeature::Kind::Ball) {
      J.block(row, static_cast<Eigen::Index>(col[r.feature]), 3, 3) = -Eigen::Matrix3d::Identity();
      row += 3;
    } else {
      J(row, static_cast<Eigen::Index>(col[r.feature])) = -1;
      row += 1;
    }
  }
  // The scale bar between balls 1 and 2 (ids "1" and "2" are features 0 and 1 in the file).
  const Vec3 d = (t.features[*t.feature_index("1")].position - t.features[*t.feature_index("2")].position).normalized();
  J.block(row, static_cast<Eigen::Index>(col[*t.feature_index("1")]), 1, 3) = d.transpose();
  J.block(row, static_cast<Eigen::Index>(col[*t.feature_index("2")]), 1, 3) = -d.transpose();
  J /= 2e-3;
  const Eigen::MatrixXd N = J.transpose() * J;
  const Eigen::MatrixXd C = N.ldlt().solve(Eigen::MatrixXd::Identity(N.rows(), N.cols()));
  for (std::size_t k = 0; k < p; ++k)
    EXPECT_NEAR(pred.parameters[k].u, std::sqrt(C(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(k))),
                2e-5 * pred.parameters[k].u)
        << kLocation[k];
}

TEST(Planning, PredictionAgreesWithSimulateIdentify) {
  // 300 runs here (about 3 s); docs/planning.md gives 1,000. The spread's own relative standard
  // error at 300 runs is 1/sqrt(600) = 4 %: 15 % is 3.7 of them.
  const Machine truth = hu40t();
  Machine prior = truth;
  for (const auto& n : kLocation) prior.set_parameter(n, 0.0);
  const ProbingPlan plan = read_probing_csv(truth, kPlans + "hu40t-samba-tango.csv");
  const IdentificationOptions o = options(kLocation);
  const PlanPrediction pred = predict_plan(prior, plan, o);
  // The same runs give the identified machines' VA over a workspace (3 values an axis over the
  // travels), to set beside its first-order uncertainty sqrt(g^T C g).
  const auto workspace = travel_grid(truth, 3);
  const PlanMonteCarlo mc = plan_monte_carlo(truth, prior, plan, o, 300, 11, 0, workspace);
  EXPECT_EQ(mc.failed, 0u);
  for (std::size_t k = 0; k < kLocation.size(); ++k)
    EXPECT_NEAR(mc.stdev[k] / pred.parameters[k].u, 1.0, 0.15) << kLocation[k];
  const VaSensitivity s = va_sensitivity(truth, workspace, o);
  const double u_va = va_uncertainty(s, pred.covariance);
  ASSERT_TRUE(mc.va);
  EXPECT_GT(u_va, 1e-5);  // a few um: not a vanishing check
  EXPECT_NEAR(mc.va_stdev / u_va, 1.0, 0.15) << mc.va_stdev << " mm against " << u_va << " mm";
  // The mean: the VA of the estimated machine is the largest of near-tied pair lengths (three
  // within 0.5 um here), each unbiased: its mean is at or above the machine's VA, by less than u.
  EXPECT_GT(mc.va_mean, s.va - 3 * u_va / std::sqrt(300.0));
  EXPECT_LT(mc.va_mean, s.va + u_va);
}

TEST(Planning, VaGradientAgainstNumericDifferences) {
  // dVA/dtheta (the critical pair's d^T (J_j - J_i)) against central differences of the whole VA
  // recomputed over the workspace: also proves the critical pair is the one that stays critical.
  const Machine m = hu40t();
  const auto workspace = travel_grid(m, 3);
  ASSERT_EQ(workspace.size(), m.axes.size());
  // The grid by hand: X travel [-300, 300] -> -300, 0, 300; C a full turn -> -180, -60, 60 deg.
  const auto x = *m.axis_index('X'), c = *m.axis_index('C');
  EXPECT_EQ(workspace[x], (std::vector<double>{-300, 0, 300}));
  EXPECT_NEAR(workspace[c][1], -std::numbers::pi / 3, 1e-15);
  const IdentificationOptions o = options(kLocation);
  const VaSensitivity s = va_sensitivity(m, workspace, o);
  ASSERT_EQ(s.gradient.size(), static_cast<Eigen::Index>(kLocation.size()));
  auto va_of = [&](const Machine& mm) {
    return volumetric_accuracy(grid_error_map(ErrorModel(mm), workspace).error).va.value;
  };
  EXPECT_NEAR(va_of(m), s.va, 1e-15);
  // The near-critical pairs (within 1 um of the VA) against a comparison of every pair.
  const ErrorMap map = grid_error_map(ErrorModel(m), workspace);
  std::vector<double> near;
  for (std::size_t i = 0; i < map.size(); ++i)
    for (std::size_t j = i + 1; j < map.size(); ++j)
      if (const double l = (map.error[j] - map.error[i]).norm(); l >= s.va - 1e-3) near.push_back(l);
  std::sort(near.rbegin(), near.rend());
  ASSERT_EQ(s.pair_lengths.size(), near.size());
  EXPECT_GT(near.size(), 1u);  // ties: why the uncertainty takes the largest over them
  for (std::size_t k = 0; k < near.size(); ++k) EXPECT_NEAR(s.pair_lengths[k], near[k], 1e-15);
  EXPECT_EQ(s.gradients.cols(), static_cast<Eigen::Index>(near.size()));
  double largest = 0.0;
  for (std::size_t k = 0; k < kLocation.size(); ++k) {
    // 1e-9 (pm, nrad, nm/m): the VA changes by less than the gap to the next pair (0.05 um here).
    const double h = 1e-9;
    Machine a = m, b = m;
    const double v = m.parameter(*m.parameter_index(kLocation[k]));
    a.set_parameter(kLocation[k], v + h);
    b.set_parameter(kLocation[k], v - h);
    const double numeric = (va_of(a) - va_of(b)) / (2 * h);
    EXPECT_NEAR(s.gradient[static_cast<Eigen::Index>(k)], numeric, 2e-4 + 2e-6 * std::abs(numeric))
        << kLocation[k];
    largest = std::max(largest, std::abs(numeric));
  }
  EXPECT_GT(largest, 1.0);  // the scale and tilt terms move the VA by hundreds of mm per unit
  // A machine without errors: no gradient, a clear error.
  Machine clean = m;
  clean.clear_errors();
  const std::string msg = error_message([&] { va_sensitivity(clean, workspace, o); });
  EXPECT_NE(msg.find("must not all vanish"), std::string::npos) << msg;
}

TEST(Planning, ParametersChosenByTheSubsetSearch) {
  // The subset search at every candidate pose against identifiability run on each subset (an
  // independent path: the SVD of the scaled Jacobian, not the incremental Cholesky).
  const Machine m = load_machine(std::string(MTCAL_EXAMPLES_DIR) + "/rrttt-table-table.yaml");
  const ProbingPlan viprey = read_probing_csv(m, kPlans + "rrttt-viprey-sphere.csv");
  const CandidateSet c = candidate_configurations(m, viprey.features, rotary_grid(m, 30 * std::numbers::pi / 180), {});
  SubsetOptions so;
  so.candidates = {"EA0C", "EB0C", "EY0A", "EZ0A", "EB0A", "EC0A", "EXw", "EC0C"};
  so.always = {"EX0C", "EY0C"};
  so.choose = 5;
  const ParameterChoice choice = choose_parameters(m, c.plan, so, IdentificationOptions{});
  EXPECT_EQ(choice.examined, 56u);  // C(8, 5)
  std::size_t full = 0;
  double best = std::numeric_limits<double>::infinity();
  std::vector<std::string> best_names;
  for (unsigned mask = 0; mask < 256; ++mask) {
    if (std::popcount(mask) != 5) continue;
    IdentificationOptions o;
    o.estimate = so.always;
    for (std::size_t i = 0; i < 8; ++i)
      if (mask & (1u << i)) o.estimate.push_back(so.candidates[i]);
    const Identifiability id = identifiability(m, c.plan, o);
    if (!id.unidentifiable.empty()) continue;
    ++full;
    if (id.condition < best) best = id.condition, best_names = o.estimate;
  }
  EXPECT_EQ(choice.full_rank, full);
  EXPECT_GT(full, 0u);
  EXPECT_EQ(choice.estimate, best_names);
  EXPECT_EQ(choice.chosen.size(), 5u);
  EXPECT_EQ(std::vector<std::string>(choice.estimate.begin(), choice.estimate.begin() + 2), so.always);
  // None identifiable: the null-space combination is named.
  so.candidates = {"EXw", "EYw"};
  so.choose = 1;
  const std::string msg = error_message([&] { choose_parameters(m, c.plan, so, IdentificationOptions{}); });
  EXPECT_NE(msg.find("none of the 2 subsets of 1"), std::string::npos) << msg;
  EXPECT_NE(msg.find("EXw = 1 ball S x"), std::string::npos) << msg;
}

TEST(Planning, BallRegionCandidates) {
  // Positions by hand: x and y from -100 to 100 every 100 mm -> 3 x 3, x fastest.
  BallRegion r;
  r.x_min = r.y_min = -100;
  r.x_max = r.y_max = 100;
  r.z = 30;
  r.spacing = 100;
  const auto balls = region_balls(r);
  ASSERT_EQ(balls.size(), 9u);
  EXPECT_EQ(balls[0].id, "R1");
  EXPECT_EQ(balls[5].id, "R6");
  EXPECT_EQ(balls[5].position, Vec3(100, 0, 30));
  EXPECT_EQ(balls[5].kind, ProbeFeature::Kind::Ball);
  // A side that is not a multiple of the spacing: its end is left out.
  r.x_max = 150;
  EXPECT_EQ(region_balls(r).size(), 9u);
  r.x_max = 100;
  // Reach: one candidate per position and indexation; what the constraints keep passes them.
  const Machine m = load_machine(std::string(MTCAL_EXAMPLES_DIR) + "/rrttt-table-table.yaml");
  const CandidateGrid g = rotary_grid(m, 30 * std::numbers::pi / 180);
  std::size_t indexations = 1;
  for (const auto& v : g.rotary) indexations *= v.size();
  ProbeReach reach;
  reach.holder_radius = 40;  // a wide holder: the table rule removes the tilted poses of these low balls
  const CandidateSet c = candidate_configurations(m, balls, g, reach);
  EXPECT_EQ(c.considered, 9 * indexations);
  std::size_t removed = 0;
  for (const auto& [name, n] : c.removed) removed += n;
  EXPECT_EQ(c.plan.records.size() + removed, c.considered);
  EXPECT_GT(c.removed[3].second, 0u) << "table";
  for (const auto& rec : c.plan.records) EXPECT_EQ(reach_violation(m, c.plan, rec, reach), "");
  // A design over them: every pose on a region ball, the parameters predicted.
  DesignOptions d;
  d.model.estimate = {"EX0C", "EY0C", "EA0C", "EB0C", "EY0A", "EZ0A", "EB0A", "EC0A"};
  d.poses = 16;
  const PlanDesign design = design_plan(m, c.plan, d);
  EXPECT_EQ(design.plan.records.size(), 16u);
  for (const auto& e : design.prediction.parameters) EXPECT_TRUE(std::isfinite(e.u) && e.u > 0) << e.name;
  const ProbingPlan again = parse_probing_csv(m, probing_csv(m, design.plan), "designed");
  EXPECT_EQ(again.records.size(), 16u);
  EXPECT_EQ(again.features[again.records[0].feature].id.front(), 'R');
  // Bad regions.
  r.spacing = 0;
  EXPECT_NE(error_message([&] { region_balls(r); }).find("spacing > 0"), std::string::npos);
  r.spacing = 100;
  r.x_min = 200;
  EXPECT_NE(error_message([&] { region_balls(r); }).find("min <= max"), std::string::npos);
  r.x_min = -100;
  r.spacing = 0.5;
  EXPECT_NE(error_message([&] { region_balls(r); }).find("at most 10,000"), std::string::npos);
  r.spacing = 100;
  ProbeFeature taken;
  taken.id = "R2";
  EXPECT_NE(error_message([&] { region_balls(r, {taken}); }).find("'R2' is already"), std::string::npos);
}

TEST(Planning, FewestPosesForAVaTarget) {
  const Machine m = hu40t();
  const ProbingPlan paper = read_probing_csv(m, kPlans + "hu40t-samba-tango.csv");
  const CandidateSet c = candidate_configurations(m, paper.features, rotary_grid(m, 45 * std::numbers::pi / 180), {});
  DesignOptions d;
  d.model = options(kLocation);
  const VaSensitivity s = va_sensitivity(m, travel_grid(m, 3), d.model);
  d.va_gradients = s.gradients;
  // Below the best reachable: the error names it.
  d.target_va_u = 1e-9;
  std::string msg = error_message([&] { design_plan(m, c.plan, d); });
  EXPECT_NE(msg.find("best reachable"), std::string::npos) << msg;
  EXPECT_NE(msg.find("VA"), std::string::npos) << msg;
  // Twice the best reachable: met, with fewer poses than every candidate, and the reported u
  // is sqrt(g^T C g) of the design's own prediction.
  const PlanPrediction all = predict_plan(m, c.plan, d.model);
  const double best = va_uncertainty(s, all.covariance);
  d.target_va_u = 2 * best;
  const PlanDesign design = design_plan(m, c.plan, d);
  EXPECT_TRUE(design.target_met);
  EXPECT_NEAR(design.va_u_best, best, 1e-9 * best);
  EXPECT_LE(design.va_u, 2 * best * (1 + 1e-6));
  EXPECT_NEAR(design.va_u, va_uncertainty(s, design.prediction.covariance), 1e-12);
  EXPECT_LT(design.plan.records.size(), c.plan.records.size() / 2);
  // One pose fewer (the last removed) would miss the target: the count is tight for the removal.
  ProbingPlan fewer = design.plan;
  bool any_meets = false;
  for (std::size_t i = 0; i < design.plan.records.size(); ++i) {
    fewer.records = design.plan.records;
    fewer.records.erase(fewer.records.begin() + static_cast<std::ptrdiff_t>(i));
    try {
      any_meets = any_meets || va_uncertainty(s, predict_plan(m, fewer, d.model).covariance) <= 2 * best * (1 - 1e-6);
    } catch (const InputError&) {
    }
  }
  EXPECT_FALSE(any_meets);
  // The c-optimal criterion with a number of poses: no larger a VA uncertainty than D's design.
  d.target_va_u = 0;
  d.poses = 30;
  d.criterion = DesignCriterion::Va;
  const PlanDesign cva = design_plan(m, c.plan, d);
  d.criterion = DesignCriterion::D;
  const PlanDesign cd = design_plan(m, c.plan, d);
  EXPECT_EQ(cva.criterion, "VA");
  EXPECT_LE(cva.va_u, cd.va_u * (1 + 1e-9));
}

TEST(Planning, DesignOfAGivenSize) {
  const Machine m = hu40t();
  const ProbingPlan paper = read_probing_csv(m, kPlans + "hu40t-samba-tango.csv");
  const CandidateSet c = candidate_configurations(m, paper.features, rotary_grid(m, 30 * std::numbers::pi / 180), {});
  DesignOptions d;
  d.model = options(kLocation);
  d.poses = 20;
  PlanDesign design;
  try {
    design = design_plan(m, c.plan, d);
  } catch (const std::exception& e) {
    ADD_FAILURE() << e.what();
  }
  EXPECT_EQ(design.plan.records.size(), 20u);
  EXPECT_EQ(design.greedy_poses, 20u);
  // The criterion is log det of the parameters' covariance (unit-norm columns): the exchange
  // only ever lowers it, and the final design's is no larger than the greedy one's.
  for (const auto& e : design.prediction.parameters) EXPECT_TRUE(std::isfinite(e.u) && e.u > 0) << e.name;
  // The paper's first 20 poses cannot do it: balls 1 and 2 (the scale bar) come later.
  ProbingPlan first20 = paper;
  first20.records.resize(20);
  const std::string why = error_message([&] { predict_plan(m, first20, d.model); });
  EXPECT_NE(why.find("never probed"), std::string::npos) << why;
  // Plan file round trip: what simulate and identify read.
  const ProbingPlan again = parse_probing_csv(m, probing_csv(m, design.plan), "designed");
  EXPECT_EQ(again.records.size(), 20u);
  const PlanPrediction p2 = predict_plan(m, again, d.model);
  for (std::size_t k = 0; k < kLocation.size(); ++k)
    EXPECT_NEAR(p2.parameters[k].u, design.prediction.parameters[k].u, 1e-9 * design.prediction.parameters[k].u);
}

TEST(Planning, FewestPosesForThePapersUncertainties) {
  const Machine m = hu40t_long_z();  // the paper's plan within reach (ThePapersPlansAreWithinReach)
  const ProbingPlan paper = read_probing_csv(m, kPlans + "hu40t-samba-tango.csv");
  DesignOptions d;
  d.model = options(kLocation);
  const PlanPrediction ref = predict_plan(m, paper, d.model);
  for (const auto& e : ref.parameters) d.target_u.emplace_back(e.name, e.u);
  const CandidateSet c = candidate_configurations(m, paper.features, rotary_grid(m, 30 * std::numbers::pi / 180), {});
  const PlanDesign design = design_plan(m, c.plan, d);
  EXPECT_TRUE(design.target_met);
  for (std::size_t k = 0; k < kLocation.size(); ++k)
    EXPECT_LE(design.prediction.parameters[k].u, ref.parameters[k].u * (1 + 1e-6)) << kLocation[k];
  // The acceptance figure of issue 31: at least 30 % fewer poses than the paper's 76.
  EXPECT_LE(design.plan.records.size(), 53u) << design.plan.records.size();
}

TEST(Planning, BadBudgetsAndParameters) {
  const Machine m = hu40t();
  const ProbingPlan paper = read_probing_csv(m, kPlans + "hu40t-samba-tango.csv");
  const CandidateSet c = candidate_configurations(m, paper.features, rotary_grid(m, 45 * std::numbers::pi / 180), {});
  DesignOptions d;
  d.model = options(kLocation);
  // A target below what every candidate together gives: the best reachable is named.
  d.target_u = {{"EX0C", 1e-9}};
  std::string msg = error_message([&] { design_plan(m, c.plan, d); });
  EXPECT_NE(msg.find("cannot be met"), std::string::npos) << msg;
  EXPECT_NE(msg.find("EX0C: target 1e-09 mm, best reachable"), std::string::npos) << msg;
  // A target for a parameter not estimated.
  d.target_u = {{"EZ0C", 1e-3}};
  msg = error_message([&] { design_plan(m, c.plan, d); });
  EXPECT_NE(msg.find("'EZ0C' is not one of the estimated parameters"), std::string::npos) << msg;
  // No budget, and more poses than candidates.
  d.target_u.clear();
  msg = error_message([&] { design_plan(m, c.plan, d); });
  EXPECT_NE(msg.find("expected a budget"), std::string::npos) << msg;
  d.poses = c.plan.records.size() + 1;
  msg = error_message([&] { design_plan(m, c.plan, d); });
  EXPECT_NE(msg.find("expected at most the"), std::string::npos) << msg;
  // Not identifiable whatever the poses: the workpiece's x position with uncalibrated balls is the
  // balls' x (identifiability's null-space combination).
  d.poses = 10;
  d.model = options({"EX0C", "EXw"});
  msg = error_message([&] { design_plan(m, c.plan, d); });
  EXPECT_NE(msg.find("EXw is not identifiable"), std::string::npos) << msg;
  EXPECT_NE(msg.find("EXw = "), std::string::npos) << msg;
}

TEST(Planning, TimeByHand) {
  // One ball of the RRTTT (chain C A Y X Z; Z +z, travel [-500, 0]: the safe retract Z 0) probed at
  // two indexations, the program's moves added up by hand.
  const Machine m = load_machine(std::string(MTCAL_EXAMPLES_DIR) + "/rrttt-table-table.yaml");
  ProbingPlan p;
  p.features.push_back({"1", ProbeFeature::Kind::Ball, Vec3(0, 0, 0), Vec3::Zero()});
  const double deg = std::numbers::pi / 180;
  for (const auto& [c, z] : {std::pair{0.0, -300.0}, std::pair{90 * deg, -290.0}}) {
    ProbingRecord r;
    r.q = {c, 0.0, 10.0, 20.0, z};  // C A Y X Z
    r.dir.assign(5, 0);
    p.records.push_back(r);
  }
  ProbeCycle c;
  c.ball_diameter = 20;  // rho = (20 + 2) / 2 = 11 mm from the centre at the contact
  c.tip_diameter = 2;
  c.approach = 2;
  c.overtravel = 1;
  c.clearance = 5;  // 16 mm above the centre between touches
  c.touches_per_ball = 5;
  TimingOptions o;
  o.rapid = 6000;         // 100 mm/s
  o.move_feed = 600;      // 10 mm/s
  o.probe_feed = 60;      // 1 mm/s
  o.rotary_speed = 3600;  // 60 deg/s
  o.settle = 1;
  const TimeEstimate t = estimate_time(m, p, c, o);
  // Each touch: 2 mm probing at 1 mm/s and the 2 mm retract at 10 mm/s.
  EXPECT_NEAR(t.probing, 10 * (2.0 + 0.2), 1e-12);
  EXPECT_EQ(t.touches, 10u);
  // C 0 -> 90 deg at 60 deg/s, and the settle.
  EXPECT_NEAR(t.indexing, 1.5 + 1.0, 1e-12);
  EXPECT_EQ(t.indexations, 2u);
  // From the first record's G0 over its pole at Z 0: G0 down to the clearance level Z -300+16
  // (284 mm at 100 mm/s), then G1 at 10 mm/s:
  //   record 1: down to the pole's start Z -300+13: 3 mm;
  //   touch +X: up 3 mm to Z -284, over 13 mm, down 16 mm: 32 mm;
  //   touch -X: up 16, over 26, down 16: 58 mm;
  //   touch +Y: up 16, over sqrt(13^2 + 13^2), down 16;
  //   touch -Y: up 16, over 26, down 16: 58 mm.
  const double ball = 32 + 58 + (32 + std::sqrt(338.0)) + 58;
  double moves = 284.0 / 100 + (3 + ball) / 10;
  // Record 2: G0 up to Z 0 from Z -300 (300 mm at 100 mm/s), G0 over the pole from Y -3 to Y 10
  // (13 mm), G0 down to Z -290+16 (274 mm), G1 down 3 mm, the same four touches; the final G0 up
  // from Z -290.
  moves += 300.0 / 100 + 13.0 / 100 + 274.0 / 100 + (3 + ball) / 10 + 290.0 / 100;
  EXPECT_NEAR(t.moves, moves, 1e-9);
  EXPECT_NEAR(t.total, t.moves + t.probing + t.indexing, 1e-12);
  // The moves at the move feed: ten times slower G1 moves take ten times longer.
  o.move_feed = 60;
  const TimeEstimate slow = estimate_time(m, p, c, o);
  EXPECT_NEAR(slow.moves, (3 + 3 + 2 * ball) / 1 + 2.84 + 3.0 + 0.13 + 2.74 + 2.9, 1e-9);
  EXPECT_NEAR(slow.probing, 10 * (2.0 + 2.0), 1e-12);
  o.move_feed = 0;
  EXPECT_NE(error_message([&] { estimate_time(m, p, c, o); }).find("move feed"), std::string::npos);
}

// identify's fit check (identification/fit_check.hpp), which the closed loop's identify --require-fit
// uses to refuse a model that does not reach the probe log (here beside the plan, whose sigma it takes).
TEST(FitCheck, BoundIsTheChiSquareQuantile) {
  // Against the chi-square table's 99.9 % quantiles (NIST/SEMATECH e-Handbook of Statistical
  // Methods, 1.3.6.7.4, upper critical values): k = 10: 29.588, 30: 59.703, 100: 149.449. The bound
  // on sigma0 is sqrt(chi2 / k); Wilson-Hilferty is within 1 % of it from k = 10 on.
  for (const auto& [k, chi2] : {std::pair{10, 29.588}, std::pair{30, 59.703}, std::pair{100, 149.449}}) {
    IdentificationResult r;
    r.unknowns = 20;
    r.residuals = 20 + static_cast<std::size_t>(k);
    r.sigma0 = 1.0;
    const FitCheck f = check_fit(r);
    EXPECT_EQ(f.degrees_of_freedom, static_cast<std::size_t>(k));
    EXPECT_NEAR(f.bound, std::sqrt(chi2 / k), 0.01 * std::sqrt(chi2 / k)) << k;
    EXPECT_FALSE(f.poor);
    r.sigma0 = 1.01 * f.bound;
    EXPECT_TRUE(check_fit(r).poor) << k;
    r.sigma0 = std::numeric_limits<double>::quiet_NaN();
    EXPECT_TRUE(check_fit(r).poor) << "a NaN sigma0 is never a good fit";
  }
  IdentificationResult none;
  none.residuals = none.unknowns = 5;
  EXPECT_FALSE(check_fit(none).poor);
  EXPECT_TRUE(std::isinf(check_fit(none).bound));
  EXPECT_THROW(check_fit(none, 0.3), InputError);
}

}  // namespace
}  // namespace mtcal
