// Viprey 2015 section 4: every k-subset of candidate parameters with a full-rank model.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <fmt/format.h>

#include "mtcal/util/parallel.hpp"
#include "mtcal/identification/identification.hpp"
#include "mtcal/util/errors.hpp"
#include "probing_model.hpp"

namespace mtcal {

namespace {

// Depth-first search over subsets in increasing index order with a Cholesky factor L of the
// scaled normal matrix G over the current set (fixed columns first). Adding column j costs one
// forward substitution; a pivot below the tolerance means column j lies (numerically) in the
// span of the set, so the set with j and every superset of it is deficient: skipped.
struct Search {
  const Eigen::MatrixXd& G;  // Gram matrix of unit columns: fixed (0..f-1), then candidates
  const Eigen::VectorXd& c;  // S^T r0 (first-order residue), or empty
  double r0_2;               // |r0|^2
  std::size_t f, k;
  double tol;
  std::vector<ParameterSubset> found;
  std::uint64_t full_rank = 0, pruned = 0;

  std::vector<std::size_t> set;  // columns of G in the current set
  Eigen::MatrixXd L;             // lower triangular, size of set
  Eigen::VectorXd y;             // L^-1 c_set

  bool push(std::size_t j) {
    const auto s = static_cast<Eigen::Index>(set.size());
    Eigen::VectorXd g(s);
    for (Eigen::Index i = 0; i < s; ++i)
      g[i] = G(static_cast<Eigen::Index>(set[static_cast<std::size_t>(i)]), static_cast<Eigen::Index>(j));
    const Eigen::VectorXd l =
        s ? Eigen::VectorXd(L.topLeftCorner(s, s).triangularView<Eigen::Lower>().solve(g)) : Eigen::VectorXd();
    const double p2 = G(static_cast<Eigen::Index>(j), static_cast<Eigen::Index>(j)) - l.squaredNorm();
    // sigma_min <= the distance of a column from the span of the others (the pivot).
    if (!(p2 > tol * tol)) return false;
    L.conservativeResize(s + 1, s + 1);
    L.row(s).head(s) = l.transpose();
    L.col(s).head(s).setZero();
    L(s, s) = std::sqrt(p2);
    if (c.size()) {
      y.conservativeResize(s + 1);
      y[s] = (c[static_cast<Eigen::Index>(j)] - (s ? l.dot(y.head(s)) : 0.0)) / L(s, s);
    }
    set.push_back(j);
    return true;
  }
  void pop() {
    set.pop_back();
    const auto s = static_cast<Eigen::Index>(set.size());
    L.conservativeResize(s, s);
    if (c.size()) y.conservativeResize(s);
  }

  void leaf() {
    const auto s = static_cast<Eigen::Index>(set.size());
    Eigen::MatrixXd Gs(s, s);
    for (Eigen::Index a = 0; a < s; ++a)
      for (Eigen::Index b = 0; b < s; ++b)
        Gs(a, b) = G(static_cast<Eigen::Index>(set[static_cast<std::size_t>(a)]),
                     static_cast<Eigen::Index>(set[static_cast<std::size_t>(b)]));
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(Gs, Eigen::EigenvaluesOnly);
    const double lmin = std::max(0.0, eig.eigenvalues()[0]), lmax = eig.eigenvalues()[s - 1];
    if (!(lmin > tol * tol * lmax)) {
      ++pruned;
      return;
    }
    ++full_rank;
    ParameterSubset p;
    for (std::size_t i = f; i < set.size(); ++i) p.members.push_back(set[i] - f);
    p.condition = std::sqrt(lmax / lmin);
    p.residue = c.size() ? std::sqrt(std::max(0.0, r0_2 - y.squaredNorm())) : std::numeric_limits<double>::quiet_NaN();
    found.push_back(std::move(p));
  }

