// Planning a probing measurement: candidates within reach, Wynn-Fedorov design, prediction, time.
#include "mtcal/identification/planning.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <random>
#include <set>
#include <tuple>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <fmt/format.h>

#include "mtcal/evaluation/volumetric.hpp"
#include "mtcal/fitting/fit.hpp"
#include "mtcal/fitting/least_squares.hpp"
#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/util/parallel.hpp"
#include "probing_model.hpp"

namespace mtcal {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

std::vector<std::size_t> rotary_axes(const Machine& m) {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < m.axes.size(); ++i)
    if (m.axes[i].kind == AxisKind::Rotary) out.push_back(i);
  return out;
}
std::vector<std::size_t> linear_axes(const Machine& m) {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < m.axes.size(); ++i)
    if (m.axes[i].kind == AxisKind::Linear) out.push_back(i);
  return out;
}

Machine nominal_of(const Machine& m) {
  Machine n = m;
  n.clear_errors();
  return n;
}

// Unit vector from the probe's tip to the spindle in the workpiece frame: the tool points along
// -(tool axis) of the tool frame (model/machine.hpp, ToolSetup).
Vec3 tool_axis(const ErrorModel& nominal, const ProbingRecord& r) {
  return nominal.nominal_pose(r.q).R.col(nominal.machine().tool.tool_axis).normalized();
}

std::string violation(const ErrorModel& nominal, const ProbingPlan& plan, const ProbingRecord& r,
                      const ProbeReach& reach) {
  const Machine& m = nominal.machine();
  for (std::size_t k = 0; k < m.axes.size(); ++k) {
    const auto& t = m.axes[k].travel;
    if (t && (r.q[k] < t->min - 1e-9 || r.q[k] > t->max + 1e-9)) return "travel";
  }
  const ProbeFeature& f = plan.features[r.feature];
  const Vec3 a = tool_axis(nominal, r);
  if (f.kind == ProbeFeature::Kind::Ball) {
    const double tilt = std::acos(std::clamp(a.dot(-reach.stem.normalized()), -1.0, 1.0)) * 180.0 / std::numbers::pi;
    if (tilt > reach.max_tilt_deg + 1e-9) return "stem";
  } else if (a.dot(f.normal) < -1e-9) {
    return "facet side";
  }
  // The holder: a disc of holder_radius centred stylus_length along a from the tip, at right angles
  // to a; its lowest point is sin(angle to z) * radius below its centre. Balls only: they stand
  // on the table, whose plane the rule takes as unbounded; facets are faces of the artefact or
  // the pallet, whose edges the probe reaches over.
  if (f.kind != ProbeFeature::Kind::Ball) return "";
  const double lowest = f.position.z() + reach.stylus_length * a.z() -
                        reach.holder_radius * std::sqrt(std::max(0.0, 1.0 - a.z() * a.z()));
  if (lowest < reach.table_z - 1e-9) return "table";
  return "";
}

}  // namespace

CandidateGrid rotary_grid(const Machine& m, double step) {
  if (!(step > 0) || !std::isfinite(step))
    throw InputError({"rotary step", 0, ""}, fmt::format("expected a step > 0, found {:g}", step));
  CandidateGrid g;
  for (std::size_t k : rotary_axes(m)) {
    const auto& t = m.axes[k].travel;
    double lo = t ? t->min : -std::numbers::pi, hi = t ? t->max : std::numbers::pi;
    bool turn = hi - lo >= 2 * std::numbers::pi - 1e-12;
    if (turn) {  // one turn, centred on zero when the travel allows
      lo = std::max(lo, -std::numbers::pi);
      hi = lo + 2 * std::numbers::pi;
    }
    std::vector<double> v;
    const auto n = static_cast<long>(std::floor((hi - lo) / step + 1e-9));
    for (long i = 0; i <= n; ++i) {
      const double x = lo + static_cast<double>(i) * step;
      if (turn && x >= hi - 1e-9) break;
      v.push_back(x);
    }
    g.rotary.push_back(std::move(v));
  }
  return g;
}

std::string reach_violation(const Machine& m, const ProbingPlan& plan, const ProbingRecord& r,
                            const ProbeReach& reach) {
  const ErrorModel nominal(nominal_of(m));
  return violation(nominal, plan, r, reach);
}

CandidateSet candidate_configurations(const Machine& m, const std::vector<ProbeFeature>& features,
                                      const CandidateGrid& grid, const ProbeReach& reach) {
  const auto rot = rotary_axes(m);
  const auto lin = linear_axes(m);
  for (const auto& f : features)
    if (f.kind != ProbeFeature::Kind::Ball && f.kind != ProbeFeature::Kind::Facet)
      throw InputError({"artefact", 0, f.id},
                       fmt::format("the design proposes probings of balls and facets; the {} '{}' is not one (its "
                                   "records are not proposed as candidates)",
                                   feature_kind_name(f.kind), f.id));
  if (grid.rotary.size() != rot.size())
    throw InputError({"candidate grid", 0, ""}, fmt::format("expected values for the {} rotary axes, found {}",
                                                            rot.size(), grid.rotary.size()));
  if (features.empty()) throw InputError({"artefact", 0, ""}, "expected at least one ball or facet, found none");
  ProbingPlan all;
  all.features = features;
  all.source = "the candidate configurations";
  std::size_t count = 1;
  for (const auto& v : grid.rotary) count *= v.size();
  if (count == 0) throw InputError({"candidate grid", 0, ""}, "a rotary axis has no values");
  for (std::size_t idx = 0; idx < count; ++idx) {
    ProbingRecord base;
    base.indexation = static_cast<int>(idx + 1);
    base.q.assign(m.axes.size(), 0.0);
    base.dir.assign(m.axes.size(), 0);
    std::size_t rest = idx;
    for (std::size_t j = rot.size(); j-- > 0;) {  // the last rotary axis fastest
      base.q[rot[j]] = grid.rotary[j][rest % grid.rotary[j].size()];
      rest /= grid.rotary[j].size();
    }
    for (std::size_t f = 0; f < features.size(); ++f) {
      base.feature = f;
      if (features[f].kind == ProbeFeature::Kind::Ball) {
        all.records.push_back(base);
        continue;
      }
      // Facets: every pre-move pattern of the linear axes; plan_targets sets the probing axis'
      // own direction (the approach), which makes half of the patterns duplicates, dropped below.
      for (int p = 0; p < (1 << lin.size()); ++p) {
        ProbingRecord r = base;
        for (std::size_t k = 0; k < lin.size(); ++k) r.dir[lin[k]] = (p >> k) & 1 ? 1 : -1;
        all.records.push_back(r);
      }
    }
  }
  all = plan_targets(m, all);
  // Duplicates (facet patterns that differ only in the probing axis).
  {
    std::set<std::tuple<int, std::size_t, std::vector<std::int8_t>>> seen;
    std::vector<ProbingRecord> unique;
    for (auto& r : all.records)
      if (seen.insert({r.indexation, r.feature, r.dir}).second) unique.push_back(std::move(r));
    all.records = std::move(unique);
  }
  CandidateSet out;
  out.considered = all.records.size();
  const std::vector<std::string> order{"travel", "stem", "facet side", "table"};
  std::map<std::string, std::size_t> removed;
  const ErrorModel nominal(nominal_of(m));
  std::vector<ProbingRecord> kept;
  for (auto& r : all.records) {
    const std::string why = violation(nominal, all, r, reach);
    if (why.empty())
      kept.push_back(std::move(r));
    else
      ++removed[why];
  }
  for (const auto& name : order) out.removed.emplace_back(name, removed[name]);
  if (kept.empty()) {
    std::string list;
    for (const auto& [name, n] : out.removed) list += fmt::format("{}{} by {}", list.empty() ? "" : ", ", n, name);
    throw InputError({"candidate configurations", 0, ""},
                     fmt::format("no candidate configuration is left: of {} ({} indexations x the features), {}",
                                 out.considered, count, list));
  }
  all.records = std::move(kept);
  out.plan = std::move(all);
  return out;
}

