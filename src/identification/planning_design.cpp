// Planning a probing measurement: the Wynn-Fedorov design of a plan and its Monte Carlo check.
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
#include "planning_common.hpp"

namespace mtcal {

using namespace planning_detail;  // the shared helpers of the planning units

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace

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
  // The poses: a probing record each, or every record of one ballbar or laser feature (a circle, a
  // line), whose rows enter and leave the information together (plan_poses).
  std::vector<std::vector<std::size_t>> poses_of;
  {
    std::map<std::size_t, std::size_t> instrument;  // feature -> pose
    for (std::size_t j = 0; j < candidates.records.size(); ++j) {
      const std::size_t f = candidates.records[j].feature;
      const auto kind = candidates.features[f].kind;
      if (kind == ProbeFeature::Kind::Ballbar || kind == ProbeFeature::Kind::Laser) {
        const auto [it, fresh] = instrument.emplace(f, poses_of.size());
        if (fresh) poses_of.emplace_back();
        poses_of[it->second].push_back(j);
      } else {
        poses_of.push_back({j});
      }
    }
  }
  const std::size_t count = poses_of.size();
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
  // The records' rows (block order), gathered pose by pose.
  std::vector<std::size_t> record_first{0};
  for (std::size_t b = 0; b < candidates.records.size(); ++b) record_first.push_back(record_first.back() + pm.block_size(b));
  const auto record_rows = static_cast<Eigen::Index>(record_first.back());
  std::vector<std::size_t> first{0};
  Eigen::MatrixXd rows(record_rows, J.cols());
  for (const auto& pose : poses_of) {
    const std::size_t begin = first.back();
    std::size_t at = begin;
    for (std::size_t j : pose) {
      const auto n = static_cast<Eigen::Index>(record_first[j + 1] - record_first[j]);
      rows.middleRows(static_cast<Eigen::Index>(at), n) = J.middleRows(static_cast<Eigen::Index>(record_first[j]), n);
      at += static_cast<std::size_t>(n);
    }
    first.push_back(at);
    // A circle's or line's own unknowns (pivot and length offset; laser offset) are seen by its rows
    // only: they are eliminated in the block (the rows projected off their columns, P = Jn (Jn^T
    // Jn)^-1 Jn^T), which leaves the information of the other unknowns exactly the Schur complement
    // (Atkinson, Donev & Tobias 2007, ch. 10, Ds-optimality) and lets the exchange add and remove
    // the pose whole (with the nuisance columns in, removing it would leave them to the ridge).
    const ProbeFeature& f = candidates.features[candidates.records[pose.front()].feature];
    if (f.kind != ProbeFeature::Kind::Ballbar && f.kind != ProbeFeature::Kind::Laser) continue;
    const auto c = static_cast<Eigen::Index>(pm.ball_column(candidates.records[pose.front()].feature));
    const auto u = static_cast<Eigen::Index>(unknowns_of(f.kind));
    auto block = rows.middleRows(static_cast<Eigen::Index>(begin), static_cast<Eigen::Index>(at - begin));
    const Eigen::MatrixXd Jn = block.middleCols(c, u);
    const Eigen::MatrixXd coef = (Jn.transpose() * Jn).ldlt().solve(Jn.transpose() * block);
    block -= Jn * coef;
    block.middleCols(c, u).setZero();
  }
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
  for (std::size_t pose : d.selection()) out.selected.insert(out.selected.end(), poses_of[pose].begin(), poses_of[pose].end());
  std::sort(out.selected.begin(), out.selected.end());  // candidates come grouped by indexation
  out.plan = candidates;
  out.plan.records.clear();
  out.plan.source = "the designed plan";
  for (std::size_t j : out.selected) out.plan.records.push_back(candidates.records[j]);
  out.poses = plan_poses(out.plan);
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

}  // namespace mtcal
