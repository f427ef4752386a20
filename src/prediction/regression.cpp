#include "mtcal/prediction/regression.hpp"
#include "mtcal/fitting/least_squares.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include <Eigen/Dense>
#include <fmt/format.h>

// Ceres' headers are not clean under this project's warning set; they stay in this file.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wsign-conversion"
#pragma GCC diagnostic ignored "-Wpedantic"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#include <ceres/ceres.h>
#pragma GCC diagnostic pop

#include "mtcal/util/errors.hpp"
#include "mtcal/util/parse.hpp"

namespace mtcal {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr int kMaxParams = 4;

struct FormName {
  ModelForm form;
  std::string_view name;
};
constexpr FormName kForms[] = {{ModelForm::Polynomial, "polynomial"},
                               {ModelForm::ExpApproach, "exp_approach"},
                               {ModelForm::StretchedExp, "stretched_exp"},
                               {ModelForm::LogisticLn, "logistic_ln"},
                               {ModelForm::Gompertz, "gompertz"},
                               {ModelForm::Saturation, "saturation"},
                               {ModelForm::Power, "power"}};

std::size_t parameter_count(const ModelSpec& s) {
  switch (s.form) {
    case ModelForm::Polynomial: return static_cast<std::size_t>(s.degree) + (s.fixed_intercept ? 0 : 1);
    case ModelForm::ExpApproach: return 3;
    case ModelForm::StretchedExp: return 4;
    case ModelForm::LogisticLn: return 4;
    case ModelForm::Gompertz: return 3;
    case ModelForm::Saturation: return 2;
    case ModelForm::Power: return 2;
  }
  return 0;
}

// x^e for x >= 0 with its limit at x = 0: 0 for e > 0, 1 for e = 0 (x^0 = 1), +inf for e < 0.
template <class T>
T pow_nonneg(double x, const T& e) {
  using std::exp;
  if (x == 0.0) {
    if (e > T(0.0)) return T(0.0);
    if (e == T(0.0)) return T(1.0);
    return T(std::numeric_limits<double>::infinity());
  }
  return exp(e * std::log(x));
}

// The nonlinear forms, templated so that Ceres' Jets give exact derivatives (section comments
// in the header name the thesis equations of each form).
template <class T>
T eval_nonlinear(ModelForm f, const T* p, double x) {
  using std::exp;
  switch (f) {
    case ModelForm::ExpApproach: return p[0] - p[1] * exp(-p[2] * x);
    case ModelForm::StretchedExp:
      if (x == 0.0) {
        // Limits of exp(-c x^d) as x -> 0+: 1 for d > 0, exp(-c) for d = 0; for d < 0, x^d -> +inf:
        // 0 for c > 0, 1 for c = 0, divergent for c < 0.
        if (p[3] > T(0.0)) return p[0] + p[1];
        if (p[3] == T(0.0)) return p[0] + p[1] * exp(-p[2]);
        if (p[2] > T(0.0)) return p[0];
        if (p[2] == T(0.0)) return p[0] + p[1];
        return T(kNaN);
      }
      return p[0] + p[1] * exp(-p[2] * pow_nonneg(x, p[3]));
    case ModelForm::LogisticLn:
      if (!(p[3] > T(0.0))) return T(kNaN);  // ln(x / x0) needs x0 > 0
      if (x == 0.0) {
        // k ln(x / x0) -> -inf (k > 0), +inf (k < 0), 0 (k = 0) as x -> 0+.
        if (p[2] > T(0.0)) return p[0] - p[1];
        if (p[2] < T(0.0)) return p[0];
        return p[0] - p[1] / T(2.0);
      }
      return p[0] - p[1] / (T(1.0) + exp(p[2] * (std::log(x) - log(p[3]))));
    case ModelForm::Gompertz: return p[0] * exp(-exp(p[1] - p[2] * x));
    case ModelForm::Saturation: return p[0] * x / (p[1] + x);
    case ModelForm::Power:
      if (x == 0.0) {
        // 0^b: 0 for b > 0, 1 for b = 0; undefined (a pole) for b < 0.
        if (p[1] > T(0.0)) return T(0.0);
        if (p[1] == T(0.0)) return p[0];
        return T(kNaN);
      }
      return p[0] * pow_nonneg(x, p[1]);
    case ModelForm::Polynomial: break;
  }
  return T(kNaN);
}

void check_data(const ModelSpec& spec, std::span<const double> x, std::span<const double> y) {
  if (x.size() != y.size())
    throw InputError({"", 0, "y"},
                     fmt::format("expected as many y as x values, found {} x and {} y", x.size(), y.size()));
  const std::size_t p = parameter_count(spec);
  if (x.size() < p)
    throw InputError({"", 0, "x"}, fmt::format("{} has {} parameters: expected at least {} points, found {}",
                                               spec.label(), p, p, x.size()));
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!std::isfinite(x[i]) || !std::isfinite(y[i]))
      throw InputError({"", 0, std::isfinite(x[i]) ? "y" : "x"},
                       fmt::format("point {}: expected finite values", i + 1));
    if (x[i] < domain_lower_bound(spec.form))
      throw InputError({"", 0, "x"},
                       fmt::format("point {}: {} needs x >= 0, found {}", i + 1, to_string(spec.form), x[i]));
  }
}