// ---------------------------------------------------------------------------------------------

std::vector<ProbeFeature> region_balls(const BallRegion& r, const std::vector<ProbeFeature>& taken) {
  for (const auto& [name, v] : {std::pair{"x_min", r.x_min}, std::pair{"x_max", r.x_max}, std::pair{"y_min", r.y_min},
                                std::pair{"y_max", r.y_max}, std::pair{"z", r.z}})
    if (!std::isfinite(v)) throw InputError({"ball region", 0, name}, fmt::format("expected a finite value, found {:g}", v));
  if (!(r.spacing > 0) || !std::isfinite(r.spacing))
    throw InputError({"ball region", 0, "spacing"}, fmt::format("expected a spacing > 0 mm, found {:g}", r.spacing));
  if (r.x_min > r.x_max || r.y_min > r.y_max)
    throw InputError({"ball region", 0, ""}, fmt::format("expected min <= max, found x {:g} to {:g}, y {:g} to {:g}",
                                                         r.x_min, r.x_max, r.y_min, r.y_max));
  const double nx = std::floor((r.x_max - r.x_min) / r.spacing + 1e-9) + 1,
               ny = std::floor((r.y_max - r.y_min) / r.spacing + 1e-9) + 1;
  if (nx * ny > 10000)
    throw InputError({"ball region", 0, "spacing"},
                     fmt::format("expected at most 10,000 positions, found {:g} x {:g}: a larger spacing", nx, ny));
  std::vector<ProbeFeature> out;
  for (long j = 0; j < static_cast<long>(ny); ++j)
    for (long i = 0; i < static_cast<long>(nx); ++i) {
      ProbeFeature f;
      f.id = r.id_prefix + std::to_string(out.size() + 1);
      if (std::any_of(taken.begin(), taken.end(), [&](const ProbeFeature& t) { return t.id == f.id; }))
        throw InputError({"ball region", 0, f.id},
                         fmt::format("the region's ball id '{}' is already a feature of the artefact", f.id));
      f.kind = ProbeFeature::Kind::Ball;
      f.position = Vec3(r.x_min + static_cast<double>(i) * r.spacing, r.y_min + static_cast<double>(j) * r.spacing, r.z);
      out.push_back(f);
    }
  return out;
}

// ---------------------------------------------------------------------------------------------

ParameterChoice choose_parameters(const Machine& m, const ProbingPlan& candidates, const SubsetOptions& so,
                                  const IdentificationOptions& model) {
  const SubsetAnalysis a = full_rank_subsets(m, candidates, so, model);
  ParameterChoice out;
  out.examined = a.examined;
  out.full_rank = a.full_rank;
  if (a.subsets.empty()) {
    IdentificationOptions all = model;
    all.estimate = so.always;
    all.estimate.insert(all.estimate.end(), so.candidates.begin(), so.candidates.end());
    all.estimate_source = so.candidates_source;
    const Identifiability id = identifiability(m, candidates, all);
    std::string why;
    for (const auto& d : id.null_directions) why += (why.empty() ? "" : "; ") + d;
    throw InputError({so.choose_source, 0, std::to_string(so.choose)},
                     fmt::format("none of the {} subsets of {} among the {} candidates is identifiable at all {} "
                                 "candidate poses{}{}",
                                 a.examined, so.choose, a.candidates.size(), candidates.records.size(),
                                 id.unidentifiable.empty() ? "" : fmt::format(" ({} {} not identifiable whatever the poses: {})",
                                                                              fmt::join(id.unidentifiable, ", "),
                                                                              id.unidentifiable.size() == 1 ? "is" : "are", why),
                                 so.always.empty() ? "" : fmt::format(", with {}", fmt::join(so.always, ","))));
  }
  const ParameterSubset& best = a.subsets.front();
  out.condition = best.condition;
  out.estimate = so.always;
  for (std::size_t i : best.members) {
    out.chosen.push_back(a.candidates[i]);
    out.estimate.push_back(a.candidates[i]);
  }
  return out;
}

// ---------------------------------------------------------------------------------------------

PlanPrediction predict_plan(const Machine& m, const ProbingPlan& plan, const IdentificationOptions& o) {
  const Machine nominal = nominal_of(m);
  const ProbingPlan targets = plan_targets(nominal, plan);
  const Identifiability id = identifiability(m, plan, o);
  if (!id.unidentifiable.empty()) {
    std::string why;
    for (const auto& d : id.null_directions) why += (why.empty() ? "" : "; ") + d;
    throw InputError({plan.source, 0, id.unidentifiable.front()},
                     fmt::format("{} {} not identifiable from the {} poses ({})",
                                 fmt::join(id.unidentifiable, ", "), id.unidentifiable.size() == 1 ? "is" : "are",
                                 plan.records.size(), why));
  }
  const auto params = detail::parameter_indices(m, o.estimate, o.estimate_source);
  const detail::ProbingModel pm(nominal, targets, params, o.scale_bars, false, o.sigma_ball, o.sigma_facet,
                                o.sigma_scale_bar, o.sigma_ballbar, o.sigma_laser);
  Eigen::VectorXd r;
  Eigen::MatrixXd J;
  pm.evaluate(pm.initial(), r, &J);
  // The rows are divided by the readings' sigma: sigma^2 (J^T J)^-1 of the unweighted Jacobian.
  const JacobianAnalysis a = analyse_jacobian(J, 1.0, JacobianOptions{o.rank_tolerance, true});
  PlanPrediction out;
  out.poses = plan.records.size();
  out.residuals = pm.residuals();
  out.unknowns = pm.unknowns();
  out.rank = a.rank;
  out.condition = a.condition;
  if (!a.full_rank())
    throw InputError({plan.source, 0, ""}, fmt::format("the {} poses leave {} of the {} unknowns undetermined",
                                                       plan.records.size(), pm.unknowns() - a.rank, pm.unknowns()));
  const auto k = static_cast<Eigen::Index>(params.size());
  out.covariance = a.covariance.topLeftCorner(k, k);
  const auto all = m.parameters();
  for (std::size_t i = 0; i < params.size(); ++i)
    out.parameters.push_back(
        {all[params[i]].name, all[params[i]].unit, a.uncertainty[static_cast<Eigen::Index>(i)], 0.0});
  return out;
}

