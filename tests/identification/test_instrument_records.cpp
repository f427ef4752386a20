// Ballbar circles and laser lines as measurement records of the identification: the file, their
// Jacobian rows against numeric differences, recovery from simulated readings, and what they add
// to probing (docs/identification.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <numbers>

#include <Eigen/Cholesky>

#include "mtcal/identification/identification.hpp"
#include "mtcal/identification/planning.hpp"
#include "mtcal/io/instruments/probing_plan_file.hpp"
#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/kinematics/error_model.hpp"
#include "input_errors.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {
namespace {

// The 3-axis example (wXYfZt): three squarenesses and the X and Z scales (its Y positioning error is a table).
const std::vector<std::string> kSquareScale{"EC0Y", "EA0Z", "EB0Z", "EXX.1", "EZZ.1"};

Machine vmc() { return load_machine(std::string(MTCAL_EXAMPLES_DIR) + "/vmc-3axis.yaml"); }

// The nominal tool point at mid-travel: the artefacts are placed about it.
Vec3 middle(const Machine& m) {
  Machine nominal = m;
  nominal.clear_errors();
  const std::vector<double> q{0.0, 0.0, -250.0};
  return ErrorModel(nominal).nominal_pose(q).t;
}

ProbingRecord record(const Machine& m, std::size_t feature, double at = 0.0) {
  ProbingRecord r;
  r.indexation = 1;
  r.q.assign(m.axes.size(), 0.0);
  r.dir.assign(m.axes.size(), 0);
  r.feature = feature;
  r.at = at;
  return r;
}

// Two uncalibrated balls 400 mm apart with a scale bar between them: probing alone.
ProbingPlan probing(const Machine& m) {
  const Vec3 c = middle(m);
  ProbingPlan p;
  p.features.push_back({"1", ProbeFeature::Kind::Ball, c + Vec3(-200, -100, -100), Vec3::Zero(), 0.0});
  p.features.push_back({"2", ProbeFeature::Kind::Ball, c + Vec3(200, 100, 100), Vec3::Zero(), 0.0});
  p.records = {record(m, 0), record(m, 1)};
  return p;
}

// The same, and ballbar circles of 150 mm in XY, YZ and ZX about the middle (12 points each, ISO
// 230-4) and a laser line along X (7 targets over 600 mm, ISO 230-2).
ProbingPlan with_instruments(const Machine& m) {
  ProbingPlan p = probing(m);
  const Vec3 c = middle(m);
  for (const auto& [id, normal] : {std::pair{"XY", Vec3(0, 0, 1)}, {"YZ", Vec3(1, 0, 0)}, {"ZX", Vec3(0, 1, 0)}}) {
    p.features.push_back({id, ProbeFeature::Kind::Ballbar, c, normal, 150.0});
    for (int i = 0; i < 12; ++i) p.records.push_back(record(m, p.features.size() - 1, i * std::numbers::pi / 6));
  }
  p.features.push_back({"LX", ProbeFeature::Kind::Laser, c + Vec3(-300, 0, 0), Vec3(1, 0, 0), 0.0});
  for (int i = 0; i <= 6; ++i) p.records.push_back(record(m, p.features.size() - 1, 100.0 * i));
  return p;
}

IdentificationOptions options() {
  IdentificationOptions o;
  o.estimate = kSquareScale;
  o.scale_bars = {{"1", "2", 0.0}};
  o.scale_bars[0].length = 2 * std::sqrt(200.0 * 200 + 100 * 100 + 100 * 100);
  return o;
}

TEST(InstrumentRecords, FileRoundTripAndTargets) {
  const Machine m = vmc();
  Simulation sim = simulate_probing(m, with_instruments(m), {1e-3, 0.0, 3, {}});
  const ProbingPlan& meas = sim.measurements;
  const std::string text = probing_csv(m, meas);
  EXPECT_NE(text.find(",radius,angle,along,reading\n"), std::string::npos) << text.substr(0, 300);
  const ProbingPlan back = parse_probing_csv(m, text, "meas.csv");
  ASSERT_EQ(back.records.size(), meas.records.size());
  for (std::size_t i = 0; i < meas.records.size(); ++i) {
    EXPECT_EQ(back.records[i].reading, meas.records[i].reading) << i;  // shortest round-trip form
    EXPECT_NEAR(back.records[i].at, meas.records[i].at, 1e-15 * (1 + std::abs(meas.records[i].at))) << i;
    EXPECT_EQ(back.records[i].q, meas.records[i].q) << i;
  }
  EXPECT_EQ(back.features[2].kind, ProbeFeature::Kind::Ballbar);
  EXPECT_EQ(back.features[2].radius, 150.0);
  EXPECT_EQ(back.features[5].kind, ProbeFeature::Kind::Laser);
  // A plan's targets put the nominal tool point on the circle and on the beam.
  Machine nominal = m;
  nominal.clear_errors();
  const ErrorModel em(nominal);
  const ProbingPlan t = plan_targets(m, with_instruments(m));
  const Vec3 c = middle(m);
  for (const auto& r : t.records) {
    const ProbeFeature& f = t.features[r.feature];
    const Vec3 p = em.nominal_pose(r.q).t;
    if (f.kind == ProbeFeature::Kind::Ballbar) {
      EXPECT_NEAR((p - c).norm(), 150.0, 1e-9);
      EXPECT_NEAR((p - c).dot(f.normal), 0.0, 1e-9);
    }
    if (f.kind == ProbeFeature::Kind::Laser) {
      EXPECT_NEAR(f.normal.dot(p - f.position), r.at, 1e-9);
    }
  }
  // The ballbar at angle 90 deg in YZ is at +z of the pivot (from +y towards +z).
  EXPECT_NEAR(em.nominal_pose(t.records[2 + 12 + 3].q).t.z() - c.z(), 150.0, 1e-9);
  // Bad files, located.
  const std::string head = "indexation,feature,kind,x,y,z,nx,ny,nz,dirX,dirY,dirZ,radius,angle,along\n";
  auto msg = testing::error_message([&] { parse_probing_csv(m, head + "1,B,ballbar,0,0,0,1,1,0,,,,100,0,\n", "p.csv"); });
  EXPECT_NE(msg.find("p.csv:2"), std::string::npos) << msg;
  EXPECT_NE(msg.find("plane normal"), std::string::npos) << msg;
  msg = testing::error_message([&] { parse_probing_csv(m, head + "1,B,ballbar,0,0,0,0,0,1,,,,,0,\n", "p.csv"); });
  EXPECT_NE(msg.find("radius"), std::string::npos) << msg;
  msg = testing::error_message([&] { parse_probing_csv(m, head + "1,L,laser,0,0,0,2,0,0,,,,,,0\n", "p.csv"); });
  EXPECT_NE(msg.find("beam direction"), std::string::npos) << msg;
  msg = testing::error_message([&] { parse_probing_csv(m, head + "1,L,laser,0,0,0,1,0,0,,,,,,\n", "p.csv"); });
  EXPECT_NE(msg.find("along"), std::string::npos) << msg;
  msg = testing::error_message([&] {
    parse_probing_csv(m, "indexation,feature,kind,x,y,z,nx,ny,nz,radius,angle,X,Y,Z\n1,B,ballbar,0,0,0,0,0,1,100,0,1,2,3\n", "p.csv");
  });
  EXPECT_NE(msg.find("reading"), std::string::npos) << msg;
}

TEST(InstrumentRecords, JacobianRowsAgainstNumericDifferences) {
  // predict_plan's covariance (the analytic rows through analyse_jacobian) against the inverse
  // normal matrix of rows from central differences of the readings' definitions:
  //   ballbar |p - c| + delta, laser d . p - o, ball p - c, scale bar |c1 - c2|.
  const Machine m = vmc();
  const ProbingPlan plan = with_instruments(m);
  const IdentificationOptions o = options();
  const PlanPrediction pred = predict_plan(m, plan, o);
  ASSERT_EQ(pred.parameters.size(), kSquareScale.size());
  Machine nominal = m;
  nominal.clear_errors();
  const ProbingPlan t = plan_targets(nominal, plan);
  // Unknowns: 6 parameters, balls 3 + 3, ballbars 3 each (pivot in its plane, length offset), laser 1.
  const std::size_t np = kSquareScale.size(), n = np + 6 + 3 * 3 + 1;
  const std::vector<std::size_t> col{np, np + 3, np + 6, np + 9, np + 12, np + 15};
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(t.residual_count() + 1), static_cast<Eigen::Index>(n));
  const double h = 1e-6;
  Eigen::Index row = 0;
  for (const auto& r : t.records) {
    const ProbeFeature& f = t.features[r.feature];
    // The reading as a function of the tool point and of the feature's unknowns u (in-plane pivot
    // coordinates and length offset; laser offset).
    auto reading = [&](const Vec3& p, const Eigen::Vector3d& u) -> Eigen::Vector3d {
      if (f.kind == ProbeFeature::Kind::Ball) return p - u;
      if (f.kind == ProbeFeature::Kind::Laser) return Eigen::Vector3d(f.normal.dot(p) - u[0], 0, 0);
      const int k = f.normal.z() == 1 ? 2 : f.normal.x() == 1 ? 0 : 1;  // XY, YZ, ZX
      Vec3 c = f.position;
      c[(k + 1) % 3] = u[0];
      c[(k + 2) % 3] = u[1];
      return Eigen::Vector3d((p - c).norm() + u[2], 0, 0);
    };
    const Eigen::Index rows = f.kind == ProbeFeature::Kind::Ball ? 3 : 1;
    Eigen::Vector3d u0 = f.position;
    if (f.kind == ProbeFeature::Kind::Laser) u0 = Eigen::Vector3d(f.normal.dot(f.position), 0, 0);
    if (f.kind == ProbeFeature::Kind::Ballbar) {
      const int k = f.normal.z() == 1 ? 2 : f.normal.x() == 1 ? 0 : 1;
      u0 = Eigen::Vector3d(f.position[(k + 1) % 3], f.position[(k + 2) % 3], 0.0);
    }
    const Vec3 p0 = ErrorModel(nominal).actual_pose(r.q, r.dir).t;
    for (std::size_t k = 0; k < np; ++k) {
      Machine a = nominal, b = nominal;
      a.set_parameter(kSquareScale[k], h);
      b.set_parameter(kSquareScale[k], -h);
      const Eigen::Vector3d d = (reading(ErrorModel(a).actual_pose(r.q, r.dir).t, u0) -
                                 reading(ErrorModel(b).actual_pose(r.q, r.dir).t, u0)) / (2 * h);
      J.block(row, static_cast<Eigen::Index>(k), rows, 1) = d.head(rows);
    }
    const Eigen::Index unknowns = f.kind == ProbeFeature::Kind::Laser ? 1 : 3;
    for (Eigen::Index j = 0; j < unknowns; ++j) {
      Eigen::Vector3d a = u0, b = u0;
      a[j] += 1e-3;
      b[j] -= 1e-3;
      J.block(row, static_cast<Eigen::Index>(col[r.feature]) + j, rows, 1) = ((reading(p0, a) - reading(p0, b)) / 2e-3).head(rows);
    }
    row += rows;
  }
  const Vec3 d = (t.features[0].position - t.features[1].position).normalized();
  J.block(row, static_cast<Eigen::Index>(col[0]), 1, 3) = d.transpose();
  J.block(row, static_cast<Eigen::Index>(col[1]), 1, 3) = -d.transpose();
  J /= 1e-3;
  const Eigen::MatrixXd N = J.transpose() * J;
  const Eigen::MatrixXd C = N.ldlt().solve(Eigen::MatrixXd::Identity(N.rows(), N.cols()));
  for (std::size_t k = 0; k < np; ++k) {
    const double u = std::sqrt(C(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(k)));
    EXPECT_GT(u, 0.0);
    EXPECT_NEAR(pred.parameters[k].u, u, 1e-4 * u) << kSquareScale[k];
  }
}