double max_abs(std::span<const double> v) {
  double m = 0.0;
  for (double a : v) m = std::max(m, std::abs(a));
  return m;
}

double rss_of(const Model& m, std::span<const double> x, std::span<const double> y) {
  double s = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double r = y[i] - m(x[i]);
    s += r * r;
  }
  return std::isfinite(s) ? s : std::numeric_limits<double>::infinity();
}

// ---- polynomials: exact linear least squares on x scaled to [-1, 1] for conditioning.
std::optional<Model> fit_polynomial(const ModelSpec& spec, std::span<const double> x, std::span<const double> y) {
  const std::size_t n = x.size();
  const int first = spec.fixed_intercept ? 1 : 0;
  const auto cols = static_cast<Eigen::Index>(parameter_count(spec));
  const double xs = std::max(max_abs(x), 1e-300);
  Eigen::MatrixXd A(static_cast<Eigen::Index>(n), cols);
  Eigen::VectorXd b(static_cast<Eigen::Index>(n));
  for (std::size_t i = 0; i < n; ++i) {
    const auto r = static_cast<Eigen::Index>(i);
    for (Eigen::Index c = 0; c < cols; ++c) A(r, c) = std::pow(x[i] / xs, static_cast<double>(c + first));
    b(r) = y[i] - spec.fixed_intercept.value_or(0.0);
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
  if (qr.rank() < cols) return std::nullopt;
  const Eigen::VectorXd c = qr.solve(b);
  Model m{spec, {}};
  for (Eigen::Index k = 0; k < cols; ++k) m.p.push_back(c(k) / std::pow(xs, static_cast<double>(k + first)));
  return m;
}

// ---- nonlinear forms.
struct Residual {
  ModelForm form;
  double x, y, scale;
  template <class T>
  bool operator()(T const* const* p, T* r) const {
    r[0] = (T(y) - eval_nonlinear(form, p[0], x)) / scale;
    return true;
  }
};

// Least squares in the amplitude parameters for fixed nonlinear ones: y ~ sum_k coef_k g_k(x).
// Returns the coefficients and the RSS, or nothing when the columns are degenerate.
std::optional<std::pair<Eigen::VectorXd, double>> linear_part(const std::vector<std::vector<double>>& g,
                                                              std::span<const double> y) {
  const auto n = static_cast<Eigen::Index>(y.size());
  const auto k = static_cast<Eigen::Index>(g.size());
  Eigen::MatrixXd A(n, k);
  Eigen::VectorXd b(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index c = 0; c < k; ++c) {
      const double v = g[static_cast<std::size_t>(c)][static_cast<std::size_t>(i)];
      if (!std::isfinite(v)) return std::nullopt;
      A(i, c) = v;
    }
    b(i) = y[static_cast<std::size_t>(i)];
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
  if (qr.rank() < k) return std::nullopt;
  Eigen::VectorXd c = qr.solve(b);
  const double rss = (A * c - b).squaredNorm();
  if (!std::isfinite(rss)) return std::nullopt;
  return std::make_pair(c, rss);
}

std::vector<double> logspace(double lo, double hi, int count) {
  std::vector<double> v;
  for (int i = 0; i < count; ++i) v.push_back(std::pow(10.0, lo + (hi - lo) * i / (count - 1)));
  return v;
}

// Candidate starts: every point of a grid over the nonlinear parameters, the amplitudes solved
// exactly for each; sorted by RSS.
std::vector<std::pair<double, std::vector<double>>> grid_starts(ModelForm f, std::span<const double> x,
                                                                std::span<const double> y) {
  const double X = std::max(max_abs(x), 1e-12);
  const std::size_t n = x.size();
  bool has_zero = std::any_of(x.begin(), x.end(), [](double v) { return v == 0.0; });
  std::vector<std::pair<double, std::vector<double>>> out;
  auto column = [&](auto fn) {
    std::vector<double> g(n);
    for (std::size_t i = 0; i < n; ++i) g[i] = fn(x[i]);
    return g;
  };
  const std::vector<double> ones(n, 1.0);
  auto add = [&](const std::vector<std::vector<double>>& g, auto make) {
    if (auto s = linear_part(g, y)) out.emplace_back(s->second, make(s->first));
  };
  switch (f) {
    case ModelForm::ExpApproach: {
      std::vector<double> scales = logspace(-2, 2.5, 46);
      for (double s : logspace(-2, 0.5, 11)) scales.push_back(-s);
      for (double s : scales) {
        const double c = s / X;
        add({ones, column([&](double t) { return -std::exp(-c * t); })}, [&](const Eigen::VectorXd& ab) {
          return std::vector<double>{ab(0), ab(1), c};
        });
      }
      break;
    }
    case ModelForm::StretchedExp:
      for (double d : {0.5, 0.75, 1.0, 1.25, 1.5, 1.75, 2.0, 2.5, 3.0})
        for (double s : logspace(-2, 2, 25)) {
          const double c = s / std::pow(X, d);
          add({ones, column([&](double t) { return std::exp(-c * pow_nonneg(t, d)); })},
              [&](const Eigen::VectorXd& ab) {
                return std::vector<double>{ab(0), ab(1), c, d};
              });
        }
      break;
    case ModelForm::LogisticLn:
      for (double k : {0.5, 1.0, 1.5, 2.0, 3.0, 4.0, 5.0, 6.0, 8.0, 10.0})
        for (double x0 : logspace(-2, 1, 31)) {
          const double t0 = x0 * X;
          add({ones, column([&](double t) { return t == 0.0 ? -1.0 : -1.0 / (1.0 + std::exp(k * std::log(t / t0))); })},
              [&](const Eigen::VectorXd& ab) {
                return std::vector<double>{ab(0), ab(1), k, t0};
              });
        }
      break;
    case ModelForm::Gompertz:
      for (double s : logspace(-1, 2, 25))
        for (int j = -5; j <= 15; ++j) {
          const double c = s / X, b = c * X * j / 10.0;
          add({column([&](double t) { return std::exp(-std::exp(b - c * t)); })}, [&](const Eigen::VectorXd& a) {
            return std::vector<double>{a(0), b, c};
          });
        }
      break;
    case ModelForm::Saturation: {
      const double xmin = *std::min_element(x.begin(), x.end());
      for (double s : logspace(-3, 2, 41)) {
        const double b = s * X;
        if (b + xmin <= 0.0) continue;
        add({column([&](double t) { return t / (b + t); })}, [&](const Eigen::VectorXd& a) {
          return std::vector<double>{a(0), b};
        });
      }
      break;
    }
    case ModelForm::Power:
      for (int j = -40; j <= 60; ++j) {
        const double b = j / 20.0;
        if (b <= 0.0 && has_zero) continue;
        add({column([&](double t) { return pow_nonneg(t, b); })}, [&](const Eigen::VectorXd& a) {
          return std::vector<double>{a(0), b};
        });
      }
      break;
    case ModelForm::Polynomial: break;
  }
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  return out;
}

struct Solved {
  std::vector<double> p;
  bool converged = false;
  std::string message;
};

// Lower bounds that keep each form inside its domain (-inf: none): ln(x / x0) needs x0 > 0;
// a x / (b + x) and x^b at x = 0 need b > 0; stretched_exp's d > 0 (every fit the thesis prints
// has these signs).
std::vector<double> lower_bounds(ModelForm f, std::span<const double> x) {
  const double X = std::max(max_abs(x), 1e-12);
  const bool has_zero = std::any_of(x.begin(), x.end(), [](double v) { return v == 0.0; });
  std::vector<double> lo(kMaxParams, -std::numeric_limits<double>::infinity());
  if (f == ModelForm::LogisticLn) lo[3] = 1e-9 * X;
  if (f == ModelForm::Saturation) lo[1] = 1e-9 * X;
  if (f == ModelForm::Power && has_zero) lo[1] = 1e-9;
  if (f == ModelForm::StretchedExp) lo[3] = 1e-3;
  return lo;
}

// A parameter the solver left on its lower bound (an active constraint, not an interior optimum).
std::vector<bool> at_lower_bound(const Model& m, std::span<const double> x) {
  std::vector<bool> at(m.p.size(), false);
  if (m.spec.form == ModelForm::Polynomial) return at;
  const std::vector<double> lo = lower_bounds(m.spec.form, x);
  for (std::size_t k = 0; k < m.p.size(); ++k) at[k] = std::isfinite(lo[k]) && m.p[k] <= lo[k] + 1e-6 * std::abs(lo[k]);
  return at;
}

Solved solve_ceres(ModelForm f, std::span<const double> x, std::span<const double> y, std::vector<double> start) {
  const double ys = std::max(max_abs(y), 1e-300);
  ceres::Problem::Options po;
  ceres::Problem problem(po);
  double* p = start.data();
  const int np = static_cast<int>(start.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    auto* cost = new ceres::DynamicAutoDiffCostFunction<Residual, kMaxParams>(new Residual{f, x[i], y[i], ys});
    cost->AddParameterBlock(np);
    cost->SetNumResiduals(1);
    problem.AddResidualBlock(cost, nullptr, p);
  }
  const std::vector<double> lower = lower_bounds(f, x);
  for (int k = 0; k < np; ++k) {
    const double lo = lower[static_cast<std::size_t>(k)];
    if (!std::isfinite(lo)) continue;
    problem.SetParameterLowerBound(p, k, lo);
    if (p[k] <= lo) p[k] = lo + 1e-9 * (1.0 + std::abs(lo));
  }
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::DENSE_QR;
  so.logging_type = ceres::SILENT;
  so.minimizer_progress_to_stdout = false;
  so.max_num_iterations = 500;
  so.function_tolerance = 1e-15;
  so.parameter_tolerance = 1e-14;
  so.gradient_tolerance = 1e-20;
  so.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  Solved s;
  s.p = start;
  const bool finite = std::all_of(s.p.begin(), s.p.end(), [](double v) { return std::isfinite(v); });
  s.converged = finite && summary.termination_type == ceres::CONVERGENCE;
  if (!s.converged)
    s.message = finite ? fmt::format("Levenberg-Marquardt did not converge ({} iterations: {})",
                                     summary.iterations.size(), summary.message)
                       : "Levenberg-Marquardt gave non-finite parameters";
  return s;
}

// Jacobian of the model values with respect to the parameters, exact by Jets (n x p).
Eigen::MatrixXd jacobian(const Model& m, std::span<const double> x) {
  const std::size_t np = m.p.size();
  Eigen::MatrixXd J(static_cast<Eigen::Index>(x.size()), static_cast<Eigen::Index>(np));
  if (m.spec.form == ModelForm::Polynomial) {
    const int first = m.spec.fixed_intercept ? 1 : 0;
    for (std::size_t i = 0; i < x.size(); ++i)
      for (std::size_t k = 0; k < np; ++k)
        J(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(k)) = std::pow(x[i], static_cast<double>(k) + first);
    return J;
  }
  using Jet = ceres::Jet<double, kMaxParams>;
  Jet p[kMaxParams];
  for (std::size_t k = 0; k < np; ++k) p[k] = Jet(m.p[k], static_cast<int>(k));
  for (std::size_t i = 0; i < x.size(); ++i) {
    const Jet v = eval_nonlinear(m.spec.form, p, x[i]);
    for (std::size_t k = 0; k < np; ++k)
      J(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(k)) = v.v[static_cast<Eigen::Index>(k)];
  }
  return J;
}

// Whether a (non-converged) end point lies where the form has degenerated over the data into a
// simpler form reached only in a limit of its parameters: logistic_ln with (x / x0)^k << 1 at
// every point is (a - b) + (b / x0^k) x^k (x0 -> inf, a and b -> inf: an offset power law), with
// (x / x0)^k >> 1 it is a - b x0^k x^-k; stretched_exp with c x^d << 1 is (a + b) - b c x^d
// (c -> 0, b -> inf: again an offset power law); exp_approach with c x << 1 is a line. Returns
// the limit in words, or "".
std::string degenerate_limit(const Model& m, std::span<const double> x) {
  const auto& p = m.p;
  double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
  switch (m.spec.form) {
    case ModelForm::LogisticLn:
      for (double v : x)
        if (v > 0.0) {
          const double u = std::pow(v / p[3], p[2]);
          lo = std::min(lo, u);
          hi = std::max(hi, u);
        }
      if (hi > 0.0 && hi < 1e-2)
        return "x0 -> inf (|a|, |b| -> inf) where logistic_ln becomes (a - b) + (b / x0^k) x^k, an offset power law "
               "c0 + A x^k with 3 parameters";
      if (lo > 1e2 && std::isfinite(lo))
        return "x0 -> 0 where logistic_ln becomes a - b x0^k x^-k, an offset power law with 3 parameters";
      return "";
    case ModelForm::StretchedExp:
      for (double v : x) hi = std::max(hi, std::abs(p[2]) * std::pow(v, p[3]));
      if (hi < 1e-2)
        return "c -> 0 (|b| -> inf) where stretched_exp becomes (a + b) - b c x^d, an offset power law c0 + A x^d "
               "with 3 parameters";
      return "";
    case ModelForm::ExpApproach:
      for (double v : x) hi = std::max(hi, std::abs(p[2] * v));
      if (hi < 1e-2) return "c -> 0 (|b| -> inf) where exp_approach becomes (a - b) + b c x, a straight line";
      return "";
    default: return "";
  }
}

// The size of a unit-consistent change of each parameter: Y for amplitudes (units of y), X for
// x0 and saturation's b (units of x), 1 / X for rates (c; 1 / X^d for stretched_exp), 1 for
// exponents and Gompertz' shift, Y / X^k for a polynomial's c_k and Y / X^b for power's a. X, Y:
// the largest |x|, |y|. Independent of the parameters' values, so that a parameter whose value is
// near 0 is not mistaken for one the data do not determine.
std::vector<double> natural_scales(const Model& m, double X, double Y) {
  const auto& p = m.p;
  switch (m.spec.form) {
    case ModelForm::Polynomial: {
      std::vector<double> s;
      for (std::size_t k = 0; k < p.size(); ++k)
        s.push_back(Y / std::pow(X, static_cast<double>(k) + (m.spec.fixed_intercept ? 1.0 : 0.0)));
      return s;
    }
    case ModelForm::ExpApproach: return {Y, Y, 1.0 / X};
    case ModelForm::StretchedExp: return {Y, Y, 1.0 / std::pow(X, p[3]), 1.0};
    case ModelForm::LogisticLn: return {Y, Y, 1.0, X};
    case ModelForm::Gompertz: return {Y, 1.0, 1.0 / X};
    case ModelForm::Saturation: return {Y, X};
    case ModelForm::Power: return {Y / std::pow(X, p[1]), 1.0};
  }
  return std::vector<double>(p.size(), 1.0);
}

// The solution only (no statistics): used by the full fit and by each leave-one-out refit.
struct Core {
  std::optional<Model> model;
  bool converged = false;
  std::string message;
};

Core fit_core(const ModelSpec& spec, std::span<const double> x, std::span<const double> y,
              const std::vector<double>* hint) {
  Core c;
  if (spec.form == ModelForm::Polynomial) {
    c.model = fit_polynomial(spec, x, y);
    c.converged = c.model.has_value();
    if (!c.converged) c.message = "the x values do not determine the polynomial (rank deficient)";
    return c;
  }
  std::vector<std::vector<double>> starts;
  if (hint) starts.push_back(*hint);
  const auto grid = grid_starts(spec.form, x, y);
  for (std::size_t i = 0; i < grid.size() && starts.size() < (hint ? 2u : 3u); ++i) starts.push_back(grid[i].second);
  if (starts.empty()) {
    c.message = "no start point gives finite values";
    return c;
  }
  double best = std::numeric_limits<double>::infinity();
  double best_failed = std::numeric_limits<double>::infinity();
  std::optional<Model> failed;  // the best non-converged end point, for the diagnosis
  for (const auto& s : starts) {
    Solved r = solve_ceres(spec.form, x, y, s);
    Model m{spec, r.p};
    const double rss = rss_of(m, x, y);
    if (r.converged && rss < best) {
      best = rss;
      c.model = m;
      c.converged = true;
      c.message.clear();
    } else if (!c.converged) {
      if (c.message.empty()) c.message = r.message;
      if (rss < best_failed) {
        best_failed = rss;
        failed = m;
      }
    }
  }
  if (!c.converged && failed) {
    // A form whose least squares have no interior optimum: the solver walks towards a limit
    // where the form degenerates into a simpler one and the amplitudes grow without bound.
    const std::string limit = degenerate_limit(*failed, x);
    if (!limit.empty()) {
      std::string ps;
      const auto names = parameter_names(spec);
      for (std::size_t k = 0; k < names.size(); ++k)
        ps += fmt::format("{}{} = {:.4g}", k ? ", " : "", names[k], failed->p[k]);
      c.message = fmt::format(
          "no interior optimum: the least squares run to the limit {}; Levenberg-Marquardt stopped at {} with "
          "RSS {:.6g}, which the form approaches but never attains",
          limit, ps, best_failed);
    }
  }
  return c;
}

}  // namespace