// ---------------------------------------------------------------------------------------------

std::vector<std::vector<double>> travel_grid(const Machine& m, std::size_t per_axis) {
  if (per_axis < 2)
    throw InputError({"workspace", 0, ""}, fmt::format("expected at least 2 values per axis, found {}", per_axis));
  std::vector<std::vector<double>> g;
  const auto n = static_cast<double>(per_axis);
  for (const auto& axis : m.axes) {
    const auto& t = axis.travel;
    std::vector<double> v;
    const bool rotary = axis.kind == AxisKind::Rotary;
    if (rotary && (!t || t->max - t->min >= 2 * std::numbers::pi - 1e-12)) {
      for (std::size_t i = 0; i < per_axis; ++i)  // one turn, the end left out (it is the start)
        v.push_back(-std::numbers::pi + 2 * std::numbers::pi * static_cast<double>(i) / n);
    } else if (!t) {
      throw InputError({m.source, 0, std::string(1, axis.letter)},
                       "a workspace over the travels needs the travel of every linear axis; axis has none");
    } else {
      for (std::size_t i = 0; i < per_axis; ++i)
        v.push_back(t->min + (t->max - t->min) * static_cast<double>(i) / (n - 1));
    }
    g.push_back(std::move(v));
  }
  return g;
}

VaSensitivity va_sensitivity(const Machine& m, const std::vector<std::vector<double>>& workspace,
                             const IdentificationOptions& o, const VaOptions& vo) {
  const auto params = detail::parameter_indices(m, o.estimate, o.estimate_source);
  const ErrorModel model(m);
  const ErrorMap map = grid_error_map(model, workspace);
  const VolumetricAccuracy va = volumetric_accuracy(map.error);
  VaSensitivity out;
  out.va = va.va.value;
  if (!(out.va > 1e-12))
    throw InputError({"workspace", 0, ""},
                     fmt::format("the machine's VA over the workspace ({} configurations) is {:g} mm: its uncertainty "
                                 "is linearised about the machine's errors, which must not all vanish there (give "
                                 "the expected errors, e.g. a prior identification's parameters)",
                                 map.size(), out.va));
  // The pairs within the tolerance of the maximum: a point can be in one only if its distance from
  // the centroid plus the map's radius about it reaches VA - tolerance (triangle inequality).
  const double floor = out.va - std::max(0.0, vo.tie_tolerance);
  Vec3 centre = Vec3::Zero();
  for (const Vec3& e : map.error) centre += e;
  centre /= static_cast<double>(map.size());
  double radius = 0.0;
  for (const Vec3& e : map.error) radius = std::max(radius, (e - centre).norm());
  std::vector<std::size_t> far;
  for (std::size_t i = 0; i < map.size(); ++i)
    if ((map.error[i] - centre).norm() + radius >= floor) far.push_back(i);
  std::vector<std::tuple<double, std::size_t, std::size_t>> pairs{{out.va, va.va.i, va.va.j}};
  for (std::size_t a = 0; a < far.size(); ++a)
    for (std::size_t b = a + 1; b < far.size(); ++b) {
      const std::size_t i = far[a], j = far[b];
      if ((i == va.va.i && j == va.va.j) || (i == va.va.j && j == va.va.i)) continue;
      const double l = (map.error[j] - map.error[i]).norm();
      if (l >= floor) pairs.emplace_back(l, i, j);
    }
  std::sort(pairs.begin() + 1, pairs.end(), [](const auto& x, const auto& y) { return std::get<0>(x) > std::get<0>(y); });
  out.tie_tolerance = std::max(0.0, vo.tie_tolerance);
  if (pairs.size() > std::max<std::size_t>(1, vo.max_pairs)) {
    pairs.resize(std::max<std::size_t>(1, vo.max_pairs));
    out.pairs_capped = true;
  }
  const auto ci = map.configuration(va.va.i), cj = map.configuration(va.va.j);
  out.from.assign(ci.begin(), ci.end());
  out.to.assign(cj.begin(), cj.end());
  const auto all = m.parameters();
  for (std::size_t k : params) out.parameters.push_back(all[k].name);
  out.gradients.resize(static_cast<Eigen::Index>(params.size()), static_cast<Eigen::Index>(pairs.size()));
  for (std::size_t n = 0; n < pairs.size(); ++n) {
    const auto [l, i, j] = pairs[n];
    const Vec3 d = (map.error[j] - map.error[i]).normalized();
    const Eigen::Matrix<double, 6, Eigen::Dynamic> Ji = model.jacobian(map.configuration(i)),
                                                   Jj = model.jacobian(map.configuration(j));
    for (std::size_t k = 0; k < params.size(); ++k) {
      const auto c = static_cast<Eigen::Index>(params[k]);
      out.gradients(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(n)) =
          d.dot(Jj.block<3, 1>(0, c) - Ji.block<3, 1>(0, c));
    }
    out.pair_lengths.push_back(l);
  }
  out.gradient = out.gradients.col(0);
  return out;
}

double va_uncertainty(const VaSensitivity& s, const Eigen::MatrixXd& covariance) {
  if (covariance.rows() != s.gradients.rows() || covariance.cols() != s.gradients.rows())
    throw Error(fmt::format("va_uncertainty: a covariance of {} x {} for {} parameters", covariance.rows(),
                            covariance.cols(), s.gradients.rows()));
  return std::sqrt(std::max(0.0, (s.gradients.transpose() * covariance * s.gradients).diagonal().maxCoeff()));
}

// ---------------------------------------------------------------------------------------------

namespace {

// Scaled variance above which an unknown counts as undetermined: with the 1e-10 ridge an
// undetermined unknown has a variance of about 1e10, a determined one of order 1 to its
// conditioning squared (columns of unit RMS per pose).
constexpr double kRidge = 1e-10, kUndetermined = 1e4;

// The exchange algorithm's state: the information of the selected poses (unit-norm columns,
// ridge), its inverse and the parameters' block of it.
class Design {
 public:
  // g: the VA's gradients in scaled units, a column per near-critical pair (empty: none);
  // va_weight: 1 / its target^2 in MaxU (0: none).
  Design(Eigen::MatrixXd rows, std::vector<std::size_t> first, Eigen::MatrixXd fixed, std::size_t params,
         Eigen::VectorXd weight, Eigen::MatrixXd g, double va_weight, int threads)
      : rows_(std::move(rows)),
        first_(std::move(first)),
        p_(static_cast<Eigen::Index>(params)),
        w_(std::move(weight)),
        g_(g.size() == 0 ? Eigen::MatrixXd::Zero(p_, 1) : std::move(g)),
        va_weight_(va_weight),
        threads_(threads) {
    base_ = fixed.transpose() * fixed;
    base_.diagonal().array() += kRidge;
    M_ = base_;
    chosen_.assign(count(), false);
    refresh();
  }
  std::size_t count() const { return first_.size() - 1; }
  bool chosen(std::size_t j) const { return chosen_[j]; }
  std::size_t size() const { return selection_.size(); }
  const std::vector<std::size_t>& selection() const { return selection_; }

