#include "mtcal/evaluation/contributions.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "mtcal/util/errors.hpp"

namespace mtcal {

double error_value(const Machine& m, const ErrorName& error, std::span<const double> q,
                   std::span<const std::int8_t> dir) {
  const int c = index_of(error.component);
  switch (error.kind) {
    case ErrorKind::Mounting:
      return error.body == 't' ? m.tool_mounting[static_cast<std::size_t>(c)]
                               : m.workpiece_mounting[static_cast<std::size_t>(c)];
    case ErrorKind::Location: return m.axis(error.body).location[static_cast<std::size_t>(c)];
    case ErrorKind::Motion: {
      const std::size_t k = *m.axis_index(error.body);
      if (k >= q.size())
        throw ModelError(fmt::format("error_value: {} joint values for {} axes", q.size(), m.axes.size()));
      return m.axes[k].motion[static_cast<std::size_t>(c)].value(q[k], dir.empty() ? 0 : dir[k]);
    }
  }
  return 0.0;
}

std::vector<ErrorName> nonzero_errors(const Machine& m) {
  std::vector<ErrorName> out;
  for (const auto& p : m.parameters())
    if (p.value != 0.0 && std::find(out.begin(), out.end(), p.error) == out.end()) out.push_back(p.error);
  return out;
}

std::vector<ErrorEffect> single_error_effects(const Machine& m, std::span<const double> q,
                                              std::span<const ErrorName> only) {
  std::vector<ErrorEffect> out;
  for (const auto& e : ErrorModel(m).error_sensitivities(q)) {
    if (!only.empty() && std::find(only.begin(), only.end(), e.error) == only.end()) continue;
    ErrorEffect r;
    r.error = e.error;
    r.rotational = is_rotation(e.error.component);
    // d(out)/d(error) in internal units; 1 um = 1e-3 mm, 1 urad = 1e-6 rad.
    const double per = r.rotational ? 1e-6 : 1e-3;
    for (int c = 0; c < 6; ++c) r.effect[static_cast<std::size_t>(c)] = e.effect[c] * per / (c < 3 ? 1e-3 : 1e-6);
    out.push_back(r);
  }
  return out;
}

std::vector<ErrorParameter> listed_parameters(const Machine& m, bool nonzero_only) {
  std::vector<ErrorParameter> out;
  for (auto& p : m.parameters())
    if (!nonzero_only || p.value != 0.0) out.push_back(std::move(p));
  return out;
}

Machine without_error(const Machine& m, const ErrorName& error) {
  Machine out = m;
  const auto params = m.parameters();
  for (std::size_t i = 0; i < params.size(); ++i)
    if (params[i].error == error) out.set_parameter(i, 0.0);
  return out;
}

ContributionAnalysis contributions(const Machine& m, std::span<const double> a, std::span<const std::int8_t> dir_a,
                                   std::optional<std::span<const double>> b, std::span<const std::int8_t> dir_b) {
  ContributionAnalysis r;
  const ErrorModel actual(m);
  Machine nominal_machine = m;
  nominal_machine.clear_errors();
  const ErrorModel nominal(nominal_machine);
  // First order about the error-free machine: e(E) = sum_k S_k(q) v_k(q) + O(|E|^2), with S_k the
  // sensitivity to error k and v_k its value (every error's definition is this linearisation).
  const auto sa = nominal.error_sensitivities(a, dir_a);
  r.exact = actual.evaluate(a, dir_a).translation;
  std::vector<Vec3> effect(sa.size());
  for (std::size_t k = 0; k < sa.size(); ++k)
    effect[k] = sa[k].effect.head<3>() * error_value(m, sa[k].error, a, dir_a);
  if (b) {
    const auto sb = nominal.error_sensitivities(*b, dir_b);
    r.exact -= actual.evaluate(*b, dir_b).translation;
    for (std::size_t k = 0; k < sb.size(); ++k)
      effect[k] -= sb[k].effect.head<3>() * error_value(m, sb[k].error, *b, dir_b);
  }
  const double norm = r.exact.norm();
  const Vec3 u = norm > 0 ? Vec3(r.exact / norm) : Vec3::Zero();
  for (std::size_t k = 0; k < sa.size(); ++k) {
    r.first_order += effect[k];
    if (effect[k].isZero(0.0)) continue;
    Contribution c;
    c.error = sa[k].error;
    c.effect = effect[k];
    c.along = u.dot(effect[k]);
    c.share = norm > 0 ? c.along / norm : 0.0;
    r.items.push_back(c);
  }
  r.residual = (r.exact - r.first_order).norm();
  std::stable_sort(r.items.begin(), r.items.end(),
                   [](const Contribution& x, const Contribution& y) { return std::abs(x.along) > std::abs(y.along); });
  return r;
}

}  // namespace mtcal