std::string_view to_string(ModelForm f) {
  for (const auto& fn : kForms)
    if (fn.form == f) return fn.name;
  return "?";
}

std::optional<ModelForm> model_form_from_string(std::string_view s) {
  for (const auto& fn : kForms)
    if (fn.name == s) return fn.form;
  return std::nullopt;
}

std::string ModelSpec::label() const {
  if (form != ModelForm::Polynomial) return std::string(to_string(form));
  if (fixed_intercept) return fmt::format("polynomial({},c0={:g})", degree, *fixed_intercept);
  return fmt::format("polynomial({})", degree);
}

std::vector<std::string> parameter_names(const ModelSpec& s) {
  switch (s.form) {
    case ModelForm::Polynomial: {
      std::vector<std::string> v;
      for (int k = s.fixed_intercept ? 1 : 0; k <= s.degree; ++k) v.push_back(fmt::format("c{}", k));
      return v;
    }
    case ModelForm::ExpApproach: return {"a", "b", "c"};
    case ModelForm::StretchedExp: return {"a", "b", "c", "d"};
    case ModelForm::LogisticLn: return {"a", "b", "k", "x0"};
    case ModelForm::Gompertz: return {"a", "b", "c"};
    case ModelForm::Saturation: return {"a", "b"};
    case ModelForm::Power: return {"a", "b"};
  }
  return {};
}

