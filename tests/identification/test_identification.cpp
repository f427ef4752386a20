// Identification from probing: plan files, the virtual machine, recovery, identifiability,
// uncertainty coverage, combinatorial counts against brute force, bad inputs.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <Eigen/SVD>

#include "mtcal/identification/identification.hpp"
#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/io/instruments/probing_plan_file.hpp"
#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/util/errors.hpp"
#include "examples.hpp"

namespace mtcal {
namespace {

using mtcal::testing::hu40t;

const std::string identification_kPlanPath = std::string(MTCAL_EXAMPLES_DIR) + "/../plans/hu40t-samba-tango.csv";
const std::vector<std::string> kLocation{"EC0Y", "EB0Z", "EA0Z", "EX0C", "EY0C",  "EA0C",  "EB0C",
                                         "EX0B", "EZ0B", "EA0B", "EC0B", "EXX.1", "EYY.1", "EZZ.1"};

// The example machine with the estimated parameters zeroed: every other error is known.
Machine prior_of(const Machine& truth, const std::vector<std::string>& names) {
  Machine m = truth;
  for (const auto& n : names) m.set_parameter(n, 0.0);
  return m;
}

IdentificationOptions options(const std::vector<std::string>& names) {
  IdentificationOptions o;
  o.estimate = names;
  o.scale_bars = {{"1", "2", 304.8}};
  return o;
}

TEST(ProbingPlan, ReadsTheHu40tPlan) {
  const Machine m = hu40t();
  const ProbingPlan p = read_probing_csv(m, identification_kPlanPath);
  EXPECT_EQ(p.records.size(), 76u);  // Mohammed 3.2: "76 points have probed"
  EXPECT_EQ(p.features.size(), 7u);
  EXPECT_FALSE(p.measured);
  EXPECT_EQ(p.residual_count(), 56u * 3 + 20u);  // 56 ball probings, 20 facet touches
  const auto b3 = p.feature_index("3");
  ASSERT_TRUE(b3);
  EXPECT_EQ(p.features[*b3].position, Vec3(160.0, 160.0, 177.835));
  // Indexation 9: B = 90, C = 270 (Table 3.1), in radians inside.
  for (const auto& r : p.records)
    if (r.indexation == 9) {
      EXPECT_NEAR(r.q[*m.axis_index('B')], M_PI / 2, 1e-15);
      EXPECT_NEAR(r.q[*m.axis_index('C')], 3 * M_PI / 2, 1e-15);
    }
  // Written and read back: the same plan.
  const ProbingPlan again = parse_probing_csv(m, probing_csv(m, p), "again");
  ASSERT_EQ(again.records.size(), p.records.size());
  for (std::size_t i = 0; i < p.records.size(); ++i) {
    EXPECT_EQ(again.records[i].dir, p.records[i].dir);
    EXPECT_EQ(again.records[i].feature, p.records[i].feature);
  }
}

TEST(ProbingPlan, BadFilesGiveLocatedErrors) {
  const Machine m = hu40t();
  const std::string head = "indexation,B,C,feature,kind,x,y,z,nx,ny,nz,dirX,dirY,dirZ\n";
  auto fails = [&](const std::string& text, const std::string& what) {
    try {
      parse_probing_csv(m, text, "plan.csv");
      ADD_FAILURE() << "accepted: " << what;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("plan.csv"), std::string::npos) << e.what();
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(fails("indexation,B,C,feature,x,y,z\n1,0,0,1,0,0,0\n", "no kind").find("missing column 'kind'"),
            std::string::npos);
  EXPECT_NE(fails(head + "1,0,0,1,ball,0,nan,0,,,,,,\n", "NaN").find("'y'"), std::string::npos);
  EXPECT_NE(fails(head + "1,0,0,1,sphere,0,0,0,,,,,,\n", "kind").find("expected ball, facet, ballbar or laser"), std::string::npos);
  EXPECT_NE(fails(head + "1,0,0,7,facet,0,0,0,1,1,0,,,\n", "normal").find("unit normal"), std::string::npos);
  EXPECT_NE(
      fails(head + "1,0,0,1,ball,0,0,0,,,,,,\n2,0,0,1,ball,1,0,0,,,,,,\n", "moved").find("different kind or geometry"),
      std::string::npos);
  EXPECT_NE(fails(head + "1,0,0,1,ball,0,0,0,,,,2,,\n", "dir").find("expected -1, 0 or +1"), std::string::npos);
  EXPECT_NE(fails(head, "empty").find("at least one probing"), std::string::npos);
  EXPECT_NE(fails("indexation,B,Q,feature,kind,x,y,z\n", "column").find("unknown column 'Q'"), std::string::npos);
  EXPECT_NE(fails(head.substr(0, head.size() - 1) + ",X,Y\n1,0,0,1,ball,0,0,0,,,,,,,1,2\n", "readings")
                .find("X, Y, Z or none"),
            std::string::npos);
  // The line of the bad row is named.
  EXPECT_NE(fails(head + "1,0,0,1,ball,0,0,0,,,,,,\n1,0,0,2,ball,0,0,x,,,,,,\n", "line").find("plan.csv:3"),
            std::string::npos);
}

TEST(VirtualMachine, ReadingsPutTheActualProbeOnTheTrueFeatures) {
  const Machine truth = hu40t();
  const ProbingPlan plan = read_probing_csv(truth, identification_kPlanPath);
  SimulationOptions so;
  so.artefact_error = 0.05;
  so.scale_bars = {{"1", "2", 304.8}};
  const Simulation sim = simulate_probing(truth, plan, so);
  ASSERT_TRUE(sim.measurements.measured);
  const ErrorModel model(truth);
  const auto b1 = *plan.feature_index("1"), b2 = *plan.feature_index("2");
  EXPECT_NEAR((sim.truth.ball[b1] - sim.truth.ball[b2]).norm(), 304.8, 1e-12);
  for (const auto& r : sim.measurements.records) {
    const auto& f = plan.features[r.feature];
    const Vec3 p = model.actual_pose(r.q, r.dir).t;
    if (f.kind == ProbeFeature::Kind::Ball) {
      EXPECT_LT((p - sim.truth.ball[r.feature]).norm(), 1e-10);
    } else {
      EXPECT_NEAR(f.normal.dot(p), sim.truth.offset[r.feature], 1e-10);
      // The probing axis moved against the normal; the others kept the plan's pre-move directions.
      int moving = 0;
      for (std::size_t k = 0; k < r.dir.size(); ++k) moving += truth.axes[k].kind == AxisKind::Linear && r.dir[k] != 0;
      EXPECT_EQ(moving, 3);
    }
  }
  // The nominal targets put the nominal tool point on the nominal features.
  Machine nominal = truth;
  nominal.clear_errors();
  const ProbingPlan targets = plan_targets(truth, plan);
  const ErrorModel nm(nominal);
  for (const auto& r : targets.records)
    EXPECT_LT((nm.nominal_pose(r.q).t - plan.features[r.feature].position).norm(), 1e-10);
}

TEST(Identification, NoiseFreeRecoveryOfEveryIdentifiableParameter) {
  // Location errors, squareness and scale (the first example set) and the extended set with
  // polynomial coefficients and the reversal terms the facet pre-moves excite (Mohammed ch. 4).
  std::vector<std::string> extended = kLocation;
  for (const char* n : {"EXY.b", "EXZ.b", "EZX.b", "EZY.b", "EYX.b", "EYZ.b", "EXX.b", "EYY.b", "EXX.2", "EYY.2",
                        "EZZ.2", "EYX.2", "EZX.2", "EXY.2", "EZY.2", "EXZ.2", "EYZ.2"})
    extended.push_back(n);
  Machine truth = hu40t();
  // Give every estimated parameter a value (some are zero in the example).
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.5, 1.5);
  for (const auto& n : extended) {
    const ErrorParameter p = truth.parameters()[*truth.parameter_index(n)];  // a copy: parameters() is a temporary
    const double size = p.unit == "mm" ? 3e-3 : p.unit == "rad" ? 2e-5 : p.unit == "mm/mm" ? 1e-5 : 1e-8;
    truth.set_parameter(n, size * u(rng) * (rng() % 2 ? 1 : -1));
  }
  const ProbingPlan plan = read_probing_csv(truth, identification_kPlanPath);
  SimulationOptions so;
  so.artefact_error = 0.05;
  so.scale_bars = {{"1", "2", 304.8}};
  const Simulation sim = simulate_probing(truth, plan, so);
  // Through the measurement file, as a user would.
  const ProbingPlan meas = parse_probing_csv(truth, probing_csv(truth, sim.measurements), "meas.csv");
  for (const std::vector<std::string>* set : std::vector<const std::vector<std::string>*>{&kLocation, &extended}) {
    const IdentificationResult r = identify(prior_of(truth, *set), meas, options(*set));
    EXPECT_TRUE(r.converged) << r.termination;
    EXPECT_TRUE(r.identifiability.unidentifiable.empty());
    ASSERT_EQ(r.parameters.size(), set->size());
    for (const auto& p : r.parameters) {
      const double want = truth.parameter(*truth.parameter_index(p.name));
      EXPECT_NEAR(p.value, want, 1e-8 * std::abs(want)) << p.name;
    }
    for (std::size_t f = 0; f < plan.features.size(); ++f) {
      if (plan.features[f].kind == ProbeFeature::Kind::Ball) {
        EXPECT_LT((r.artefact.ball[f] - sim.truth.ball[f]).norm(), 1e-8);
      }
    }
    // e_V: the identified model is the imposed one everywhere, not only where it was measured.
    const auto dev = model_deviation(r.machine, truth, {{-300, 300}, {-250, 250}, {-300, 300}, {0.0, 1.0}, {0.0, 2.0}});
    EXPECT_LT(dev.max, 1e-9);
  }
}

TEST(Identification, UnidentifiableRequestsAreReportedAndExcluded) {
  const Machine m = hu40t();
  const ProbingPlan plan = read_probing_csv(m, identification_kPlanPath);
  // The X zero position together with the tool offset along x: one effect, two names; and the
  // workpiece position, which the uncalibrated balls' positions absorb.
  IdentificationOptions o = options({"EX0X", "EXt", "EXw"});
  const Identifiability id = identifiability(m, plan, o);
  EXPECT_EQ(id.identifiable, (std::vector<std::string>{"EX0X"}));
  EXPECT_EQ(id.unidentifiable, (std::vector<std::string>{"EXt", "EXw"}));
  ASSERT_EQ(id.null_directions.size(), 2u);
  EXPECT_NE(id.null_directions[0].find("EXt = 1 EX0X"), std::string::npos) << id.null_directions[0];
  // With the rotary location errors in, the X zero and the tool offset are both absorbed.
  o = options({"EX0C", "EX0B", "EX0X", "EXt"});
  const Identifiability id2 = identifiability(m, plan, o);
  EXPECT_EQ(id2.identifiable, (std::vector<std::string>{"EX0C", "EX0B"}));
  EXPECT_EQ(id2.unidentifiable, (std::vector<std::string>{"EX0X", "EXt"}));
  ASSERT_EQ(id2.null_directions.size(), 2u);
  EXPECT_NE(id2.null_directions[0].find("EX0X ="), std::string::npos);
  EXPECT_NE(id2.null_directions[0].find("EX0C"), std::string::npos);
  // identify excludes them: never given values.
  const Simulation sim = simulate_probing(m, plan, {});
  const IdentificationResult r = identify(m, sim.measurements, o);
  ASSERT_EQ(r.parameters.size(), 2u);
  EXPECT_EQ(r.parameters[0].name, "EX0C");
  EXPECT_EQ(r.identifiability.unidentifiable, (std::vector<std::string>{"EX0X", "EXt"}));
  // The pre-travel cannot be told from the facet's offset when the facet is always approached
  // against its normal.
  o = options({"EX0C"});
  o.estimate_pretravel = true;
  const Identifiability id3 = identifiability(m, plan, o);
  EXPECT_EQ(id3.unidentifiable, (std::vector<std::string>{"pre-travel"}));
}

TEST(Identification, UncertaintiesCoverTheTruth) {
  // 200 simulations with 1 um noise: each estimate within its reported 2u about 95 % of the time.
  const Machine truth = hu40t();
  const ProbingPlan plan = read_probing_csv(truth, identification_kPlanPath);
  const Machine prior = prior_of(truth, kLocation);
  std::size_t inside = 0, total = 0;
  for (std::uint64_t seed = 1; seed <= 200; ++seed) {
    SimulationOptions so;
    so.noise = 1e-3;
    so.seed = seed;
    so.artefact_error = 0.02;
    so.scale_bars = {{"1", "2", 304.8}};
    const IdentificationResult r = identify(prior, simulate_probing(truth, plan, so).measurements, options(kLocation));
    for (const auto& p : r.parameters) {
      inside += std::abs(p.value - truth.parameter(*truth.parameter_index(p.name))) <= 2 * p.u;
      ++total;
    }
  }
  const double coverage = static_cast<double>(inside) / static_cast<double>(total);
  EXPECT_GT(coverage, 0.93);
  EXPECT_LT(coverage, 0.97);
}

TEST(Identification, CovarianceIsTheOneTheUncertaintiesComeFrom) {
  // The parameters' covariance block: u is the root of its diagonal, the correlation its scaled form.
  const Machine truth = hu40t();
  const ProbingPlan plan = read_probing_csv(truth, identification_kPlanPath);
  SimulationOptions so;
  so.noise = 1e-3;
  so.artefact_error = 0.02;
  so.scale_bars = {{"1", "2", 304.8}};
  const IdentificationResult r =
      identify(prior_of(truth, kLocation), simulate_probing(truth, plan, so).measurements, options(kLocation));
  const auto k = static_cast<Eigen::Index>(r.parameters.size());
  ASSERT_EQ(r.covariance.rows(), k);
  ASSERT_EQ(r.covariance.cols(), k);
  for (Eigen::Index i = 0; i < k; ++i) {
    const double ui = r.parameters[static_cast<std::size_t>(i)].u;
    EXPECT_GT(ui, 0.0);
    EXPECT_NEAR(std::sqrt(r.covariance(i, i)), ui, 1e-15 * ui);
    for (Eigen::Index j = 0; j < k; ++j) {
      const double uj = r.parameters[static_cast<std::size_t>(j)].u;
      EXPECT_NEAR(r.covariance(i, j), r.covariance(j, i), 1e-12 * ui * uj);
      if (i != j) {
        EXPECT_NEAR(r.covariance(i, j) / (ui * uj), r.correlation(i, j), 1e-12);
      }
    }
  }
}

TEST(Identification, MonteCarloSpreadAgreesWithTheCovariance) {
  const Machine truth = hu40t();
  const ProbingPlan plan = read_probing_csv(truth, identification_kPlanPath);
  SimulationOptions so;
  so.noise = 1e-3;
  so.seed = 11;
  so.scale_bars = {{"1", "2", 304.8}};
  const Simulation sim = simulate_probing(truth, plan, so);
  const IdentificationOptions o = options(kLocation);
  const IdentificationResult r = identify(prior_of(truth, kLocation), sim.measurements, o);
  MonteCarloOptions mc;
  mc.runs = 200;
  mc.seed = 5;
  mc.noise = 1e-3;
  const MonteCarloResult a = monte_carlo(prior_of(truth, kLocation), sim.measurements, o, r, mc);
  EXPECT_EQ(a.failed, 0u);
  for (std::size_t i = 0; i < r.parameters.size(); ++i) {
    // The covariance's u scales with the fit's sigma0; the runs use the true 1 um.
    const double u = r.parameters[i].u / r.sigma0;
    EXPECT_NEAR(a.stdev[i] / u, 1.0, 0.2) << r.parameters[i].name;
  }
  // Without a given noise, sigma0 times the assumed sigma: an unbiased estimate of the 1 um.
  mc.noise = 0.0;
  const MonteCarloResult est = monte_carlo(prior_of(truth, kLocation), sim.measurements, o, r, mc);
  for (std::size_t i = 0; i < r.parameters.size(); ++i)
    EXPECT_NEAR(est.stdev[i] / r.parameters[i].u, 1.0, 0.2) << r.parameters[i].name;
  // Any thread count, the same numbers (one seed per run).
  mc.threads = 1;
  mc.runs = 20;
  const MonteCarloResult one = monte_carlo(prior_of(truth, kLocation), sim.measurements, o, r, mc);
  mc.threads = 2;
  const MonteCarloResult two = monte_carlo(prior_of(truth, kLocation), sim.measurements, o, r, mc);
  EXPECT_EQ(one.samples, two.samples);
}

TEST(Identification, BadInput) {
  const Machine m = hu40t();
  const ProbingPlan plan = read_probing_csv(m, identification_kPlanPath);
  EXPECT_THROW(identify(m, plan, options({"EX0C"})), InputError);  // a plan has no readings
  const Simulation sim = simulate_probing(m, plan, {});
  EXPECT_THROW(identify(m, sim.measurements, options({"EQQ"})), InputError);
  IdentificationOptions o = options({"EX0C"});
  o.scale_bars = {{"1", "9", 300}};
  EXPECT_THROW(identify(m, sim.measurements, o), InputError);  // no ball 9
  // Too few measurements: one ball probing for 3 ball unknowns and a parameter.
  ProbingPlan few = sim.measurements;
  few.records.resize(1);
  EXPECT_THROW(identify(m, few, options({"EX0C"})), InputError);  // the scale bar's balls are never probed
  try {
    IdentificationOptions no_bar = options({"EX0C"});
    no_bar.scale_bars.clear();
    identify(m, few, no_bar);  // 3 residuals for EX0C and the ball's centre
    ADD_FAILURE() << "accepted too few measurements";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("too few measurements"), std::string::npos) << e.what();
  }
  EXPECT_THROW(parse_scale_bar("1:2", "bar"), InputError);
  EXPECT_THROW(parse_scale_bar("1:2:-5", "bar"), InputError);
  EXPECT_EQ(parse_scale_bar("1:2:304.8", "bar").length, 304.8);
}

TEST(Subsets, CountEqualsBruteForce) {
  // Every 4-subset of 10 candidates, against a rank test of each subset on its own.
  const Machine m = hu40t();
  const ProbingPlan plan = read_probing_csv(m, identification_kPlanPath);
  const std::vector<std::string> cand{"EX0C", "EY0C", "EA0C", "EB0C", "EC0C", "EX0X", "EY0Y", "EC0Y", "EXt", "EYt"};
  SubsetOptions so;
  so.candidates = cand;
  so.always = {"EX0B"};
  so.choose = 4;
  so.rank_tolerance = 1e-7;
  so.keep = 1000;
  IdentificationOptions mo = options({});
  const SubsetAnalysis a = full_rank_subsets(m, plan, so, mo);
  EXPECT_EQ(a.examined, 210u);
  std::uint64_t brute = 0;
  for (std::size_t i = 0; i < cand.size(); ++i)
    for (std::size_t j = i + 1; j < cand.size(); ++j)
      for (std::size_t k = j + 1; k < cand.size(); ++k)
        for (std::size_t l = k + 1; l < cand.size(); ++l) {
          IdentificationOptions o = mo;
          o.estimate = {"EX0B", cand[i], cand[j], cand[k], cand[l]};
          o.rank_tolerance = 1e-7;
          brute += identifiability(m, plan, o).unidentifiable.empty();
        }
  EXPECT_EQ(a.full_rank, brute);
  EXPECT_GT(brute, 0u);
  EXPECT_LT(brute, 210u);
  EXPECT_EQ(a.subsets.size(), a.full_rank);
  for (std::size_t s = 1; s < a.subsets.size(); ++s) EXPECT_GE(a.subsets[s].condition, a.subsets[s - 1].condition);
  EXPECT_GT(a.pruned, 0u);
}

TEST(Subsets, ResidueIsTheLeastSquaresResidue) {
  // With measurements, each subset's residue equals the norm left by a linear least-squares fit.
  Machine truth = hu40t();
  const ProbingPlan plan = read_probing_csv(truth, identification_kPlanPath);
  SimulationOptions so;
  so.noise = 1e-3;
  so.scale_bars = {{"1", "2", 304.8}};
  Machine clean = truth;
  clean.clear_errors();
  for (const auto& n : kLocation) clean.set_parameter(n, truth.parameter(*truth.parameter_index(n)));
  const Simulation sim = simulate_probing(clean, plan, so);
  SubsetOptions sub;
  sub.candidates = kLocation;
  sub.choose = 14;
  const SubsetAnalysis a = full_rank_subsets(clean, sim.measurements, sub, options({}));
  ASSERT_EQ(a.full_rank, 1u);
  // At first order the residue is what the nonlinear fit leaves (weights 1/sigma = 1000 per mm).
  const IdentificationResult r = identify(prior_of(clean, kLocation), sim.measurements, options(kLocation));
  EXPECT_NEAR(a.subsets[0].residue, std::sqrt(2 * r.final_cost), 0.05 * std::sqrt(2 * r.final_cost));
}

}  // namespace
}  // namespace mtcal