  void add(std::size_t j) {
    M_ += block(j).transpose() * block(j);
    chosen_[j] = true;
    selection_.push_back(j);
    refresh();
  }
  void remove(std::size_t j) {
    M_ -= block(j).transpose() * block(j);
    chosen_[j] = false;
    selection_.erase(std::find(selection_.begin(), selection_.end(), j));
    refresh();
  }
  void set(const std::vector<std::size_t>& sel) {
    M_ = base_;
    chosen_.assign(count(), false);
    selection_.clear();
    for (std::size_t j : sel) {
      M_ += block(j).transpose() * block(j);
      chosen_[j] = true;
      selection_.push_back(j);
    }
    refresh();
  }
  // Every direction of the parameters determined: the largest eigenvalue of their covariance
  // block below the threshold (a marginal variance can be small along a null direction that is
  // mostly the artefact's unknowns).
  bool determined() const {
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(cov_.topLeftCorner(p_, p_), Eigen::EigenvaluesOnly);
    return es.eigenvalues().maxCoeff() < kUndetermined;
  }
  double value(DesignCriterion c) const {
    return criterion(c, cov_.topLeftCorner(p_, p_).diagonal(), logdet_, va_vars_.maxCoeff());
  }
  // The criterion after adding (sign +1) or removing (sign -1) each candidate, for those with
  // want[j]; infinity elsewhere. One product with the inverse for all candidates (Sherman-Morrison-
  // Woodbury: C' = C - s U (I + s J U)^-1 U^T with U = C J^T).
  std::vector<double> trial(DesignCriterion c, int sign, const std::vector<bool>& want) const {
    std::vector<double> out(count(), kInf);
    const Eigen::MatrixXd U = cov_ * rows_.transpose();  // n x rows
    Eigen::MatrixXd V;
    if (c == DesignCriterion::D) V = cpp_inv_ * U.topRows(p_);
    constexpr std::size_t kChunk = 64;
    parallel_for((count() + kChunk - 1) / kChunk, threads_, [&](std::size_t t, std::size_t) {
      for (std::size_t j = t * kChunk; j < std::min(count(), (t + 1) * kChunk); ++j) {
        if (!want[j]) continue;
        const auto b = static_cast<Eigen::Index>(first_[j]);
        const auto r = static_cast<Eigen::Index>(first_[j + 1] - first_[j]);
        const auto Uj = U.middleCols(b, r);
        Eigen::MatrixXd S = Eigen::MatrixXd::Identity(r, r) + sign * (rows_.middleRows(b, r) * Uj);
        Eigen::FullPivLU<Eigen::MatrixXd> lu(S);
        if (!lu.isInvertible() || std::abs(lu.determinant()) < 1e-12) continue;
        const Eigen::MatrixXd Sinv = lu.inverse();
        const auto Up = Uj.topRows(p_);
        const Eigen::VectorXd dd = ((Up * Sinv).array() * Up.array()).rowwise().sum();
        const Eigen::VectorXd diag = cov_.topLeftCorner(p_, p_).diagonal() - sign * dd;
        // g^T C' g by the same update, per pair: g^T C g - s a^T S^-1 a, a = Up^T g.
        const Eigen::MatrixXd ag = Up.transpose() * g_;
        const double va_var =
            (va_vars_ - sign * ((Sinv * ag).array() * ag.array()).colwise().sum().transpose().matrix()).maxCoeff();
        if ((va_weight_ > 0 || c == DesignCriterion::Va) && !(va_var > 0)) continue;  // lost to cancellation (see exchange)
        double logdet = 0.0;
        if (c == DesignCriterion::D) {
          const Eigen::MatrixXd K =
              Eigen::MatrixXd::Identity(r, r) - sign * (Sinv * (Up.transpose() * V.middleCols(b, r)));
          const double det = K.determinant();
          if (!(det > 0)) continue;
          logdet = logdet_ + std::log(det);
        }
        out[j] = criterion(c, diag, logdet, va_var);
      }
    });
    return out;
  }

 private:
  Eigen::Block<const Eigen::MatrixXd> block(std::size_t j) const {
    return rows_.middleRows(static_cast<Eigen::Index>(first_[j]), static_cast<Eigen::Index>(first_[j + 1] - first_[j]));
  }
  double criterion(DesignCriterion c, const Eigen::VectorXd& diag, double logdet, double va_var) const {
    if (c == DesignCriterion::D) return logdet;
    if ((diag.array() > kUndetermined).any() || !(diag.array() > 0).all()) return kInf;
    if (c == DesignCriterion::Va) return std::sqrt(std::max(0.0, va_var));
    const Eigen::ArrayXd rel = diag.array() * w_.array();
    if (c == DesignCriterion::A) return rel.sum();
    return std::sqrt(std::max(rel.maxCoeff(), va_var * va_weight_));
  }
  void refresh() {
    const Eigen::LLT<Eigen::MatrixXd> llt(M_);
    cov_ = llt.solve(Eigen::MatrixXd::Identity(M_.rows(), M_.cols()));
    const Eigen::MatrixXd cpp = cov_.topLeftCorner(p_, p_);
    const Eigen::LLT<Eigen::MatrixXd> lp(cpp);
    cpp_inv_ = lp.solve(Eigen::MatrixXd::Identity(p_, p_));
    logdet_ = 2.0 * lp.matrixLLT().diagonal().array().log().sum();
    va_vars_ = (g_.transpose() * cpp * g_).diagonal();
  }

