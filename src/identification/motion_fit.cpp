// Motion errors fitted to positioning runs (fitting/motion_fit.hpp; criterion in docs/fit-motion.md).
#include "mtcal/identification/motion_fit.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "mtcal/fitting/least_squares.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/util/units.hpp"

namespace mtcal {
namespace {

// One target mean of one direction in internal units, with its standard uncertainty (NaN: unknown).
struct Point {
  double q = 0, y = 0, u = 0;
  int dir = 1;
};

struct Candidate {
  Eigen::VectorXd x;  // coefficients in the scaled basis
  Eigen::VectorXd u;  // their standard uncertainties
  double rms = 0;
  bool ok = false;
};

// Columns: the form's basis at q (polynomial in q / scale, or Fourier in q), then the reversal.
Eigen::RowVectorXd basis_row(bool rotary, int degree, bool reversal, double q, double scale, int dir) {
  const int nb = rotary ? 2 * degree + 1 : degree + 1;
  Eigen::RowVectorXd row(nb + (reversal ? 1 : 0));
  if (rotary) {
    row[0] = 1;
    for (int k = 1; k <= degree; ++k) row[k] = std::cos(k * q), row[degree + k] = std::sin(k * q);
  } else {
    for (int k = 0; k <= degree; ++k) row[k] = std::pow(q / scale, k);
  }
  if (reversal) row[nb] = dir;
  return row;
}

Candidate fit_candidate(const std::vector<Point>& pts, bool rotary, int degree, bool reversal, double scale,
                        double u_floor) {
  Candidate c;
  const Eigen::Index n = static_cast<Eigen::Index>(pts.size());
  const Eigen::Index p = (rotary ? 2 * degree + 1 : degree + 1) + (reversal ? 1 : 0);
  if (n < p + 1) return c;  // no degree of freedom left to judge the form by
  Eigen::MatrixXd A(n, p), J(n, p);
  Eigen::VectorXd y(n), w(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto& pt = pts[static_cast<std::size_t>(i)];
    A.row(i) = basis_row(rotary, degree, reversal, pt.q, scale, pt.dir);
    y[i] = pt.y;
    // Weights 1/u; a mean with no scatter (u = 0) or an unknown u gets the floor.
    w[i] = u_floor > 0 ? 1.0 / std::max(pt.u == pt.u ? pt.u : 0.0, u_floor) : 1.0;
  }
  J = w.asDiagonal() * A;
  const Eigen::VectorXd wy = w.cwiseProduct(y);
  c.x = J.colPivHouseholderQr().solve(wy);
  const Eigen::VectorXd r = y - A * c.x;
  c.rms = std::sqrt(r.squaredNorm() / static_cast<double>(n));
  const double dof = static_cast<double>(n - p);
  const double chi2 = (w.cwiseProduct(r)).squaredNorm() / dof;
  // Weighted by the repeatability: scale the covariance only when the residual exceeds it.
  const double sigma0_sq = u_floor > 0 ? std::max(1.0, chi2) : chi2;
  const auto a = analyse_jacobian(J, sigma0_sq, JacobianOptions{1e-10, true});
  if (!a.full_rank()) return c;
  c.u = a.uncertainty;
  c.ok = c.x.allFinite();
  return c;
}

}  // namespace

MotionFit fit_motion(const PositioningEvaluation& e, double tf, double vf, const MotionFitOptions& o,
                     const std::string& source) {
  if (e.targets.size() < 2)
    throw InputError({source, 0, ""}, fmt::format("expected at least 2 targets, found {}", e.targets.size()));
  if (o.form != "auto" && o.form != "table" && o.form != "polynomial" && o.form != "fourier")
    throw InputError({source, 0, "form"}, "expected auto, table, polynomial or fourier, found '" + o.form + "'");
  if (o.form == "fourier" && !o.rotary)
    throw InputError({source, 0, "form"}, "a Fourier series is for a rotary axis; this axis is linear");
  if (o.form == "polynomial" && o.rotary)
    throw InputError({source, 0, "form"}, "a rotary axis takes a Fourier series or a table, not a polynomial");
  if (o.max_degree < 1 || o.max_degree > 3)
    throw InputError({source, 0, "degree"}, fmt::format("expected a degree of 1 to 3, found {}", o.max_degree));
  const bool up = e.directions != TestDirections::DownOnly, down = e.directions != TestDirections::UpOnly;
  const bool both = up && down;
  MotionFit out;
  out.targets = e.targets.size();
  out.bidirectional = both;

  std::vector<TargetEvaluation> t = e.targets;
  std::sort(t.begin(), t.end(), [](const auto& a, const auto& b) { return a.target < b.target; });
  for (std::size_t i = 1; i < t.size(); ++i)
    if (!(t[i].target > t[i - 1].target))
      throw InputError({source, 0, "target"}, fmt::format("target {:g} is given twice", t[i].target));
  std::vector<Point> pts;
  for (const auto& ti : t) {
    const double q = ti.target * tf;
    if (up) pts.push_back({q, ti.mean_up * vf, ti.s_up * vf / std::sqrt(static_cast<double>(ti.n_up)), 1});
    if (down) pts.push_back({q, ti.mean_down * vf, ti.s_down * vf / std::sqrt(static_cast<double>(ti.n_down)), -1});
  }
  // The reference the instrument cannot give: a straightness reflector's line, an angle
  // interferometer's zero (docs/fit-motion.md). Removed from the means of both directions alike.
  if (o.quantity != MeasuredQuantity::Positioning) {
    Eigen::MatrixXd A(static_cast<Eigen::Index>(pts.size()), o.quantity == MeasuredQuantity::Straightness ? 2 : 1);
    Eigen::VectorXd y(A.rows());
    for (Eigen::Index i = 0; i < A.rows(); ++i) {
      A(i, 0) = 1;
      if (A.cols() == 2) A(i, 1) = pts[static_cast<std::size_t>(i)].q;
      y[i] = pts[static_cast<std::size_t>(i)].y;
    }
    const Eigen::VectorXd line = A.colPivHouseholderQr().solve(y);
    for (std::size_t i = 0; i < pts.size(); ++i) pts[i].y -= line[0] + (A.cols() == 2 ? line[1] * pts[i].q : 0.0);
    out.notes.push_back(o.quantity == MeasuredQuantity::Straightness
                            ? fmt::format("the least-squares line (offset {:.4g} um, slope {:.4g} um/m) is removed: "
                                          "a straightness test does not give the axis's alignment",
                                          line[0] * 1e3, line[1] * 1e6)
                            : fmt::format("the mean ({:.4g} urad) is removed: an angular test reads angles relative "
                                          "to its start",
                                          line[0] * 1e6));
  }
  double u2 = 0;
  bool u_known = true;
  for (const auto& p : pts) {
    if (!(p.u == p.u)) u_known = false;
    u2 += u_known ? p.u * p.u : 0.0;
  }
  out.u_mean = u_known ? std::sqrt(u2 / static_cast<double>(pts.size())) : 0.0;

  double scale = 0;
  for (const auto& p : pts) scale = std::max(scale, std::abs(p.q));
  if (!(scale > 0)) scale = 1;

  auto make_table = [&] {
    Table table;
    for (const auto& ti : t) table.positions.push_back(ti.target * tf);
    std::vector<double> uf, ub;
    for (const auto& p : pts) {
      const bool fwd = both ? p.dir > 0 : true;
      (fwd ? table.forward : table.backward).push_back(p.y);
      (fwd ? uf : ub).push_back(p.u == p.u ? p.u : std::nan(""));
    }
    out.function = MotionFunction(table);
    out.uncertainty = uf;
    out.uncertainty.insert(out.uncertainty.end(), ub.begin(), ub.end());
    out.form = "table";
    out.degree = 0;
    out.residual_rms = 0;
  };
  auto make_smooth = [&](int degree, const Candidate& c) {
    const std::size_t nb = o.rotary ? static_cast<std::size_t>(2 * degree + 1) : static_cast<std::size_t>(degree + 1);
    const double rev = both ? c.x[static_cast<Eigen::Index>(nb)] : 0.0;
    const double rev_u = both ? c.u[static_cast<Eigen::Index>(nb)] : 0.0;
    if (o.rotary) {
      Fourier f;
      f.constant = c.x[0];
      out.uncertainty = {c.u[0]};
      for (int k = 1; k <= degree; ++k) f.cos_terms.push_back(c.x[k]), out.uncertainty.push_back(c.u[k]);
      for (int k = 1; k <= degree; ++k)
        f.sin_terms.push_back(c.x[degree + k]), out.uncertainty.push_back(c.u[degree + k]);
      f.reversal = rev;
      out.uncertainty.push_back(rev_u);
      out.function = MotionFunction(f);
      out.form = "fourier";
    } else {
      Polynomial p;
      out.uncertainty.assign(5, 0.0);
      for (int k = 0; k <= degree; ++k) {
        p.coefficients[static_cast<std::size_t>(k)] = c.x[k] / std::pow(scale, k);
        out.uncertainty[static_cast<std::size_t>(k)] = c.u[k] / std::pow(scale, k);
      }
      p.reversal = rev;
      out.uncertainty[4] = rev_u;
      out.function = MotionFunction(p);
      out.form = "polynomial";
    }
    out.degree = degree;
    out.residual_rms = c.rms;
  };

  const char* smooth = o.rotary ? "Fourier series" : "polynomial";
  // Figures of the reason in the unit users read: um or urad.
  auto shown = [&](double v) {
    return fmt::format("{:.3g} {}", v * (o.angular ? 1e6 : 1e3), o.angular ? "urad" : "um");
  };
  if (o.form == "table") {
    make_table();
    out.reason = "table (asked for)";
    return out;
  }
  const double threshold = o.coverage * out.u_mean;
  std::string tried;
  for (int d = 1; d <= o.max_degree; ++d) {
    const Candidate c = fit_candidate(pts, o.rotary, d, both, scale, out.u_mean > 0 ? 0.1 * out.u_mean : 0.0);
    if (!c.ok) continue;
    tried += fmt::format("{}degree {}: rms {}", tried.empty() ? "" : ", ", d, shown(c.rms));
    const bool last = d == o.max_degree;
    if (o.form != "auto") {
      if (last) {
        make_smooth(d, c);
        out.reason = fmt::format("{} of degree {} (asked for); residual rms {}", smooth, d, shown(c.rms));
        return out;
      }
      continue;
    }
    if (out.u_mean > 0 && c.rms <= threshold) {
      make_smooth(d, c);
      out.reason = fmt::format(
          "{} of degree {}: its residual rms {} is within {:g} x the standard uncertainty "
          "of the means ({})",
          smooth, d, shown(c.rms), o.coverage, shown(out.u_mean));
      return out;
    }
  }
  if (o.form != "auto")
    throw InputError({source, 0, "form"}, fmt::format("too few targets for a {} of degree {} with {}", smooth,
                                                      o.max_degree, both ? "a reversal term" : "no reversal term"));
  make_table();
  out.reason = out.u_mean > 0
                   ? fmt::format(
                         "table: no {} up to degree {} comes within {:g} x the standard uncertainty of the "
                         "means ({}){}",
                         smooth, o.max_degree, o.coverage, shown(out.u_mean), tried.empty() ? "" : " (" + tried + ")")
                   : "table: with one run there is no repeatability to judge a smoother form by";
  return out;
}

EstimatedError estimate_motion_error(const PositioningRuns& runs, const std::string& name, MotionFitOptions o,
                                     MotionFit* fit_out) {
  const auto n = ErrorName::parse(name);
  if (!n || n->kind != ErrorKind::Motion || n->body == 't' || n->body == 'w')
    throw InputError({runs.source, 0, ""}, "'" + printable(name) +
                                               "' is not a motion error (expected E + direction + axis, e.g. EXX, EYX, "
                                               "EBX, ECC)");
  const char axis = n->body;
  const bool rotary = axis == 'A' || axis == 'B' || axis == 'C';
  const char dir = "XYZABC"[static_cast<int>(n->component)];
  const bool angular_value = dir == 'A' || dir == 'B' || dir == 'C';
  const std::string tu_name = runs.target_unit.empty() ? runs.unit : runs.target_unit;
  const auto tu = find_unit(tu_name), vu = find_unit(runs.unit);
  if (!tu || tu->ratio || (tu->dimension == Dimension::Angle) != rotary)
    throw InputError({runs.source, 0, "target unit"},
                     fmt::format("the targets of {} are positions of axis {}, expected {} unit, found '{}'", name, axis,
                                 rotary ? "an angle" : "a length", printable(tu_name)));
  if (!vu || (vu->dimension == Dimension::Angle) != angular_value)
    throw InputError({runs.source, 0, "unit"},
                     fmt::format("{} is {}, expected its deviations in {} unit, found '{}'", name,
                                 angular_value ? "an angle" : "a length", angular_value ? "an angle" : "a length",
                                 printable(runs.unit)));
  o.rotary = rotary;
  o.angular = angular_value;
  o.quantity = dir == axis || rotary ? MeasuredQuantity::Positioning
               : angular_value       ? MeasuredQuantity::Angular
                                     : MeasuredQuantity::Straightness;
  const PositioningEvaluation e = evaluate_positioning(runs);
  MotionFit f = fit_motion(e, tu->to_internal, vu->to_internal, o, runs.source);
  EstimatedError out;
  out.name = *n;
  out.motion = f.function;
  out.uncertainty = f.uncertainty;
  out.rotary_argument = rotary;
  out.source = runs.source;
  out.method = f.reason;
  for (const auto& note : f.notes) out.method += "; " + note;
  for (const auto& note : e.notes) out.method += "; " + note;
  if (fit_out) *fit_out = std::move(f);
  return out;
}

}  // namespace mtcal