double domain_lower_bound(ModelForm f) {
  switch (f) {
    case ModelForm::LogisticLn:
    case ModelForm::Power:
    case ModelForm::StretchedExp: return 0.0;
    default: return -std::numeric_limits<double>::infinity();
  }
}

std::string parameter_domain_problem(const Model& m, double x_low) {
  if (m.p.size() != parameter_count(m.spec))
    return fmt::format("expected {} parameters, found {}", parameter_count(m.spec), m.p.size());
  switch (m.spec.form) {
    case ModelForm::LogisticLn:
      if (!(m.p[3] > 0.0))
        return fmt::format("logistic_ln needs x0 > 0 (ln(x / x0) is undefined otherwise), found x0 = {:g}", m.p[3]);
      break;
    case ModelForm::Saturation:
      if (!(m.p[1] > 0.0))
        return fmt::format("saturation a x / (b + x) needs b > 0 (a pole at x = -b otherwise), found b = {:g}", m.p[1]);
      if (x_low <= -m.p[1])
        return fmt::format("saturation a x / (b + x) has a pole at x = {:g}, inside the range x >= {:g}", -m.p[1],
                           x_low);
      break;
    case ModelForm::StretchedExp:
      if (!(m.p[3] > 0.0))
        return fmt::format(
            "stretched_exp needs d > 0 (x^d with d <= 0 is singular or constant at x = 0), found d = {:g}", m.p[3]);
      break;
    case ModelForm::Power:
      if (m.p[1] < 0.0 && x_low <= 0.0)
        return fmt::format(
            "power a x^b with b = {:g} < 0 is undefined at x = 0: give b >= 0 or a 'valid' range above 0", m.p[1]);
      break;
    default: break;
  }
  return "";
}