  Eigen::MatrixXd rows_;
  std::vector<std::size_t> first_;
  Eigen::Index p_;
  Eigen::VectorXd w_;
  Eigen::MatrixXd g_;
  double va_weight_ = 0.0;
  int threads_;
  Eigen::MatrixXd base_, M_, cov_, cpp_inv_;
  Eigen::VectorXd va_vars_;
  double logdet_ = 0.0;
  std::vector<bool> chosen_;
  std::vector<std::size_t> selection_;
};

std::size_t best(const std::vector<double>& v) {
  std::size_t b = v.size();
  for (std::size_t j = 0; j < v.size(); ++j)
    if (std::isfinite(v[j]) && (b == v.size() || v[j] < v[b])) b = j;
  return b;
}

bool better(double a, double b) { return a < b - 1e-9 * std::max(1.0, std::abs(b)); }

// Exchange passes (Fedorov 1972; the "modified Fedorov" of Cook & Nachtsheim 1980: one selected
// pose at a time, against every candidate): returns the number of exchanges.
std::size_t exchange(Design& d, DesignCriterion c, int max_passes, std::size_t& passes,
                     const std::function<void(const char*, std::size_t)>& progress) {
  std::size_t swaps = 0;
  for (int pass = 0; pass < max_passes; ++pass) {
    ++passes;
    if (progress) progress("exchange", d.size());
    bool improved = false;
    const std::vector<std::size_t> sel = d.selection();
    for (std::size_t i : sel) {
      const double before = d.value(c);
      d.remove(i);
      std::vector<bool> want(d.count());
      for (std::size_t j = 0; j < d.count(); ++j) want[j] = !d.chosen(j);
      const auto v = d.trial(c, +1, want);
      const std::size_t j = best(v);
      // The trial values come from rank-one updates of a covariance that can hold undetermined
      // directions (variance 1 / ridge) after the removal: their cancellation can be gross, so
      // a swap is kept only when the refreshed (re-factorised) criterion confirms it.
      bool swapped = false;
      if (j < v.size() && j != i && better(v[j], before)) {
        d.add(j);
        if (better(d.value(c), before)) {
          swapped = true;
        } else {
          d.remove(j);
        }
      }
      if (swapped) {
        ++swaps;
        improved = true;
      } else {
        d.add(i);
      }
    }
    if (!improved) break;
  }
  return swaps;
}

// The options with only the scale bars whose two balls the plan probes (identify refuses a bar
// with a ball never probed; such a bar adds nothing to the plan's information).
IdentificationOptions with_probed_scale_bars(IdentificationOptions o, const ProbingPlan& plan) {
  std::erase_if(o.scale_bars, [&](const ScaleBar& sb) {
    for (const auto& id : {sb.ball_a, sb.ball_b}) {
      const auto f = plan.feature_index(id);
      if (!f || std::none_of(plan.records.begin(), plan.records.end(),
                             [&](const ProbingRecord& r) { return r.feature == *f; }))
        return true;
    }
    return false;
  });
  return o;
}

const char* criterion_name(DesignCriterion c) {
  return c == DesignCriterion::D ? "D" : c == DesignCriterion::A ? "A" : c == DesignCriterion::Va ? "VA" : "max-u";
}

}  // namespace

PlanDesign design_plan(const Machine& m, const ProbingPlan& candidates_in, const DesignOptions& o) {
  if (candidates_in.records.empty())
    throw InputError({candidates_in.source, 0, ""}, "expected candidate configurations, found none");
  const Machine nominal = nominal_of(m);
  const ProbingPlan candidates = plan_targets(nominal, candidates_in);
  const std::size_t count = candidates.records.size();
  if (o.poses > count)
    throw InputError({o.poses_source, 0, std::to_string(o.poses)},
                     fmt::format("expected at most the {} candidate poses, found {}", count, o.poses));
  if (o.poses == 0 && o.target_u.empty() && o.target_va_u == 0)
    throw InputError({o.poses_source, 0, ""}, "expected a budget: a number of poses or target uncertainties");
  if (o.target_va_u != 0 && (!(o.target_va_u > 0) || !std::isfinite(o.target_va_u)))
    throw InputError({o.target_va_source, 0, ""}, fmt::format("expected an uncertainty > 0, found {:g}", o.target_va_u));
  if ((o.target_va_u > 0 || o.criterion == DesignCriterion::Va) && o.va_gradients.size() == 0)
    throw InputError({o.target_va_source, 0, ""}, "a target or criterion on the VA needs the VA's gradient");

  PlanDesign out;
  // A budget of targets is met with max-u whatever --criterion says (it applies to a number of poses).
  out.criterion = criterion_name(o.poses > 0 ? o.criterion : DesignCriterion::MaxU);
  out.all_candidates = predict_plan(m, candidates, o.model);  // throws when not identifiable at all
  const auto params = detail::parameter_indices(m, o.model.estimate, o.model.estimate_source);
  const std::size_t p = params.size();
  const auto all_params = m.parameters();
  const bool va = o.va_gradients.size() > 0;
  if (va && o.va_gradients.rows() != static_cast<Eigen::Index>(p))
    throw Error(fmt::format("design_plan: VA gradients of {} for {} parameters", o.va_gradients.rows(), p));
  auto va_u_of = [&](const Eigen::MatrixXd& C) {
    return std::sqrt(std::max(0.0, (o.va_gradients.transpose() * C * o.va_gradients).diagonal().maxCoeff()));
  };
  if (va) out.va_u_best = va_u_of(out.all_candidates.covariance);

  // Targets, by parameter.
  std::vector<double> target(p, 0.0);
  for (const auto& [name, u] : o.target_u) {
    std::size_t k = p;
    for (std::size_t i = 0; i < p; ++i)
      if (all_params[params[i]].name == name) k = i;
    if (k == p)
      throw InputError({o.target_source, 0, name}, fmt::format("'{}' is not one of the estimated parameters ({})",
                                                               printable(name), fmt::join(o.model.estimate, ",")));
    if (!(u > 0) || !std::isfinite(u))
      throw InputError({o.target_source, 0, name}, fmt::format("expected an uncertainty > 0, found {:g}", u));
    target[k] = u;
  }
  if (o.poses == 0) {
    std::string unmet;
    for (std::size_t k = 0; k < p; ++k)
      if (target[k] > 0 && out.all_candidates.parameters[k].u > target[k] * (1 + 1e-9))
        unmet += fmt::format("{}{}: target {:.4g} {}, best reachable {:.4g} {}", unmet.empty() ? "" : "; ",
                             out.all_candidates.parameters[k].name, target[k], out.all_candidates.parameters[k].unit,
                             out.all_candidates.parameters[k].u, out.all_candidates.parameters[k].unit);
    if (!unmet.empty())
      throw InputError({o.target_source, 0, ""},
                       fmt::format("the target cannot be met even with all {} candidate poses ({})", count, unmet));
    if (o.target_va_u > 0 && out.va_u_best > o.target_va_u * (1 + 1e-9))
      throw InputError({o.target_va_source, 0, ""},
                       fmt::format("the target cannot be met even with all {} candidate poses (the VA's standard "
                                   "uncertainty: target {:.4g} um, best reachable {:.4g} um)",
                                   count, o.target_va_u * 1e3, out.va_u_best * 1e3));
  }

  // Jacobian rows of every candidate (and the fixed scale-bar rows), unit-norm columns.
  const detail::ProbingModel pm(nominal, candidates, params, o.model.scale_bars, false, o.model.sigma_ball,
                                o.model.sigma_facet, o.model.sigma_scale_bar, o.model.sigma_ballbar, o.model.sigma_laser);
  Eigen::VectorXd res;
  Eigen::MatrixXd J;
  pm.evaluate(pm.initial(), res, &J);
  // Columns scaled to unit root-mean-square per candidate pose: an unknown that one pose
  // determines has a variance of order 1, one that none determines 1 / ridge.
  const Eigen::VectorXd norm =
      (J.colwise().norm().transpose() / std::sqrt(static_cast<double>(count))).cwiseMax(1e-300);
  J = J * norm.cwiseInverse().asDiagonal();
  std::vector<std::size_t> first{0};
  for (std::size_t b = 0; b < count; ++b) first.push_back(first.back() + pm.block_size(b));
  const auto record_rows = static_cast<Eigen::Index>(first.back());
  const Eigen::MatrixXd rows = J.topRows(record_rows);
  const Eigen::MatrixXd fixed = J.bottomRows(J.rows() - record_rows);
  // Weights of the relative variances: by target where targets are given (the others count only
  // as having to be determined), else by the best reachable uncertainty.
  Eigen::VectorXd w(static_cast<Eigen::Index>(p));
  // A budget on the VA alone: the parameters need only be determined (weight 0).
  const bool targets = std::any_of(target.begin(), target.end(), [](double t) { return t > 0; }) ||
                       (o.poses == 0 && o.target_va_u > 0);
  for (std::size_t k = 0; k < p; ++k) {
    const double ref = targets ? target[k] : out.all_candidates.parameters[k].u;
    const double s = 1.0 / norm[static_cast<Eigen::Index>(k)];  // scaled unit -> parameter unit
    w[static_cast<Eigen::Index>(k)] = ref > 0 ? (s / ref) * (s / ref) : 0.0;
  }
  // The VA's gradient in the scaled parameters (theta_scaled = theta * norm).
  Eigen::MatrixXd g;
  if (va) g = norm.head(static_cast<Eigen::Index>(p)).cwiseInverse().asDiagonal() * o.va_gradients;
  const double va_weight = o.target_va_u > 0 ? 1.0 / (o.target_va_u * o.target_va_u) : 0.0;
  Design d(rows, first, fixed, p, w, g, va_weight, o.threads);

  // Backward elimination from every candidate, then exchange. (A forward build-up is myopic
  // here: a scale bar fixes the scale only once both its balls are probed, so no single pose
  // improves the criterion and the build-up never takes the second ball.)
  std::vector<std::size_t> all(count);
  for (std::size_t j = 0; j < count; ++j) all[j] = j;
  d.set(all);
  auto remove_best = [&](DesignCriterion c, double limit) {
    std::vector<bool> want(d.count());
    for (std::size_t j = 0; j < d.count(); ++j) want[j] = d.chosen(j);
    const auto v = d.trial(c, -1, want);
    const std::size_t j = best(v);
    if (j == v.size() || !(v[j] <= limit)) return false;
    d.remove(j);
    if (!(d.value(c) <= limit * (1 + 1e-9))) {  // the update misjudged it (see exchange): undone
      d.add(j);
      return false;
    }
    return true;
  };
  if (o.poses > 0) {
    while (d.size() > o.poses) {
      if (o.progress) o.progress("eliminate", d.size());
      if (!remove_best(o.criterion, kInf)) break;
    }
    out.greedy_poses = d.size();
    out.exchanges = exchange(d, o.criterion, o.max_passes, out.passes, o.progress);
  } else {
    // Fewest poses for the targets (largest relative uncertainty <= 1): remove while a removal
    // keeps the targets; when none does, an exchange lowers the largest relative uncertainty and
    // removal is tried again. The count found is an upper bound of the true minimum.
    for (bool initial = true;; initial = false) {
      while (d.size() > 1) {
        if (o.progress) o.progress("eliminate", d.size());
        if (!remove_best(DesignCriterion::MaxU, 1.0)) break;
      }
      if (initial) out.greedy_poses = d.size();
      const std::size_t swaps = exchange(d, DesignCriterion::MaxU, o.max_passes, out.passes, o.progress);
      out.exchanges += swaps;
      if (swaps == 0 || d.size() <= 1) break;
      std::vector<bool> want(d.count());
      for (std::size_t j = 0; j < d.count(); ++j) want[j] = d.chosen(j);
      const auto v = d.trial(DesignCriterion::MaxU, -1, want);
      const std::size_t j = best(v);
      if (j == v.size() || !(v[j] <= 1.0)) break;
    }
  }
  out.selected = d.selection();
  std::sort(out.selected.begin(), out.selected.end());  // candidates come grouped by indexation
  out.plan = candidates;
  out.plan.records.clear();
  out.plan.source = "the designed plan";
  for (std::size_t j : out.selected) out.plan.records.push_back(candidates.records[j]);
  // Scale bars whose balls are not both probed add nothing: left out of the prediction.
  out.prediction = predict_plan(m, out.plan, with_probed_scale_bars(o.model, out.plan));
  for (std::size_t k = 0; k < p; ++k) {
    out.prediction.parameters[k].target = target[k];
    out.all_candidates.parameters[k].target = target[k];
    if (target[k] > 0 && out.prediction.parameters[k].u > target[k] * (1 + 1e-6)) out.target_met = false;
  }
  if (va) {
    out.va_u = va_u_of(out.prediction.covariance);
    if (o.target_va_u > 0 && out.va_u > o.target_va_u * (1 + 1e-6)) out.target_met = false;
  }
  out.criterion_value = d.value(o.poses > 0 ? o.criterion : DesignCriterion::MaxU);
  return out;
}

