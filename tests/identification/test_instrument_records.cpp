// Ballbar circles and laser lines as measurement records of the identification: the file, their
// Jacobian rows against numeric differences, recovery from simulated readings, and what they add
// to probing (docs/identification.md).
#include <gtest/gtest.h>

#include <cmath>
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
  // Plans with them are predicted but not proposed, nor probed by a program.
  const std::string msg = testing::error_message(
      [&] { candidate_configurations(truth, with_instruments(truth).features, CandidateGrid{}, ProbeReach{}); });
  EXPECT_NE(msg.find("not proposed"), std::string::npos) << msg;
}

}  // namespace
}  // namespace mtcal