std::vector<double> Model::polynomial_coefficients() const {
  std::vector<double> c(4, 0.0);
  if (spec.form != ModelForm::Polynomial) return c;
  const std::size_t first = spec.fixed_intercept ? 1 : 0;
  if (spec.fixed_intercept) c[0] = *spec.fixed_intercept;
  for (std::size_t k = 0; k < p.size() && k + first < 4; ++k) c[k + first] = p[k];
  return c;
}

double Model::operator()(double x) const {
  if (p.size() != parameter_count(spec)) return kNaN;
  if (spec.form == ModelForm::Polynomial) {
    const auto c = polynomial_coefficients();
    return c[0] + x * (c[1] + x * (c[2] + x * c[3]));
  }
  if (x < domain_lower_bound(spec.form)) return kNaN;
  return eval_nonlinear(spec.form, p.data(), x);
}

BackwardPrediction backward_prediction(const Model& m, std::span<const double> x, std::span<const double> y) {
  BackwardPrediction b;
  double rel = 0.0;
  std::size_t nrel = 0;
  for (std::size_t i = 0; i < x.size() && i < y.size(); ++i) {
    const double d = std::abs(y[i] - m(x[i]));
    b.abs_diff.push_back(d);
    b.mean += d;
    b.max = std::max(b.max, d);
    if (y[i] != 0.0) {
      rel += d / std::abs(y[i]);
      ++nrel;
    }
  }
  if (!b.abs_diff.empty()) b.mean /= static_cast<double>(b.abs_diff.size());
  b.mean_relative = nrel ? rel / static_cast<double>(nrel) : kNaN;
  return b;
}