// ---------------------------------------------------------------------------------------------

PlanMonteCarlo plan_monte_carlo(const Machine& truth, const Machine& prior, const ProbingPlan& plan,
                                const IdentificationOptions& given, std::size_t runs, std::uint64_t seed, int threads,
                                const std::vector<std::vector<double>>& workspace) {
  const IdentificationOptions o = with_probed_scale_bars(given, plan);  // as design_plan predicts it
  const auto params = detail::parameter_indices(prior, o.estimate, o.estimate_source);
  const std::size_t p = params.size();
  std::vector<std::vector<double>> values(runs);
  std::vector<double> vas(runs, 0.0);
  std::vector<char> ok(runs, 0);
  parallel_for(runs, threads, [&](std::size_t k, std::size_t) {
    SimulationOptions so;
    so.noise = o.sigma_ball;
    so.seed = seed + k;
    // The bars' calibrated lengths are uncertain by sigma_scale_bar, as the prediction weighs them:
    // each run's true length is drawn about the nominal one (an exact bar would make the spread
    // of the scale-related parameters smaller than predicted).
    std::mt19937_64 rng(seed + k + 0x5ca1eULL);
    std::normal_distribution<double> g(0.0, 1.0);
    so.scale_bars = o.scale_bars;
    for (auto& bar : so.scale_bars) bar.length += o.sigma_scale_bar * g(rng);
    try {
      const Simulation sim = simulate_probing(truth, plan, so);
      const IdentificationResult r = identify(prior, sim.measurements, o);
      if (!r.converged || r.parameters.size() != p) return;
      for (const auto& e : r.parameters) values[k].push_back(e.value);
      if (!workspace.empty())  // one thread each: the runs are already spread over the threads
        vas[k] = volumetric_accuracy(grid_error_map(ErrorModel(r.machine), workspace, {1}).error).va.value;
      ok[k] = 1;
    } catch (const Error&) {
    }
  });
  PlanMonteCarlo out;
  out.runs = runs;
  out.mean.assign(p, 0.0);
  out.stdev.assign(p, 0.0);
  std::size_t n = 0;
  for (std::size_t k = 0; k < runs; ++k) {
    if (!ok[k]) {
      ++out.failed;
      continue;
    }
    ++n;
    for (std::size_t i = 0; i < p; ++i) out.mean[i] += values[k][i];
  }
  if (n < 2) return out;
  for (auto& v : out.mean) v /= static_cast<double>(n);
  for (std::size_t k = 0; k < runs; ++k)
    if (ok[k])
      for (std::size_t i = 0; i < p; ++i) out.stdev[i] += std::pow(values[k][i] - out.mean[i], 2);
  for (auto& v : out.stdev) v = std::sqrt(v / static_cast<double>(n - 1));
  if (!workspace.empty()) {
    out.va = true;
    for (std::size_t k = 0; k < runs; ++k)
      if (ok[k]) out.va_mean += vas[k];
    out.va_mean /= static_cast<double>(n);
    for (std::size_t k = 0; k < runs; ++k)
      if (ok[k]) out.va_stdev += std::pow(vas[k] - out.va_mean, 2);
    out.va_stdev = std::sqrt(out.va_stdev / static_cast<double>(n - 1));
  }
  return out;
}