TEST(InstrumentRecords, CirclesAndALaserLineIdentifyWhatProbingCannot) {
  const Machine truth = vmc();
  const IdentificationOptions o = options();
  // Probing two uncalibrated balls on a 3-axis machine: each ball is seen at one configuration,
  // so only the bar's length is a reading on the machine: one combination of the parameters (the
  // first requested, EC0Y, stands for it), the other four are not determined.
  const Identifiability alone = identifiability(truth, probing(truth), o);
  EXPECT_EQ(alone.identifiable, std::vector<std::string>{"EC0Y"});
  for (const char* p : {"EA0Z", "EB0Z", "EXX.1", "EZZ.1"})
    EXPECT_NE(std::find(alone.unidentifiable.begin(), alone.unidentifiable.end(), p), alone.unidentifiable.end()) << p;
  // With the circles (squareness and the scales' differences, ISO 230-4) and the laser line (the
  // X scale, ISO 230-2): all five.
  const Identifiability both = identifiability(truth, with_instruments(truth), o);
  EXPECT_TRUE(both.unidentifiable.empty()) << both.unidentifiable.size() << " " << both.null_directions.front();
  EXPECT_EQ(both.identifiable.size(), kSquareScale.size());
  // Recovery from simulated readings (1 um noise, the artefacts 5 um off their nominal places and
  // lengths): every parameter within 3 u of the truth.
  Machine prior = truth;
  for (const auto& p : kSquareScale) prior.set_parameter(p, 0.0);
  SimulationOptions so;
  so.noise = 1e-3;
  so.artefact_error = 5e-3;
  so.seed = 5;
  so.scale_bars = o.scale_bars;
  const Simulation sim = simulate_probing(truth, with_instruments(truth), so);
  const IdentificationResult r = identify(prior, sim.measurements, o);
  EXPECT_TRUE(r.converged) << r.termination;
  ASSERT_EQ(r.parameters.size(), kSquareScale.size());
  for (const auto& e : r.parameters) {
    const double t = truth.parameter(*truth.parameter_index(e.name));
    EXPECT_GT(std::abs(t), 0.0) << e.name;  // a parameter of the example that is not zero
    EXPECT_LT(std::abs(e.value - t), 3 * e.u) << e.name << ": " << e.value << " against " << t << ", u " << e.u;
  }
  EXPECT_GT(r.rms_ballbar, 0.0);
  EXPECT_LT(r.rms_ballbar, 3e-3);
  EXPECT_GT(r.rms_laser, 0.0);
  EXPECT_LT(r.rms_laser, 3e-3);
  // The identified pivots and length offsets: near the simulated truth (5 um off nominal).
  for (std::size_t f = 2; f < 5; ++f) EXPECT_NEAR(r.artefact.offset[f], sim.truth.offset[f], 2e-3) << f;
  // An artefact's own circles and lines are not candidates (plan offers its own: InstrumentCandidates).
  const std::string msg = testing::error_message(
      [&] { candidate_configurations(truth, with_instruments(truth).features, CandidateGrid{}, ProbeReach{}); });
  EXPECT_NE(msg.find("not proposed"), std::string::npos) << msg;
}