FitResult fit_model(const ModelSpec& spec, std::span<const double> x, std::span<const double> y,
                    const FitOptions& options) {
  if (spec.form == ModelForm::Polynomial && (spec.degree < 1 || spec.degree > 3))
    throw InputError({"", 0, "degree"}, fmt::format("expected a polynomial degree 1 to 3, found {}", spec.degree));
  check_data(spec, x, y);
  FitResult r;
  Core core = fit_core(spec, x, y, nullptr);
  r.converged = core.converged;
  r.message = core.message;
  const std::size_t np = parameter_count(spec);
  r.model = core.model.value_or(Model{spec, std::vector<double>(np, kNaN)});
  const std::size_t n = x.size();
  r.dof = static_cast<int>(n) - static_cast<int>(np);
  r.stddev.assign(np, kNaN);
  r.covariance.assign(np * np, kNaN);
  r.at_bound.assign(np, false);
  r.identified.assign(np, false);
  if (!core.model) {
    r.identifiable = false;
    r.rss = r.sigma = r.r_squared = r.aicc = kNaN;
    return r;
  }
  r.rss = rss_of(r.model, x, y);
  r.sigma = r.dof > 0 ? std::sqrt(r.rss / r.dof) : kNaN;
  const double ymean = std::accumulate(y.begin(), y.end(), 0.0) / static_cast<double>(n);
  double tss = 0.0;
  for (double v : y) tss += (v - ymean) * (v - ymean);
  r.r_squared = tss > 0.0 ? 1.0 - r.rss / tss : kNaN;
  const double dn = static_cast<double>(n), dp = static_cast<double>(np);
  r.aicc = (dn - dp - 1.0 > 0.0 && r.rss > 0.0)
               ? dn * std::log(r.rss / dn) + 2.0 * dp + 2.0 * dp * (dp + 1.0) / (dn - dp - 1.0)
               : kNaN;
  r.backward = backward_prediction(r.model, x, y);

  // Covariance sigma^2 (J^T J)^-1 over the parameters inside their bounds (a parameter on a
  // bound is an active constraint: the interior formula does not apply to it), columns scaled to
  // unit norm so that the rank test does not depend on the parameters' units.
  r.at_bound = at_lower_bound(r.model, x);
  r.identified.assign(np, true);
  const Eigen::MatrixXd J = jacobian(r.model, x);
  // A column that is zero, or so small that a change of its parameter by its natural scale (see
  // natural_scales) moves the fitted values by less than 1e-9 of the data's size (e.g. the rate
  // of an amplitude that is 0, or of an exponential that has died out at every point), does not
  // determine its parameter; scaling it to unit norm would hide that (with RSS = 0 it would
  // give an uncertainty of exactly 0).
  const double Y = max_abs(y) > 0.0 ? max_abs(y) : 1.0;
  const std::vector<double> scale = natural_scales(r.model, std::max(max_abs(x), 1e-300), Y);
  const double negligible = 1e-9 * Y * std::sqrt(static_cast<double>(n));
  std::vector<Eigen::Index> free;
  for (std::size_t k = 0; k < np; ++k) {
    if (r.at_bound[k]) continue;  // flagged as such; its own column says nothing at the bound
    const double nk = J.col(static_cast<Eigen::Index>(k)).norm();
    if (!(nk > 0.0) || !std::isfinite(nk) || nk * scale[k] <= negligible)
      r.identified[k] = false;
    else
      free.push_back(static_cast<Eigen::Index>(k));
  }
  const auto nf = static_cast<Eigen::Index>(free.size());
  bool full_rank = true;
  if (nf > 0) {
    Eigen::MatrixXd Jf(J.rows(), nf);
    for (Eigen::Index c = 0; c < nf; ++c) Jf.col(c) = J.col(free[static_cast<std::size_t>(c)]);
    // Columns scaled to unit norm; a singular value below 1e-6 of the largest (an eigenvalue of
    // J^T J below 1e-12 of the largest) is a dependence between the free parameters.
    const double sigma2 = r.dof > 0 ? r.rss / r.dof : kNaN;
    const JacobianAnalysis a = analyse_jacobian(Jf, sigma2, JacobianOptions{1e-6, true});
    full_rank = a.full_rank();
    if (!full_rank)
      for (Eigen::Index c = 0; c < nf; ++c)
        r.identified[static_cast<std::size_t>(free[static_cast<std::size_t>(c)])] = false;
    // The covariance of the free parameters is that of the model with the bound ones fixed; with
    // a parameter not identified it does not exist (J^T J singular).
    const bool all_identified = std::all_of(r.identified.begin(), r.identified.end(), [](bool b) { return b; });
    if (full_rank && all_identified && r.dof > 0) {
      for (Eigen::Index i = 0; i < nf; ++i) {
        const auto pi = static_cast<std::size_t>(free[static_cast<std::size_t>(i)]);
        r.stddev[pi] = std::sqrt(a.covariance(i, i));
        for (Eigen::Index k = 0; k < nf; ++k)
          r.covariance[pi * np + static_cast<std::size_t>(free[static_cast<std::size_t>(k)])] = a.covariance(i, k);
      }
    }
  }
  r.identifiable = full_rank && std::all_of(r.identified.begin(), r.identified.end(), [](bool b) { return b; });

  if (options.loocv && n >= np + 1 && n > options.loocv_refit_max) {
    // PRESS residuals e_i = r_i / (1 - h_ii), h_ii = |row i of Q|^2 for J = QR (Allen 1974; Cook &
    // Weisberg, Residuals and Influence in Regression, 1982, eq. 2.2.23): exact for linear least
    // squares, for a nonlinear form the prediction of a refit that takes one Gauss-Newton step
    // from the full solution. Parameters on a bound stay fixed, as in a refit.
    std::vector<Eigen::Index> cols;
    for (std::size_t k = 0; k < np; ++k)
      if (!r.at_bound[k]) cols.push_back(static_cast<Eigen::Index>(k));
    Eigen::MatrixXd A(J.rows(), static_cast<Eigen::Index>(cols.size()));
    for (std::size_t c = 0; c < cols.size(); ++c) {
      A.col(static_cast<Eigen::Index>(c)) = J.col(cols[c]);
      const double norm = A.col(static_cast<Eigen::Index>(c)).norm();
      if (norm > 0.0) A.col(static_cast<Eigen::Index>(c)) /= norm;  // units out of the rank test
    }
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
    qr.setThreshold(1e-12);
    const Eigen::Index rank = qr.rank();
    // The thin Q only (n x rank): the full one would be n x n.
    const Eigen::MatrixXd Q = qr.householderQ() * Eigen::MatrixXd::Identity(A.rows(), rank);
    std::vector<double> errors(n);
    double sum = 0.0;
    bool ok = rank == static_cast<Eigen::Index>(cols.size()) && r.converged;
    for (std::size_t i = 0; i < n && ok; ++i) {
      const double h = Q.row(static_cast<Eigen::Index>(i)).squaredNorm();
      const double e = (y[i] - r.model(x[i])) / (1.0 - h);
      ok = h < 1.0 - 1e-12 && std::isfinite(e);
      errors[i] = e;
      sum += e * e;
    }
    if (ok) {
      r.loocv_errors = errors;
      r.loocv_rmse = std::sqrt(sum / static_cast<double>(n));
      r.loocv_method = spec.form == ModelForm::Polynomial ? "hat_matrix" : "linearised";
    }
  } else if (options.loocv && n >= np + 1) {
    std::vector<double> xs(n - 1), ys(n - 1), errors;
    double sum = 0.0;
    bool ok = true;
    for (std::size_t i = 0; i < n && ok; ++i) {
      for (std::size_t j = 0, k = 0; j < n; ++j)
        if (j != i) {
          xs[k] = x[j];
          ys[k] = y[j];
          ++k;
        }
      const Core c = fit_core(spec, xs, ys, &r.model.p);
      const double e = c.model ? y[i] - (*c.model)(x[i]) : kNaN;
      ok = c.converged && std::isfinite(e);
      errors.push_back(e);
      sum += e * e;
    }
    if (ok) {
      r.loocv_errors = errors;
      r.loocv_rmse = std::sqrt(sum / static_cast<double>(n));
      r.loocv_method = "refit";
    }
  }
  return r;
}