// ---------------------------------------------------------------------------------------------

namespace {

// Unit direction in axis-value space (X, Y, Z values) that moves the tool along machine axis
// `machine_axis` (0 x, 1 y, 2 z) by +1: the linear axis along it, with its direction's sign.
Vec3 axis_space(const Machine& m, const std::vector<std::size_t>& lin, int machine_axis) {
  Vec3 u = Vec3::Zero();
  for (std::size_t k = 0; k < lin.size() && k < 3; ++k)
    if (m.axes[lin[k]].direction_axis == machine_axis) u[static_cast<Eigen::Index>(k)] = m.axes[lin[k]].direction_sign;
  return u;
}

}  // namespace

std::vector<ProbeTouch> probe_touches(const Machine& m, const ProbingPlan& plan, const ProbeCycle& c) {
  for (const auto& [name, v] : {std::pair{"ball diameter", c.ball_diameter}, std::pair{"tip diameter", c.tip_diameter},
                                std::pair{"approach", c.approach}, std::pair{"overtravel", c.overtravel},
                                std::pair{"clearance", c.clearance}})
    if (!(v > 0) || !std::isfinite(v)) throw InputError({name, 0, ""}, fmt::format("expected > 0 mm, found {:g}", v));
  if (c.touches_per_ball != 4 && c.touches_per_ball != 5)
    throw InputError({"touches per ball", 0, ""}, fmt::format("expected 4 or 5, found {}", c.touches_per_ball));
  const auto lin = linear_axes(m);
  if (lin.size() != 3) throw InputError({m.source, 0, ""}, "a probing program needs the three linear axes X, Y, Z");
  const int t = m.tool.tool_axis;
  // Tool frame directions in axis space: up (away from the workpiece along the tool) and two
  // across it. A ball centre from 4 touches: the pole and three of the equator.
  const Vec3 up = axis_space(m, lin, t), a = axis_space(m, lin, (t + 1) % 3), b = axis_space(m, lin, (t + 2) % 3);
  const double rho = (c.ball_diameter + c.tip_diameter) / 2;
  const ErrorModel nominal(nominal_of(m));
  std::vector<ProbeTouch> out;
  auto at = [&](const std::vector<double>& q, const Vec3& p) {
    std::vector<double> r = q;
    for (std::size_t k = 0; k < 3; ++k) r[lin[k]] = p[static_cast<Eigen::Index>(k)];
    return r;
  };
  for (std::size_t i = 0; i < plan.records.size(); ++i) {
    const ProbingRecord& r = plan.records[i];
    const ProbeFeature::Kind kind = plan.features[r.feature].kind;
    if (kind != ProbeFeature::Kind::Ball && kind != ProbeFeature::Kind::Facet)
      throw InputError({plan.source, r.line, "kind"},
                       fmt::format("a probing program probes balls and facets, not a {}", feature_kind_name(kind)));
    const Vec3 target(r.q[lin[0]], r.q[lin[1]], r.q[lin[2]]);
    if (plan.features[r.feature].kind == ProbeFeature::Kind::Ball) {
      std::vector<Vec3> dirs{up, a, -a, b, -b};
      if (c.touches_per_ball == 4) dirs.pop_back();
      for (const Vec3& u : dirs)
        out.push_back({i, at(r.q, target + (rho + c.approach) * u), at(r.q, target + (rho - c.overtravel) * u),
                       at(r.q, target + rho * u)});
      continue;
    }
    // Facet: along the probing axis (the linear axis whose motion is most nearly along the
    // normal, as plan_targets chooses it), against the normal.
    const Vec3& n = plan.features[r.feature].normal;
    const Vec3 p0 = nominal.nominal_pose(r.q).t;
    std::size_t k = 0;
    double best_slope = 0.0;
    for (std::size_t j = 0; j < 3; ++j) {
      std::vector<double> q = r.q;
      q[lin[j]] += 1.0;
      const double slope = n.dot(nominal.nominal_pose(q).t - p0);
      if (std::abs(slope) > std::abs(best_slope)) best_slope = slope, k = j;
    }
    Vec3 u = Vec3::Zero();
    u[static_cast<Eigen::Index>(k)] = best_slope > 0 ? 1.0 : -1.0;  // the side the probe comes from
    out.push_back({i, at(r.q, target + c.approach * u), at(r.q, target - c.overtravel * u), at(r.q, target)});
  }
  return out;
}

