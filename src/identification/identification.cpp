#include "mtcal/identification/identification.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <new>
#include <mutex>
#include <random>

#include <ceres/ceres.h>
#include <Eigen/Cholesky>
#include <Eigen/SVD>
#include <fmt/format.h>

#include "mtcal/fitting/least_squares.hpp"
#include "mtcal/util/parallel.hpp"
#include "mtcal/evaluation/volumetric.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/util/interrupt.hpp"
#include "mtcal/util/parse.hpp"
#include "mtcal/util/solver_log.hpp"
#include "probing_model.hpp"

namespace mtcal {

using detail::ProbingModel;

ArtefactState nominal_artefact(const ProbingPlan& plan) {
  ArtefactState a;
  a.ball.assign(plan.features.size(), Vec3::Zero());
  a.offset.assign(plan.features.size(), 0.0);
  for (std::size_t f = 0; f < plan.features.size(); ++f) {
    a.ball[f] = plan.features[f].position;
    // A ballbar's offset is its length offset (nominally none); a laser's, d . p where it reads 0.
    a.offset[f] = plan.features[f].kind == ProbeFeature::Kind::Ballbar
                      ? 0.0
                      : plan.features[f].normal.dot(plan.features[f].position);
  }
  return a;
}

namespace {

std::array<std::size_t, 3> xyz_axes(const Machine& m) {
  return {*m.axis_index('X'), *m.axis_index('Y'), *m.axis_index('Z')};
}

// d p / d (X, Y, Z) of the nominal tool point at q: constant in the linear axes at fixed rotary
// values (the nominal chain is affine in them), so one difference per axis is exact.
Eigen::Matrix3d linear_jacobian(const ErrorModel& nominal, const std::vector<double>& q,
                                const std::array<std::size_t, 3>& lin) {
  Eigen::Matrix3d A;
  const Vec3 p0 = nominal.nominal_pose(q).t;
  for (int c = 0; c < 3; ++c) {
    std::vector<double> qq = q;
    qq[lin[static_cast<std::size_t>(c)]] += 1.0;
    A.col(c) = nominal.nominal_pose(qq).t - p0;
  }
  return A;
}

// Linear axis values that put the tool point (actual or nominal) on target: Newton steps with
// the nominal linear Jacobian, which the errors change only by parts in 1e4.
void solve_position(const ErrorModel& model, bool actual, std::vector<double>& q, const std::vector<std::int8_t>& dir,
                    const Vec3& target, const Eigen::Matrix3d& A, const std::array<std::size_t, 3>& lin, int line) {
  const Eigen::PartialPivLU<Eigen::Matrix3d> lu(A);
  for (int it = 0; it < 50; ++it) {
    const Vec3 p = actual ? model.actual_pose(q, dir).t : model.nominal_pose(q).t;
    const Vec3 step = lu.solve(target - p);
    for (int c = 0; c < 3; ++c) q[lin[static_cast<std::size_t>(c)]] += step[c];
    if (step.norm() < 1e-13 * (1.0 + target.norm())) return;
  }
  throw ModelError(fmt::format("the position of the probing on line {} does not converge", line));
}

// The probing axis of a facet touch: the linear axis whose motion is most nearly along the
// normal, and its direction when approaching against the normal (n . p decreasing).
std::pair<std::size_t, std::int8_t> probing_axis(const Eigen::Matrix3d& A, const Vec3& normal,
                                                 const std::array<std::size_t, 3>& lin) {
  const Vec3 along = A.transpose() * normal;
  int c = 0;
  for (int k = 1; k < 3; ++k)
    if (std::abs(along[k]) > std::abs(along[c])) c = k;
  return {lin[static_cast<std::size_t>(c)], static_cast<std::int8_t>(along[c] > 0 ? -1 : 1)};
}

}  // namespace

ProbingPlan plan_targets(const Machine& m, const ProbingPlan& plan) {
  Machine nominal_machine = m;
  nominal_machine.clear_errors();
  const ErrorModel nominal(nominal_machine);
  const auto lin = xyz_axes(m);
  ProbingPlan out = plan;
  for (auto& r : out.records) {
    const auto& f = plan.features[r.feature];
    for (std::size_t k : lin) r.q[k] = 0.0;
    const Eigen::Matrix3d A = linear_jacobian(nominal, r.q, lin);
    const bool instrument = f.kind == ProbeFeature::Kind::Ballbar || f.kind == ProbeFeature::Kind::Laser;
    solve_position(nominal, false, r.q, r.dir, instrument ? instrument_target(f, r.at) : f.position, A, lin, r.line);
    if (f.kind == ProbeFeature::Kind::Facet) {
      const auto [k, sign] = probing_axis(A, f.normal, lin);
      r.dir[k] = sign;
    }
  }
  out.measured = false;
  return out;
}

namespace {

// The readings machine `truth` gives for a plan against a known artefact (facet planes moved by
// the pre-travel: the probe triggers that much beyond the plane), with Gaussian noise.
ProbingPlan simulate_readings(const Machine& truth, const ProbingPlan& plan, const ArtefactState& artefact,
                              double pretravel, double noise_ball, double noise_facet, std::mt19937_64& rng) {
  std::normal_distribution<double> gauss(0.0, 1.0);
  ProbingPlan out = plan_targets(truth, plan);
  out.measured = true;
  Machine nominal_machine = truth;
  nominal_machine.clear_errors();
  const ErrorModel nominal(nominal_machine), actual(truth);
  const auto lin = xyz_axes(truth);
  for (auto& r : out.records) {
    const auto& f = plan.features[r.feature];
    const Eigen::Matrix3d A = linear_jacobian(nominal, r.q, lin);
    // The instruments read at the commanded (nominal) targets: the bar's length from the true
    // pivot, read with its length offset; the displacement along the beam less its offset.
    if (f.kind == ProbeFeature::Kind::Ballbar) {
      const Vec3 p = actual.actual_pose(r.q, r.dir).t;
      r.reading = (p - artefact.ball[r.feature]).norm() + artefact.offset[r.feature] + noise_facet * gauss(rng);
      continue;
    }
    if (f.kind == ProbeFeature::Kind::Laser) {
      const Vec3 p = actual.actual_pose(r.q, r.dir).t;
      r.reading = f.normal.dot(p) - artefact.offset[r.feature] + noise_facet * gauss(rng);
      continue;
    }
    if (f.kind == ProbeFeature::Kind::Ball) {
      solve_position(actual, true, r.q, r.dir, artefact.ball[r.feature], A, lin, r.line);
      for (std::size_t k : lin) r.q[k] += noise_ball * gauss(rng);
      continue;
    }
    const auto [k, sign] = probing_axis(A, f.normal, lin);
    r.dir[k] = sign;
    const double slope =
        f.normal.dot(A.col(static_cast<Eigen::Index>(std::find(lin.begin(), lin.end(), k) - lin.begin())));
    const double plane = artefact.offset[r.feature] - pretravel;
    for (int it = 0;; ++it) {
      const double g = f.normal.dot(actual.actual_pose(r.q, r.dir).t) - plane;
      r.q[k] -= g / slope;
      if (std::abs(g) < 1e-13 * (1.0 + std::abs(plane))) break;
      if (it == 50) throw ModelError(fmt::format("the facet contact on line {} does not converge", r.line));
    }
    r.q[k] += noise_facet * gauss(rng);
  }
  return out;
}

}  // namespace

Simulation simulate_probing(const Machine& truth, const ProbingPlan& plan, const SimulationOptions& o) {
  if (!(o.noise >= 0) || !std::isfinite(o.noise))
    throw InputError({"noise", 0, ""}, fmt::format("expected a noise >= 0 mm, found {:g}", o.noise));
  if (!(o.artefact_error >= 0) || !std::isfinite(o.artefact_error))
    throw InputError({"artefact error", 0, ""}, fmt::format("expected >= 0 mm, found {:g}", o.artefact_error));
  std::mt19937_64 rng(o.seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  Simulation sim;
  sim.truth = nominal_artefact(plan);
  for (std::size_t f = 0; f < plan.features.size(); ++f) {
    if (plan.features[f].kind == ProbeFeature::Kind::Ball) {
      // Drawn one by one: the order of a call's arguments is unspecified (GCC right to left, Clang
      // left to right). z, y, x keeps the numbers mtcal has always given (GCC's order).
      const double dz = gauss(rng), dy = gauss(rng), dx = gauss(rng);
      sim.truth.ball[f] += o.artefact_error * Vec3(dx, dy, dz);
    } else if (plan.features[f].kind == ProbeFeature::Kind::Ballbar) {
      // The pivot placed and the bar's length set as well as a ball's position is known.
      const double dz = gauss(rng), dy = gauss(rng), dx = gauss(rng);
      sim.truth.ball[f] += o.artefact_error * Vec3(dx, dy, dz);
      sim.truth.offset[f] += o.artefact_error * gauss(rng);
    } else
      sim.truth.offset[f] += o.artefact_error * gauss(rng);
  }
  for (const auto& sb : o.scale_bars) {
    const auto a = plan.feature_index(sb.ball_a), b = plan.feature_index(sb.ball_b);
    if (!a || !b || plan.features[*a].kind != ProbeFeature::Kind::Ball ||
        plan.features[*b].kind != ProbeFeature::Kind::Ball || *a == *b)
      throw InputError({sb.source, 0, sb.ball_a + ":" + sb.ball_b}, "expected two different balls of the plan");
    const Vec3 d = sim.truth.ball[*b] - sim.truth.ball[*a];
    sim.truth.ball[*b] = sim.truth.ball[*a] + d.normalized() * sb.length;
  }
  sim.measurements = simulate_readings(truth, plan, sim.truth, 0.0, o.noise, o.noise, rng);
  return sim;
}

namespace {

// Jacobi-scaled SVD analysis of J's columns: rank, singular values, condition; and a sequential
// choice of columns (in the given order) that keeps the rank growing.
struct ColumnAnalysis {
  std::size_t rank = 0;
  std::vector<double> singular;
  double condition = 0.0;
  std::vector<std::size_t> kept, dropped;
  std::vector<Eigen::VectorXd> combination;  // per dropped column: coefficients over kept (natural units)
  std::vector<Eigen::VectorXd> weight;       // per dropped column: |J_kept| / |J_dropped|
  double kept_condition = 0.0;               // of the kept columns
};

ColumnAnalysis analyse_columns(const Eigen::MatrixXd& J, const std::vector<std::size_t>& order, double tol) {
  ColumnAnalysis a;
  const Eigen::Index n = J.cols();
  Eigen::VectorXd scale(n);
  for (Eigen::Index j = 0; j < n; ++j) scale[j] = J.col(j).norm();
  Eigen::MatrixXd S = J;
  for (Eigen::Index j = 0; j < n; ++j)
    if (scale[j] > 0) S.col(j) /= scale[j];
  const JacobianAnalysis ja = analyse_jacobian(J, 1.0, JacobianOptions{tol, true});
  const auto& sv = ja.singular_values;
  a.singular.assign(sv.data(), sv.data() + sv.size());
  const double smax = sv.size() ? sv[0] : 0.0;
  a.rank = ja.rank;
  a.condition = ja.condition;
  // Sequential: keep a column when its part orthogonal to the kept ones is above the same
  // threshold as the SVD's (distance from the span bounds the smallest singular value).
  Eigen::MatrixXd Q(J.rows(), 0);
  for (std::size_t j : order) {
    const auto col = static_cast<Eigen::Index>(j);
    if (scale[col] == 0) {
      a.dropped.push_back(j);
      continue;
    }
    Eigen::VectorXd v = S.col(col);
    for (int pass = 0; pass < 2; ++pass) v -= Q * (Q.transpose() * v);  // twice: Gram-Schmidt stays orthogonal
    if (v.norm() > tol * smax) {
      Q.conservativeResize(Eigen::NoChange, Q.cols() + 1);
      Q.col(Q.cols() - 1) = v / v.norm();
      a.kept.push_back(j);
    } else {
      a.dropped.push_back(j);
    }
  }
  {
    Eigen::MatrixXd K(S.rows(), static_cast<Eigen::Index>(a.kept.size()));
    for (std::size_t i = 0; i < a.kept.size(); ++i)
      K.col(static_cast<Eigen::Index>(i)) = S.col(static_cast<Eigen::Index>(a.kept[i]));
    if (K.cols() > 0) {
      const Eigen::JacobiSVD<Eigen::MatrixXd> ks(K);
      a.kept_condition = ks.singularValues()[0] / ks.singularValues()[K.cols() - 1];
    }
  }
  for (std::size_t j : a.dropped) {
    Eigen::MatrixXd K(J.rows(), static_cast<Eigen::Index>(a.kept.size()));
    for (std::size_t i = 0; i < a.kept.size(); ++i)
      K.col(static_cast<Eigen::Index>(i)) = J.col(static_cast<Eigen::Index>(a.kept[i]));
    a.combination.push_back(K.size()
                                ? Eigen::VectorXd(K.colPivHouseholderQr().solve(J.col(static_cast<Eigen::Index>(j))))
                                : Eigen::VectorXd());
    Eigen::VectorXd w(static_cast<Eigen::Index>(a.kept.size()));
    const double own = scale[static_cast<Eigen::Index>(j)];
    for (std::size_t i = 0; i < a.kept.size(); ++i)
      w[static_cast<Eigen::Index>(i)] = own > 0 ? scale[static_cast<Eigen::Index>(a.kept[i])] / own : 0.0;
    a.weight.push_back(w);
  }
  return a;
}

// c in natural units; weight[i] = |J_kept_i| / |J_name|: a term's share of the combination, which
// decides what is negligible (natural-unit sizes differ by orders of magnitude between mm and rad).
std::string combination_text(const std::string& name, const Eigen::VectorXd& c, const Eigen::VectorXd& weight,
                             const std::vector<std::string>& kept_names) {
  std::vector<std::pair<double, std::size_t>> terms;
  for (Eigen::Index i = 0; i < c.size(); ++i)
    if (std::abs(c[i]) * weight[i] > 1e-9) terms.push_back({std::abs(c[i]) * weight[i], static_cast<std::size_t>(i)});
  std::sort(terms.begin(), terms.end(), std::greater<>());
  if (terms.empty()) return name + " has no effect on the measurements";
  std::string s = name + " =";
  for (std::size_t t = 0; t < terms.size() && t < 6; ++t) {
    const double v = c[static_cast<Eigen::Index>(terms[t].second)];
    if (t == 0)
      s += fmt::format(" {}{:.4g} {}", v < 0 ? "-" : "", std::abs(v), kept_names[terms[t].second]);
    else
      s += fmt::format(" {} {:.4g} {}", v < 0 ? "-" : "+", std::abs(v), kept_names[terms[t].second]);
  }
  if (terms.size() > 6) s += fmt::format(" ... ({} terms)", terms.size());
  return s;
}

// The order of columns for the sequential rank test: artefact unknowns first (they are always
// needed), then the machine parameters as requested, then the pre-travel.
std::vector<std::size_t> column_order(const ProbingModel& pm) {
  std::vector<std::size_t> order;
  const std::size_t k = pm.parameters().size();
  const std::size_t end = pm.has_pretravel() ? pm.pretravel_column() : pm.unknowns();
  for (std::size_t j = k; j < end; ++j) order.push_back(j);
  for (std::size_t j = 0; j < k; ++j) order.push_back(j);
  if (pm.has_pretravel()) order.push_back(pm.pretravel_column());
  return order;
}

Identifiability make_identifiability(const ProbingModel& pm, const Eigen::MatrixXd& J, double tol) {
  Identifiability out;
  out.columns = pm.names();
  const ColumnAnalysis a = analyse_columns(J, column_order(pm), tol);
  out.rank = a.rank;
  out.singular_values = a.singular;
  out.condition = a.condition;
  out.condition_identifiable = a.kept_condition;
  std::vector<std::string> kept_names;
  for (std::size_t j : a.kept) kept_names.push_back(out.columns[j]);
  const std::size_t k = pm.parameters().size();
  for (std::size_t j = 0; j < k; ++j)
    (std::find(a.kept.begin(), a.kept.end(), j) != a.kept.end() ? out.identifiable : out.unidentifiable)
        .push_back(out.columns[j]);
  for (std::size_t d = 0; d < a.dropped.size(); ++d) {
    const std::size_t j = a.dropped[d];
    if (j >= k && j != pm.pretravel_column()) {
      out.unidentifiable.push_back(out.columns[j]);  // an artefact unknown: the plan cannot fix it
    } else if (pm.has_pretravel() && j == pm.pretravel_column()) {
      out.unidentifiable.push_back(out.columns[j]);
    }
    out.null_directions.push_back(combination_text(out.columns[j], a.combination[d], a.weight[d], kept_names));
  }
  return out;
}

// The parameter of largest magnitude, for messages about non-finite results ("EXX.1 = 1e+200 mm/mm").
std::string largest_parameter(const Machine& m) {
  std::string largest;
  double big = -1;
  for (const auto& p : m.parameters())
    if (std::abs(p.value) > big) {
      big = std::abs(p.value);
      largest = fmt::format("{} = {:g} {}", p.name, p.value, p.unit);
    }
  return largest;
}

// The residuals must be finite where the solver starts: a parameter value far outside any real
// machine (1e300 mm/mm) overflows the model, and the solver would report inf/nan estimates.
// Located at the first record whose residual is not finite; names the largest parameter.
void check_finite_start(const Machine& prior, const ProbingModel& pm, const ProbingPlan& meas,
                        const Eigen::VectorXd& x) {
  std::vector<double> r;
  for (std::size_t b = 0; b < pm.blocks(); ++b) {
    r.assign(pm.block_size(b), 0.0);
    pm.block(x.data(), b, r.data(), nullptr);
    if (std::all_of(r.begin(), r.end(), [](double v) { return std::isfinite(v); })) continue;
    const int line = b < meas.records.size() ? meas.records[b].line : 0;
    throw InputError({meas.source, line, ""},
                     "the model's residual is not finite with the machine's parameter values "
                     "(largest: " +
                         largest_parameter(prior) + "); expected finite errors of a real machine");
  }
}

void check_enough(const ProbingModel& pm, const std::string& source) {
  // Strictly more: with as many residuals as unknowns nothing is left to estimate the noise from.
  if (pm.residuals() <= pm.unknowns())
    throw InputError({source, 0, ""},
                     fmt::format("too few measurements: {} residuals for {} unknowns (machine parameters, "
                                 "ball centres, facet offsets); expected more residuals than unknowns",
                                 pm.residuals(), pm.unknowns()));
}

class RecordCost : public ceres::CostFunction {
 public:
  RecordCost(const ProbingModel& pm, std::size_t b) : pm_(pm), b_(b) {
    set_num_residuals(static_cast<int>(pm.block_size(b)));
    mutable_parameter_block_sizes()->push_back(static_cast<std::int32_t>(pm.unknowns()));
  }
  bool Evaluate(double const* const* x, double* r, double** J) const override {
    pm_.block(x[0], b_, r, J && J[0] ? J[0] : nullptr);
    for (int i = 0; i < num_residuals(); ++i)
      if (!std::isfinite(r[i])) return false;
    return true;
  }

 private:
  const ProbingModel& pm_;
  std::size_t b_;
};

struct Solve {
  Eigen::VectorXd x;
  ceres::Solver::Summary summary;
};

Solve run_ceres(const ProbingModel& pm, Eigen::VectorXd x, const IdentificationOptions& o) {
  ceres::Problem::Options po;
  po.cost_function_ownership = ceres::TAKE_OWNERSHIP;
  po.loss_function_ownership = ceres::TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  for (std::size_t b = 0; b < pm.blocks(); ++b) {
    ceres::LossFunction* loss = nullptr;
    if (o.loss == IdentificationOptions::Loss::Huber) loss = new ceres::HuberLoss(o.loss_scale);
    if (o.loss == IdentificationOptions::Loss::Cauchy) loss = new ceres::CauchyLoss(o.loss_scale);
    problem.AddResidualBlock(new RecordCost(pm, b), loss, x.data());
  }
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::DENSE_QR;
  so.max_num_iterations = o.max_iterations;
  so.function_tolerance = o.function_tolerance;
  so.parameter_tolerance = o.parameter_tolerance;
  so.gradient_tolerance = o.gradient_tolerance;
  so.num_threads = 1;
  so.logging_type = ceres::SILENT;
  so.minimizer_progress_to_stdout = false;
  Solve s;
  apply_solver_logging();
  ceres::Solve(so, &problem, &s.summary);
  s.x = x;
  return s;
}

// statistics false: the solution only (values, convergence, the identified machine and artefact),
// without the Jacobian analyses (rank, covariance, residual RMS) that a Monte Carlo run discards.
IdentificationResult identify_with(const Machine& prior, const ProbingPlan& meas, const IdentificationOptions& o,
                                   const std::vector<std::size_t>* fixed_params, const Eigen::VectorXd* start,
                                   bool statistics = true) {
  if (!meas.measured)
    throw InputError({meas.source, 0, ""}, "expected measurements (columns X, Y, Z with the readings), found a plan");
  const std::vector<std::size_t> requested =
      fixed_params ? *fixed_params : detail::parameter_indices(prior, o.estimate, o.estimate_source);
  IdentificationResult res;
  std::vector<std::size_t> params = requested;
  bool pretravel = o.estimate_pretravel;
  if (!fixed_params) {
    // Exclude what the measurements cannot determine, before solving. Structural: at the
    // error-free machine, where the errors' equivalences are exact (at the actual errors they
    // hold only to parts in 1e5 and would pass a rank test while leaving huge uncertainties).
    Machine nominal_machine = prior;
    nominal_machine.clear_errors();
    // At the nominal targets, not the readings: the readings carry the machine's errors (up to
    // 1e-4 of the travel), which would turn exact equivalences into near ones.
    const ProbingModel pm0(nominal_machine, plan_targets(nominal_machine, meas), requested, o.scale_bars,
                           o.estimate_pretravel, o.sigma_ball, o.sigma_facet, o.sigma_scale_bar, o.sigma_ballbar, o.sigma_laser);
    check_enough(pm0, meas.source);
    Eigen::VectorXd r;
    Eigen::MatrixXd J;
    pm0.evaluate(pm0.initial(), r, &J);
    const Identifiability before = make_identifiability(pm0, J, o.rank_tolerance);
    params.clear();
    const auto names = pm0.names();
    for (std::size_t i = 0; i < requested.size(); ++i)
      if (std::find(before.identifiable.begin(), before.identifiable.end(), names[i]) != before.identifiable.end())
        params.push_back(requested[i]);
    res.identifiability.unidentifiable = before.unidentifiable;
    res.identifiability.null_directions = before.null_directions;
    for (const auto& u : before.unidentifiable) {
      if (u == "pre-travel") {
        pretravel = false;  // requested like a parameter: reported and excluded
        continue;
      }
      if (u.rfind("ball ", 0) != 0 && u.rfind("facet ", 0) != 0 && u.rfind("ballbar ", 0) != 0 &&
          u.rfind("laser ", 0) != 0)
        continue;
      std::string why;
      for (const auto& d : before.null_directions)
        if (d.rfind(u + " ", 0) == 0) why = ": " + d;
      throw InputError({meas.source, 0, ""}, "the measurements cannot determine " + u + why);
    }
  }
  const ProbingModel pm(prior, meas, params, o.scale_bars, pretravel, o.sigma_ball, o.sigma_facet, o.sigma_scale_bar, o.sigma_ballbar, o.sigma_laser);
  res.pretravel_estimated = pretravel;
  check_enough(pm, meas.source);
  const Eigen::VectorXd x0 = start ? *start : pm.initial();
  check_finite_start(prior, pm, meas, x0);
  const Solve s = run_ceres(pm, x0, o);
  if (!s.x.allFinite() || !std::isfinite(s.summary.final_cost))
    throw InputError({meas.source, 0, ""},
                     "the identification diverged: the solution is not finite (solver: " +
                         std::string(ceres::TerminationTypeToString(s.summary.termination_type)) +
                         "); expected finite errors of a real machine (largest parameter of the prior: " +
                         largest_parameter(prior) + ")");
  res.termination = std::string(ceres::TerminationTypeToString(s.summary.termination_type)) + ": " + s.summary.message;
  res.converged = s.summary.termination_type == ceres::CONVERGENCE;
  res.iterations = static_cast<int>(s.summary.iterations.size()) - 1;
  res.initial_cost = s.summary.initial_cost;
  res.final_cost = s.summary.final_cost;
  res.residuals = pm.residuals();
  res.unknowns = pm.unknowns();
  if (!statistics) {
    const auto all = prior.parameters();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (std::size_t i = 0; i < params.size(); ++i)
      res.parameters.push_back({all[params[i]].name, s.x[static_cast<Eigen::Index>(i)], nan, all[params[i]].unit});
    res.artefact = pm.artefact(s.x.data());
    if (pm.has_pretravel()) res.pretravel = s.x[static_cast<Eigen::Index>(pm.pretravel_column())];
    res.machine = pm.machine(s.x.data());
    return res;
  }
  Eigen::VectorXd r;
  Eigen::MatrixXd J;
  pm.evaluate(s.x, r, &J);
  const double dof = static_cast<double>(pm.residuals()) - static_cast<double>(pm.unknowns());
  res.sigma0 = dof > 0 ? std::sqrt(r.squaredNorm() / dof) : 0.0;
  // Unweighted residual RMS per kind.
  // Per kind: ball, facet, ballbar, laser, scale bar.
  std::array<double, 5> sum{};
  std::array<std::size_t, 5> count{};
  for (std::size_t b = 0, row = 0; b < pm.blocks(); ++b) {
    const std::size_t size = pm.block_size(b);
    const std::size_t kind = b < meas.records.size() ? static_cast<std::size_t>(pm.block_kind(b)) : 4;
    for (std::size_t i = 0; i < size; ++i) {
      const double v = r[static_cast<Eigen::Index>(row + i)] * pm.sigma(b);
      sum[kind] += v * v;
      ++count[kind];
    }
    row += size;
  }
  auto rms = [&](std::size_t kind) { return count[kind] ? std::sqrt(sum[kind] / static_cast<double>(count[kind])) : 0.0; };
  res.rms_ball = rms(static_cast<std::size_t>(ProbeFeature::Kind::Ball));
  res.rms_facet = rms(static_cast<std::size_t>(ProbeFeature::Kind::Facet));
  res.rms_ballbar = rms(static_cast<std::size_t>(ProbeFeature::Kind::Ballbar));
  res.rms_laser = rms(static_cast<std::size_t>(ProbeFeature::Kind::Laser));
  res.rms_scale_bar = rms(4);
  // Covariance sigma0^2 (J^T J)^-1 at the solution (weighted Jacobian).
  const Identifiability at = make_identifiability(pm, J, o.rank_tolerance);
  res.identifiability.columns = at.columns;
  res.identifiability.rank = at.rank;
  res.identifiability.singular_values = at.singular_values;
  res.identifiability.condition = at.condition;
  res.identifiability.condition_identifiable = at.condition_identifiable;
  res.identifiability.identifiable = at.identifiable;
  // Rank deficient at the solution (a near-dependence the structural test let through): no
  // uncertainty can be given, and NaN says so rather than a false zero.
  Eigen::MatrixXd cov = Eigen::MatrixXd::Constant(J.cols(), J.cols(), std::numeric_limits<double>::quiet_NaN());
  if (at.rank == static_cast<std::size_t>(J.cols()))
    cov = analyse_jacobian(J, res.sigma0 * res.sigma0, JacobianOptions{o.rank_tolerance, true}).covariance;
  const auto all = prior.parameters();
  const std::size_t k = params.size();
  for (std::size_t i = 0; i < k; ++i)
    res.parameters.push_back({all[params[i]].name, s.x[static_cast<Eigen::Index>(i)],
                              std::sqrt(cov(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(i))),
                              all[params[i]].unit});
  res.correlation = Eigen::MatrixXd::Identity(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(k));
  for (std::size_t i = 0; i < k; ++i)
    for (std::size_t j = 0; j < k; ++j) {
      const double d = std::sqrt(cov(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(i)) *
                                 cov(static_cast<Eigen::Index>(j), static_cast<Eigen::Index>(j)));
      if (i != j)
        res.correlation(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) =
            cov(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) / d;
    }
  res.covariance = cov.topLeftCorner(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(k));
  res.artefact = pm.artefact(s.x.data());
  if (pm.has_pretravel()) {
    const auto c = static_cast<Eigen::Index>(pm.pretravel_column());
    res.pretravel = s.x[c];
    res.pretravel_u = std::sqrt(cov(c, c));
  }
  res.machine = pm.machine(s.x.data());
  return res;
}

}  // namespace

Identifiability identifiability(const Machine& machine, const ProbingPlan& plan, const IdentificationOptions& o) {
  Machine m = machine;
  m.clear_errors();                             // structural: see identify_with
  const ProbingPlan p = plan_targets(m, plan);  // measurements too: see identify_with
  const ProbingModel pm(m, p, detail::parameter_indices(m, o.estimate, o.estimate_source), o.scale_bars,
                        o.estimate_pretravel, o.sigma_ball, o.sigma_facet, o.sigma_scale_bar, o.sigma_ballbar, o.sigma_laser);
  Eigen::VectorXd r;
  Eigen::MatrixXd J;
  pm.evaluate(pm.initial(), r, &J);
  return make_identifiability(pm, J, o.rank_tolerance);
}

IdentificationResult identify(const Machine& prior, const ProbingPlan& measurements,
                              const IdentificationOptions& options) {
  return identify_with(prior, measurements, options, nullptr, nullptr);
}

MonteCarloResult monte_carlo(const Machine& prior, const ProbingPlan& measurements, const IdentificationOptions& o,
                             const IdentificationResult& result, const MonteCarloOptions& mc) {
  MonteCarloResult out;
  out.runs = mc.runs;
  const auto params = detail::parameter_indices(
      prior,
      [&] {
        std::vector<std::string> names;
        for (const auto& p : result.parameters) names.push_back(p.name);
        return names;
      }(),
      o.estimate_source);
  const std::size_t k = params.size();
  // The readings' noise: given, or estimated from the fit without bias: sigma0 (which divides by
  // m - n) times each kind's assumed standard deviation.
  const double noise_ball = mc.noise > 0 ? mc.noise : result.sigma0 * o.sigma_ball;
  const double noise_facet = mc.noise > 0 ? mc.noise : result.sigma0 * o.sigma_facet;
  IdentificationOptions run_options = o;
  run_options.estimate_pretravel = result.pretravel_estimated;
  const ProbingModel pm(prior, measurements, params, o.scale_bars, result.pretravel_estimated, o.sigma_ball,
                        o.sigma_facet, o.sigma_scale_bar, o.sigma_ballbar, o.sigma_laser);
  // The solution vector of the identification, as the start of every run.
  Eigen::VectorXd x0 = pm.initial();
  for (std::size_t i = 0; i < k; ++i) x0[static_cast<Eigen::Index>(i)] = result.parameters[i].value;
  for (std::size_t f = 0; f < measurements.features.size(); ++f) {
    bool used = false;
    for (const auto& r : measurements.records) used = used || r.feature == f;
    if (!used) continue;
    pm.put_artefact(f, result.artefact, x0.data());
  }
  if (pm.has_pretravel()) x0[static_cast<Eigen::Index>(pm.pretravel_column())] = result.pretravel;
  out.samples.assign(mc.runs, std::vector<double>(k, std::numeric_limits<double>::quiet_NaN()));
  std::vector<double> va(mc.runs, std::numeric_limits<double>::quiet_NaN());
  std::vector<char> ok(mc.runs, 0);
  std::vector<std::vector<Vec3>> maps(mc.workspace.empty() ? 0 : mc.runs);
  std::mutex error_mutex;
  std::string first_error;
  std::atomic<std::size_t> finished{0};
  parallel_for(mc.runs, mc.threads, [&](std::size_t run, std::size_t) {
    try {
      // Parametric bootstrap: the readings the identified machine gives against the fitted
      // artefact, with fresh noise; one seed per run, so results do not depend on the threads.
      std::mt19937_64 rng(mc.seed * 1000003ULL + run);
      const ProbingPlan meas =
          simulate_readings(result.machine, measurements, result.artefact, pm.has_pretravel() ? result.pretravel : 0.0,
                            noise_ball, noise_facet, rng);
      const IdentificationResult r = identify_with(prior, meas, run_options, &params, &x0, false);
      for (std::size_t j = 0; j < k; ++j) out.samples[run][j] = r.parameters[j].value;
      if (!mc.workspace.empty()) {
        const ErrorMap map = grid_error_map(ErrorModel(r.machine), mc.workspace, {1});
        va[run] = volumetric_accuracy(map.error).va.value;
        // Per-point sums for the map's spread, summed in run order after the pool (below).
        maps[run] = map.error;
      }
      ok[run] = r.converged;  // a run the solver did not finish is counted as failed, not averaged in
      if (mc.progress) mc.progress(++finished, mc.runs);
    } catch (const Interrupted&) {
      throw;  // a stop asked for from outside, not a failed run
    } catch (const Error& e) {
      // A run the model or solver refuses (a reading that does not converge) is a failed run.
      const std::lock_guard lock(error_mutex);
      if (first_error.empty()) first_error = e.what();
    } catch (const std::bad_alloc&) {
      // Out of memory says nothing about the run's data: the analysis stops (parallel_for
      // rethrows the first), instead of counting it among the solver's failures.
      throw Error(fmt::format("Monte Carlo run {} ran out of memory (fewer runs, threads or workspace points)", run));
    }
  });
  out.mean.assign(k, 0.0);
  out.stdev.assign(k, 0.0);
  std::size_t good = 0;
  for (std::size_t run = 0; run < mc.runs; ++run) good += ok[run] != 0;
  out.failed = mc.runs - good;
  if (good == 0)
    throw Error("every Monte Carlo run failed" + (first_error.empty() ? std::string() : ": " + first_error));
  for (std::size_t j = 0; j < k; ++j) {
    double s = 0, s2 = 0;
    for (std::size_t run = 0; run < mc.runs; ++run)
      if (ok[run]) s += out.samples[run][j];
    const double mean = s / static_cast<double>(good);
    for (std::size_t run = 0; run < mc.runs; ++run)
      if (ok[run]) s2 += (out.samples[run][j] - mean) * (out.samples[run][j] - mean);
    out.mean[j] = mean;
    out.stdev[j] = good > 1 ? std::sqrt(s2 / static_cast<double>(good - 1)) : 0.0;
  }
  if (!mc.workspace.empty()) {
    out.va_identified =
        volumetric_accuracy(grid_error_map(ErrorModel(result.machine), mc.workspace, {1}).error).va.value;
    double s = 0, s2 = 0;
    for (std::size_t run = 0; run < mc.runs; ++run)
      if (ok[run]) s += va[run];
    out.va_mean = s / static_cast<double>(good);
    for (std::size_t run = 0; run < mc.runs; ++run)
      if (ok[run]) s2 += (va[run] - out.va_mean) * (va[run] - out.va_mean);
    out.va_stdev = good > 1 ? std::sqrt(s2 / static_cast<double>(good - 1)) : 0.0;
    // The map's uncertainty: per point and component the spread over the runs; its largest.
    const std::size_t points = maps.empty() ? 0 : maps[0].size();
    for (std::size_t i = 0; i < points && good > 1; ++i) {
      Vec3 mean = Vec3::Zero(), sq = Vec3::Zero();
      for (std::size_t run = 0; run < mc.runs; ++run)
        if (ok[run]) mean += maps[run][i];
      mean /= static_cast<double>(good);
      for (std::size_t run = 0; run < mc.runs; ++run)
        if (ok[run]) sq += (maps[run][i] - mean).cwiseAbs2();
      out.map_stdev_max = std::max(out.map_stdev_max, std::sqrt(sq.maxCoeff() / static_cast<double>(good - 1)));
    }
  }
  return out;
}

ModelDeviation model_deviation(const Machine& identified, const Machine& truth,
                               const std::vector<std::vector<double>>& workspace) {
  const ErrorMap a = grid_error_map(ErrorModel(identified), workspace),
                 b = grid_error_map(ErrorModel(truth), workspace);
  ModelDeviation d;
  double s2 = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const double v = (a.error[i] - b.error[i]).norm();
    d.max = std::max(d.max, v);
    s2 += v * v;
  }
  d.rms = a.size() ? std::sqrt(s2 / static_cast<double>(a.size())) : 0.0;
  return d;
}

}  // namespace mtcal