std::vector<ModelSpec> all_model_specs() {
  std::vector<ModelSpec> v;
  for (int d = 1; d <= 3; ++d) v.push_back({ModelForm::Polynomial, d, std::nullopt});
  for (int d = 1; d <= 3; ++d) v.push_back({ModelForm::Polynomial, d, 0.0});
  for (ModelForm f : {ModelForm::ExpApproach, ModelForm::StretchedExp, ModelForm::LogisticLn, ModelForm::Gompertz,
                      ModelForm::Saturation, ModelForm::Power})
    v.push_back({f, 1, std::nullopt});
  return v;
}

std::vector<ModelSpec> parse_model_specs(const std::string& list, const std::string& source) {
  if (trim(list) == "all") return all_model_specs();
  std::vector<ModelSpec> out;
  // Split on commas outside parentheses: "polynomial(2,c0=0),exp_approach".
  std::vector<std::string> items;
  std::string cur;
  int depth = 0;
  for (char ch : list) {
    if (ch == '(') ++depth;
    if (ch == ')') --depth;
    if (ch == ',' && depth == 0) {
      items.push_back(trim(cur));
      cur.clear();
    } else {
      cur += ch;
    }
  }
  items.push_back(trim(cur));
  const std::string expected =
      "expected 'all' or a comma list of polynomial(DEGREE) (1..3), polynomial(DEGREE,c0=VALUE), exp_approach, "
      "stretched_exp, logistic_ln, gompertz, saturation, power";
  for (const auto& item : items) {
    std::string s;
    for (char ch : item)
      if (ch != ' ') s += ch;
    if (s.empty()) throw InputError({source, 0, "models"}, expected + ", found an empty item in '" + list + "'");
    if (auto f = model_form_from_string(s); f && *f != ModelForm::Polynomial) {
      out.push_back({*f, 1, std::nullopt});
      continue;
    }
    if (s.rfind("polynomial(", 0) == 0 && s.back() == ')') {
      const std::string inner = s.substr(11, s.size() - 12);
      const auto comma = inner.find(',');
      const auto deg = parse_number(inner.substr(0, comma));
      ModelSpec spec{ModelForm::Polynomial, 0, std::nullopt};
      bool ok = deg && (*deg == 1 || *deg == 2 || *deg == 3);
      if (ok) spec.degree = static_cast<int>(*deg);
      if (ok && comma != std::string::npos) {
        const std::string rest = inner.substr(comma + 1);
        const auto v = rest.rfind("c0=", 0) == 0 ? parse_number(rest.substr(3)) : std::nullopt;
        ok = v.has_value();
        if (ok) spec.fixed_intercept = *v;
      }
      if (ok) {
        out.push_back(spec);
        continue;
      }
    }
    throw InputError({source, 0, "models"}, expected + ", found '" + item + "'");
  }
  return out;
}