ProbingPlan measurements_from_contacts(const Machine& m, const ProbingPlan& plan, const ProbeCycle& c,
                                       const std::vector<LoggedContact>& contacts, const std::string& log_source) {
  const auto touches = probe_touches(m, plan, c);
  const auto lin = linear_axes(m);
  const auto rot = rotary_axes(m);
  const std::string source = contacts.empty() ? std::string("probe log") : contacts.front().source;
  if (contacts.size() < touches.size()) {
    // A short log: name the first contact missing, where the program stopped or a probe never
    // tripped (LinuxCNC: "G38.2 move finished without making contact", the program ends there).
    const std::size_t k = contacts.size();
    const ProbeTouch& t = touches[k];
    std::size_t nth = 1;
    for (std::size_t i = k; i > 0 && touches[i - 1].record == t.record; --i) ++nth;
    throw InputError({contacts.empty() ? log_source : source, contacts.empty() ? 0 : contacts.back().line, ""},
                     fmt::format("expected {} contacts, found {}: contact {} is missing (touch {} of the plan's record "
                                 "{}, line {}): the probe did not trip there (LinuxCNC: G38.2 move finished without "
                                 "making contact) or the program stopped before it",
                                 touches.size(), k, k + 1, nth, t.record + 1, plan.records[t.record].line));
  }
  if (contacts.size() != touches.size()) {
    const int line = contacts.size() > touches.size() ? contacts[touches.size()].line
                                                      : (contacts.empty() ? 0 : contacts.back().line);
    throw InputError({source, line, ""},
                     fmt::format("expected {} contacts (the program's probing moves for {} records), found {}{}",
                                 touches.size(), plan.records.size(), contacts.size(),
                                 contacts.size() > touches.size() ? ": the first extra one is on this line"
                                                                  : ": the log ends early"));
  }
  ProbingPlan out = plan;
  out.measured = true;
  out.source = source;
  std::vector<std::vector<Point3>> ball(plan.records.size());
  for (std::size_t i = 0; i < touches.size(); ++i) {
    const ProbeTouch& t = touches[i];
    const LoggedContact& lc = contacts[i];
    const ProbingRecord& r = plan.records[t.record];
    for (std::size_t k : rot)
      if (std::isfinite(lc.q[k]) && std::abs(lc.q[k] - r.q[k]) > 1e-6)
        throw InputError({lc.source, lc.line, std::string(1, m.axes[k].letter)},
                         fmt::format("contact {} belongs to the plan's record {} (line {}) at {} = {:.4f} deg, found "
                                     "{:.4f} deg: the log does not follow the plan",
                                     i + 1, t.record + 1, r.line, m.axes[k].letter, r.q[k] * 180 / std::numbers::pi,
                                     lc.q[k] * 180 / std::numbers::pi));
    Vec3 p, e;
    for (std::size_t k = 0; k < 3; ++k) {
      p[static_cast<Eigen::Index>(k)] = lc.q[lin[k]];
      e[static_cast<Eigen::Index>(k)] = t.expected[lin[k]];
    }
    if (!p.allFinite())
      throw InputError({lc.source, lc.line, ""}, "expected the X, Y and Z of the contact, found them missing");
    if ((p - e).norm() > c.approach + c.overtravel)
      throw InputError({lc.source, lc.line, ""},
                       fmt::format("contact {} is {:.3f} mm from where the plan's record {} (line {}) expects it, more "
                                   "than approach + overtravel ({:g} mm): the log does not follow the plan",
                                   i + 1, (p - e).norm(), t.record + 1, r.line, c.approach + c.overtravel));
    if (plan.features[r.feature].kind == ProbeFeature::Kind::Ball) {
      ball[t.record].push_back(p);
    } else {
      for (std::size_t k = 0; k < 3; ++k) out.records[t.record].q[lin[k]] = p[static_cast<Eigen::Index>(k)];
    }
  }
  for (std::size_t i = 0; i < plan.records.size(); ++i) {
    if (ball[i].empty()) continue;
    const auto fit = fit_sphere(ball[i]);
    if (!fit)
      throw InputError({source, 0, ""}, fmt::format("the touches of the plan's record {} (line {}) do not define a sphere",
                                                    i + 1, plan.records[i].line));
    for (std::size_t k = 0; k < 3; ++k) out.records[i].q[lin[k]] = fit->centre[static_cast<Eigen::Index>(k)];
  }
  return out;
}

// ---------------------------------------------------------------------------------------------

std::pair<std::size_t, double> probe_safe_retract(const Machine& m) {
  std::size_t tz = m.axes.size();
  for (std::size_t k = 0; k < m.axes.size(); ++k)
    if (m.axes[k].kind == AxisKind::Linear && m.axes[k].direction_axis == m.tool.tool_axis) tz = k;
  if (tz == m.axes.size() || !m.axes[tz].travel)
    throw InputError({m.source, 0, ""}, "the linear axis along the tool needs a travel (its end is the safe retract)");
  const Axis& z = m.axes[tz];
  return {tz, z.direction_sign > 0 ? z.travel->max : z.travel->min};
}

TimeEstimate estimate_time(const Machine& m, const ProbingPlan& plan, const ProbeCycle& cycle, const TimingOptions& o) {
  for (const auto& [name, v] : {std::pair{"rapid", o.rapid}, std::pair{"rotary speed", o.rotary_speed},
                                std::pair{"probing feed", o.probe_feed}, std::pair{"move feed", o.move_feed}})
    if (!(v > 0) || !std::isfinite(v))
      throw InputError({name, 0, ""}, fmt::format("expected a speed > 0, found {:g}", v));
  if (!(o.settle >= 0) || !std::isfinite(o.settle))
    throw InputError({"settle", 0, ""}, fmt::format("expected a time >= 0 s, found {:g}", o.settle));
  TimeEstimate t;
  if (plan.records.empty()) return t;
  const std::vector<ProbeTouch> touches = probe_touches(m, plan, cycle);
  const auto [tz, safe] = probe_safe_retract(m);
  const auto rot = rotary_axes(m);
  const auto lin = linear_axes(m);
  const double rapid = o.rapid / 60.0, feed = o.move_feed / 60.0, probe = o.probe_feed / 60.0;  // mm/s
  const double rotary = o.rotary_speed / 60.0 * std::numbers::pi / 180.0;                      // rad/s
  // G0: every axis at its rapid, the largest change sets the time; G1 and the probing move: the
  // feed along the path of the linear axes (RS274/NGC feed rate mode G94, LinuxCNC's G1).
  auto g0 = [&](const std::vector<double>& a, const std::vector<double>& b) {
    double d = 0.0;
    for (std::size_t k : lin) d = std::max(d, std::abs(b[k] - a[k]));
    return d / rapid;
  };
  auto path = [&](const std::vector<double>& a, const std::vector<double>& b) {
    double d = 0.0;
    for (std::size_t k : lin) d += (b[k] - a[k]) * (b[k] - a[k]);
    return std::sqrt(d);
  };
  const double rho = (cycle.ball_diameter + cycle.tip_diameter) / 2;
  const double top_offset = m.axes[tz].direction_sign * (rho + cycle.clearance);
  std::vector<double> at;  // the linear axes' position (chain order); empty before the first record
  std::size_t current = plan.records.size();
  const ProbingRecord* last = nullptr;
  for (std::size_t i = 0; i < touches.size(); ++i) {
    const ProbeTouch& tt = touches[i];
    const ProbingRecord& r = plan.records[tt.record];
    std::vector<double> over = tt.start;
    over[tz] = safe;
    if (tt.record != current) {
      current = tt.record;
      if (!at.empty()) {
        std::vector<double> up = at;
        up[tz] = safe;
        t.moves += g0(at, up);
        double index = 0.0;
        for (std::size_t k : rot) index = std::max(index, std::abs(r.q[k] - last->q[k]));
        if (index > 0) {
          t.indexing += index / rotary + o.settle;
          ++t.indexations;
        }
        t.moves += g0(up, over);
      } else {
        ++t.indexations;
      }
      last = &r;
      at = over;
    } else if (plan.features[r.feature].kind == ProbeFeature::Kind::Ball) {
      // Between a ball's touches: up to the clearance level above it, over the next start.
      std::vector<double> lift = at, above = tt.start;
      lift[tz] = above[tz] = r.q[tz] + top_offset;
      t.moves += (path(at, lift) + path(lift, above)) / feed;
      at = above;
    }
    t.moves += path(at, tt.start) / feed;
    const double approach = path(tt.start, tt.expected);
    t.probing += approach / probe + approach / feed;
    ++t.touches;
    at = tt.start;
  }
  std::vector<double> up = at;
  up[tz] = safe;
  t.moves += g0(at, up);
  t.total = t.moves + t.probing + t.indexing;
  return t;
}

}  // namespace mtcal