// The candidates of plan --ballbar 150 --laser X,Z on the 3-axis example beside the two balls.
InstrumentCandidates circles_and_lines() {
  InstrumentCandidates c;
  c.ballbar_radii = {150.0};
  c.laser_axes = {"X", "Z"};
  return c;
}

TEST(InstrumentRecords, CandidatesLaidOutInTheTravel) {
  const Machine m = vmc();
  const ProbingPlan balls = probing(m);
  const CandidateSet cs = candidate_configurations(m, balls.features, rotary_grid(m, 1.0), ProbeReach{}, circles_and_lines());
  // The tool point's travel box is 800 x 500 x 500 mm: a 150 mm circle fits every plane, 3 x 3
  // pivots each (27 circles), and two lines; with the two balls 29 + 2 candidates, every one kept.
  EXPECT_EQ(cs.considered, 2u + 27u + 2u);
  EXPECT_EQ(plan_poses(cs.plan), 31u);
  EXPECT_EQ(cs.plan.records.size(), 2u + 27u * 36u + 2u * 11u);
  Machine nominal = m;
  nominal.clear_errors();
  const ErrorModel em(nominal);
  std::size_t circles = 0;
  for (const auto& r : cs.plan.records) {
    for (std::size_t k = 0; k < m.axes.size(); ++k) {
      EXPECT_GE(r.q[k], m.axes[k].travel->min - 1e-6);
      EXPECT_LE(r.q[k], m.axes[k].travel->max + 1e-6);
    }
    const ProbeFeature& f = cs.plan.features[r.feature];
    if (f.kind == ProbeFeature::Kind::Ballbar) {
      EXPECT_NEAR((em.nominal_pose(r.q).t - f.position).norm(), 150.0, 1e-9) << f.id;
      circles += r.at == 0.0;
    }
  }
  EXPECT_EQ(circles, 27u);
  // The X line over the whole X travel (800 mm), 11 targets.
  const auto setups = instrument_setups(m, cs.plan);
  ASSERT_EQ(setups.size(), 29u);
  EXPECT_EQ(setups[27].id, "LX");
  EXPECT_NEAR(setups[27].to - setups[27].from, 800.0, 1e-9);
  EXPECT_EQ(setups[27].readings, 11u);
  EXPECT_EQ(setups[0].plane, "XY");
  EXPECT_NE(describe_setup(setups[0]).find("radius 150 mm, 36 readings"), std::string::npos) << describe_setup(setups[0]);
  EXPECT_EQ(probing_part(cs.plan).records.size(), 2u);
  // Bad input, named by its value.
  InstrumentCandidates big;
  big.ballbar_radii = {300.0};  // 600 mm: only X has it
  std::string msg = testing::error_message(
      [&] { candidate_configurations(m, balls.features, rotary_grid(m, 1.0), ProbeReach{}, big); });
  EXPECT_NE(msg.find("ballbar radius"), std::string::npos) << msg;
  EXPECT_NE(msg.find("300"), std::string::npos) << msg;
  EXPECT_NE(msg.find("no plane"), std::string::npos) << msg;
  InstrumentCandidates axis;
  axis.laser_axes = {"Q"};
  msg = testing::error_message(
      [&] { candidate_configurations(m, balls.features, rotary_grid(m, 1.0), ProbeReach{}, axis); });
  EXPECT_NE(msg.find("laser axis"), std::string::npos) << msg;
  EXPECT_NE(msg.find("'Q'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("X, Y, Z"), std::string::npos) << msg;
}

TEST(InstrumentRecords, TimeOfCirclesAndLines) {
  // By hand: a circle = setup + 2 x 2 pi R at the ballbar feed; a line = setup + targets x (step at
  // the rapid feed + dwell). 150 mm at 1000 mm/min: 300 + 2 x 942.48 mm / 16.667 mm/s = 413.10 s;
  // X over 800 mm, 11 targets at 10000 mm/min and 4 s: 900 + 11 x (80 / 166.67 + 4) = 949.28 s.
  const Machine m = vmc();
  const CandidateSet cs = candidate_configurations(m, {}, rotary_grid(m, 1.0), ProbeReach{}, circles_and_lines());
  ProbingPlan one = cs.plan;
  std::erase_if(one.records, [&](const ProbingRecord& r) {
    const auto& id = one.features[r.feature].id;
    return id != "BB150XY1" && id != "LX";
  });
  const TimeEstimate t = estimate_time(m, one, ProbeCycle{}, TimingOptions{});
  EXPECT_EQ(t.circles, 1u);
  EXPECT_EQ(t.lines, 1u);
  EXPECT_EQ(t.touches, 0u);
  EXPECT_NEAR(t.instruments, 413.0973 + 949.28, 1e-3);
  EXPECT_NEAR(t.total, t.instruments, 1e-12);
}

TEST(InstrumentRecords, PlanPicksTheCircleThatProbingLacks) {
  // Probing the two balls determines EC0Y only through the scale bar's length (one reading):
  // poorly, u = 10.6 urad at 1 um. An XY circle sees the squareness directly; asked for a third of
  // that u, the design takes one circle, XY, alone (3.14 urad).
  const Machine m = vmc();
  IdentificationOptions o = options();
  o.estimate = {"EC0Y"};
  const ProbingPlan balls = probing(m);
  const double before = predict_plan(m, balls, o).parameters[0].u;
  const CandidateSet cs = candidate_configurations(m, balls.features, rotary_grid(m, 1.0), ProbeReach{}, circles_and_lines());
  DesignOptions d;
  d.model = o;
  d.target_u = {{"EC0Y", before / 3}};
  const PlanDesign design = design_plan(m, cs.plan, d);
  EXPECT_TRUE(design.target_met);
  EXPECT_EQ(design.poses, 1u);
  const auto setups = instrument_setups(m, design.plan);
  ASSERT_EQ(setups.size(), 1u);
  EXPECT_EQ(setups[0].plane, "XY");
  const double after = design.prediction.parameters[0].u;
  EXPECT_LT(after, before / 3);
  std::cout << "EC0Y: u " << before * 1e6 << " urad probing the two balls, " << after * 1e6 << " urad with "
            << setups[0].id << "\n";
}

TEST(InstrumentRecords, PlannedCirclesAndLinesRoundTrip) {
  // The five squarenesses and scales: probing alone leaves four undetermined; with --ballbar 150
  // --laser X,Z and 6 poses the design takes circles and lines; simulated (1 um, artefacts 5 um
  // off) and identified, every parameter within 3 u, the plan file carrying them.
  const Machine truth = vmc();
  const IdentificationOptions o = options();
  const ProbingPlan balls = probing(truth);
  const CandidateSet cs =
      candidate_configurations(truth, balls.features, rotary_grid(truth, 1.0), ProbeReach{}, circles_and_lines());
  DesignOptions d;
  d.model = o;
  d.poses = 6;
  const PlanDesign design = design_plan(truth, cs.plan, d);
  EXPECT_EQ(design.poses, 6u);
  const auto setups = instrument_setups(truth, design.plan);
  EXPECT_GE(setups.size(), 3u);
  const ProbingPlan back = parse_probing_csv(truth, probing_csv(truth, design.plan), "plan.csv");
  ASSERT_EQ(back.records.size(), design.plan.records.size());
  EXPECT_EQ(plan_poses(back), 6u);
  Machine prior = truth;
  for (const auto& p : kSquareScale) prior.set_parameter(p, 0.0);
  SimulationOptions so;
  so.noise = 1e-3;
  so.artefact_error = 5e-3;
  so.seed = 11;
  so.scale_bars = o.scale_bars;
  IdentificationOptions io = o;
  // The bar counts when the design probes both its balls (as design_plan predicts it).
  auto probed = [&](const std::string& id) {
    const auto f = back.feature_index(id);
    return f && std::any_of(back.records.begin(), back.records.end(), [&](const ProbingRecord& x) { return x.feature == *f; });
  };
  std::erase_if(io.scale_bars, [&](const ScaleBar& b) { return !probed(b.ball_a) || !probed(b.ball_b); });
  so.scale_bars = io.scale_bars;
  const Simulation sim = simulate_probing(truth, back, so);
  const IdentificationResult r = identify(prior, sim.measurements, io);
  EXPECT_TRUE(r.converged) << r.termination;
  ASSERT_EQ(r.parameters.size(), kSquareScale.size());
  for (std::size_t k = 0; k < r.parameters.size(); ++k) {
    const auto& e = r.parameters[k];
    const double t = truth.parameter(*truth.parameter_index(e.name));
    EXPECT_LT(std::abs(e.value - t), 3 * e.u) << e.name << ": " << e.value << " against " << t << ", u " << e.u;
    EXPECT_NEAR(e.u, design.prediction.parameters[k].u, 0.2 * design.prediction.parameters[k].u) << e.name;
  }
}

}  // namespace
}  // namespace mtcal