ModelComparison compare_models(const std::vector<ModelSpec>& specs, std::span<const double> x,
                               std::span<const double> y) {
  ModelComparison c;
  for (const auto& s : specs) {
    try {
      FitResult r = fit_model(s, x, y);
      if (!r.converged) {
        c.skipped.push_back({s, r.message});
        continue;
      }
      c.fits.push_back(std::move(r));
    } catch (const InputError& e) {
      // A form that does not apply to these data (too few points, x < 0) is listed, not fatal.
      c.skipped.push_back({s, e.what()});
    }
  }
  c.by_backward.resize(c.fits.size());
  std::iota(c.by_backward.begin(), c.by_backward.end(), 0);
  c.by_loocv = c.by_backward;
  std::stable_sort(c.by_backward.begin(), c.by_backward.end(),
                   [&](std::size_t a, std::size_t b) { return c.fits[a].backward.mean < c.fits[b].backward.mean; });
  const double inf = std::numeric_limits<double>::infinity();
  std::stable_sort(c.by_loocv.begin(), c.by_loocv.end(), [&](std::size_t a, std::size_t b) {
    return c.fits[a].loocv_rmse.value_or(inf) < c.fits[b].loocv_rmse.value_or(inf);
  });
  return c;
}

}  // namespace mtcal