  void descend(std::size_t next, std::size_t n) {
    if (set.size() == f + k) {
      leaf();
      return;
    }
    const std::size_t need = f + k - set.size();
    for (std::size_t j = next; j + need <= n; ++j) {
      if (!push(f + j)) {
        ++pruned;
        continue;
      }
      descend(j + 1, n);
      pop();
    }
  }
};

// C(n, k), saturating at the largest uint64 (r * (n - k + i) is divisible by i at every step).
std::uint64_t binomial(std::uint64_t n, std::uint64_t k) {
  if (k > n) return 0;
  std::uint64_t r = 1;
  for (std::uint64_t i = 1; i <= k; ++i) {
    std::uint64_t t = 0;
    if (__builtin_mul_overflow(r, n - k + i, &t)) return std::numeric_limits<std::uint64_t>::max();
    r = t / i;
  }
  return r;
}

}  // namespace

SubsetAnalysis full_rank_subsets(const Machine& machine, const ProbingPlan& plan, const SubsetOptions& o,
                                 const IdentificationOptions& mo) {
  // First order about the error-free machine (Viprey: little displacement theory), where the
  // equivalences between errors are exact.
  Machine m = machine;
  m.clear_errors();
  // The Jacobian at the nominal targets (structural, as identifiability); the residue's r0 at
  // the readings of a measurement file.
  const ProbingPlan p = plan_targets(m, plan);
  const auto always = detail::parameter_indices(m, o.always, o.always_source);
  const auto cand = detail::parameter_indices(m, o.candidates, o.candidates_source);
  for (std::size_t c : cand)
    if (std::find(always.begin(), always.end(), c) != always.end())
      throw InputError({o.candidates_source, 0, m.parameters()[c].name}, "a candidate is also in " + o.always_source);
  if (cand.empty()) throw InputError({o.candidates_source, 0, ""}, "expected candidate parameters, found none");
  if (o.by_residue && !plan.measured)
    throw InputError({o.by_residue_source, 0, ""},
                     "ranking by residue needs measurements (a file with the readings X, Y, Z)");
  if (o.choose < 1 || o.choose > cand.size())
    throw InputError({o.choose_source, 0, ""},
                     fmt::format("expected a subset size from 1 to {} (the candidates), found {}", cand.size(),
                                 o.choose));
  if (!(o.rank_tolerance >= 1e-7 && o.rank_tolerance < 1))
    throw InputError({o.rank_tolerance_source, 0, ""},
                     fmt::format("expected a tolerance from 1e-7 to 1 for the subset analysis (its normal-matrix test "
                                 "resolves no finer), found {:g}",
                                 o.rank_tolerance));
  std::vector<std::size_t> params = always;
  params.insert(params.end(), cand.begin(), cand.end());
  const detail::ProbingModel pm(m, p, params, mo.scale_bars, mo.estimate_pretravel, mo.sigma_ball, mo.sigma_facet,
                                mo.sigma_scale_bar, mo.sigma_ballbar, mo.sigma_laser);
  Eigen::VectorXd r0;
  Eigen::MatrixXd J;
  pm.evaluate(pm.initial(), r0, &J);
  // Columns: fixed = artefact unknowns (+ pre-travel) and always-parameters; then candidates.
  std::vector<std::size_t> fixed;
  for (std::size_t j = params.size(); j < pm.unknowns(); ++j) fixed.push_back(j);
  for (std::size_t j = 0; j < always.size(); ++j) fixed.push_back(j);
  const std::size_t f = fixed.size(), n = cand.size();
  Eigen::MatrixXd S(J.rows(), static_cast<Eigen::Index>(f + n));
  for (std::size_t j = 0; j < f; ++j) S.col(static_cast<Eigen::Index>(j)) = J.col(static_cast<Eigen::Index>(fixed[j]));
  for (std::size_t j = 0; j < n; ++j)
    S.col(static_cast<Eigen::Index>(f + j)) = J.col(static_cast<Eigen::Index>(always.size() + j));
  const auto names = pm.names();
  for (Eigen::Index j = 0; j < S.cols(); ++j) {
    const double norm = S.col(j).norm();
    if (norm == 0) {
      if (static_cast<std::size_t>(j) < f)
        throw InputError({o.always_source, 0, ""},
                         "'" + names[fixed[static_cast<std::size_t>(j)]] + "' has no effect on the measurements");
      continue;  // a candidate with no effect: every subset holding it is deficient
    }
    S.col(j) /= norm;
  }
  const Eigen::MatrixXd G = S.transpose() * S;
  // With measurements, the first-order residue of each subset (Viprey eq. 5): |r0 + S dx| minimised.
  Eigen::VectorXd c;
  double r0_2 = 0;
  if (plan.measured) {
    const detail::ProbingModel measured(m, plan, params, mo.scale_bars, mo.estimate_pretravel, mo.sigma_ball,
                                        mo.sigma_facet, mo.sigma_scale_bar, mo.sigma_ballbar, mo.sigma_laser);
    measured.evaluate(measured.initial(), r0, nullptr);
    c = -(S.transpose() * r0);
    r0_2 = r0.squaredNorm();
  }
  SubsetAnalysis out;
  out.examined = binomial(n, o.choose);
  if (o.max_subsets && out.examined > o.max_subsets)
    throw LimitError(Limit::Time, {o.choose_source, 0, ""},
                     fmt::format("C({}, {}) = {:.3g} subsets of the candidates to examine, more than the {:.3g} that "
                                 "fit in the time limit",
                                 n, o.choose, static_cast<double>(out.examined), static_cast<double>(o.max_subsets)));
  for (std::size_t ci : cand) out.candidates.push_back(m.parameters()[ci].name);
  // The fixed part must be full rank by itself.
  {
    Search base{G, c, r0_2, f, 0, o.rank_tolerance, {}, 0, 0, {}, {}, {}};
    for (std::size_t j = 0; j < f; ++j)
      if (!base.push(j))
        throw InputError({o.always_source, 0, ""},
                         "the artefact unknowns and the parameters in every subset are already not "
                         "identifiable together (at '" +
                             names[fixed[j]] + "'); see mtcal identifiability");
  }
  // One task per leading candidate; each search owns its factor.
  const std::size_t tasks = n - o.choose + 1;
  std::vector<Search> results;
  results.reserve(tasks);
  for (std::size_t t = 0; t < tasks; ++t)
    results.push_back(Search{G, c, r0_2, f, o.choose, o.rank_tolerance, {}, 0, 0, {}, {}, {}});
  // Progress in subsets: task t covers the C(n - 1 - t, k - 1) subsets that start with candidate t.
  std::atomic<std::uint64_t> done{0};
  const std::uint64_t total = binomial(n, o.choose);
  parallel_for(tasks, o.threads, [&](std::size_t t, std::size_t) {
    Search& s = results[t];
    struct Report {
      const SubsetOptions& o;
      std::atomic<std::uint64_t>& done;
      std::uint64_t part, total;
      ~Report() {
        if (o.progress) o.progress(static_cast<std::size_t>(done += part), static_cast<std::size_t>(total));
      }
    } report{o, done, binomial(n - 1 - t, o.choose - 1), total};
    for (std::size_t j = 0; j < f; ++j) s.push(j);
    if (!s.push(f + t)) {
      ++s.pruned;
      return;
    }
    s.descend(t + 1, n);
    // Only the best `keep` of a task can be among the best `keep` of all: bounded memory.
    auto better = [&](const ParameterSubset& a, const ParameterSubset& b) {
      return o.by_residue ? a.residue < b.residue : a.condition < b.condition;
    };
    if (s.found.size() > o.keep) {
      std::nth_element(s.found.begin(), s.found.begin() + static_cast<std::ptrdiff_t>(o.keep), s.found.end(), better);
      s.found.resize(o.keep);
    }
  });
  for (auto& s : results) {
    out.full_rank += s.full_rank;
    out.pruned += s.pruned;
    for (auto& found : s.found) out.subsets.push_back(std::move(found));
  }
  std::stable_sort(out.subsets.begin(), out.subsets.end(), [&](const ParameterSubset& a, const ParameterSubset& b) {
    return o.by_residue ? a.residue < b.residue : a.condition < b.condition;
  });
  if (out.subsets.size() > o.keep) out.subsets.resize(o.keep);
  return out;
}

}  // namespace mtcal
