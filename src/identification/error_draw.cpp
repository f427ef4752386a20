#include "mtcal/identification/error_draw.hpp"

#include <algorithm>
#include <array>
#include <tuple>
#include <cmath>
#include <numbers>
#include <random>
#include <set>

#include <fmt/format.h>

#include "mtcal/util/errors.hpp"

namespace mtcal {
namespace {

// Uniform in [0, 1) from the generator's top 53 bits: std::uniform_real_distribution's algorithm
// is left to the library, this is the same number everywhere.
double uniform01(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }
double uniform(std::mt19937_64& rng, double lo, double hi) { return lo + (hi - lo) * uniform01(rng); }
double sign(std::mt19937_64& rng) { return (rng() >> 63) ? -1.0 : 1.0; }

// The values of the axis at which a motion error's largest |value| is taken.
std::vector<double> travel_samples(const Axis& ax) {
  std::vector<double> q;
  constexpr int n = 200;
  for (int i = 0; i <= n; ++i) q.push_back(ax.travel->min + (ax.travel->max - ax.travel->min) * i / n);
  return q;
}

double largest(const MotionFunction& f, const std::vector<double>& q) {
  double m = 0.0;
  for (double v : q)
    for (int dir : {-1, 0, 1}) m = std::max(m, std::abs(f.value(v, dir)));
  return m;
}

// A smooth curve of unit size over the travel: three harmonics with decaying random amplitudes;
// periodic in the angle on a rotary axis (a rotary table's errors repeat every turn).
std::vector<double> smooth_curve(const Axis& ax, const std::vector<double>& positions, std::mt19937_64& rng) {
  std::array<double, 3> a{}, b{};
  for (std::size_t k = 0; k < 3; ++k) {
    a[k] = uniform(rng, -1, 1) / static_cast<double>(k + 1);
    b[k] = uniform(rng, -1, 1) / static_cast<double>(k + 1);
  }
  const double lo = ax.travel->min, span = ax.travel->max - ax.travel->min;
  auto f = [&](double q) {
    const double x = ax.kind == AxisKind::Rotary ? q : std::numbers::pi * (q - lo) / span;
    double s = 0.0;
    for (std::size_t k = 0; k < 3; ++k) {
      const double w = static_cast<double>(k + 1);
      s += a[k] * std::cos(w * x) + b[k] * std::sin(w * x);
    }
    return s;
  };
  std::vector<double> v;
  for (double q : positions) v.push_back(f(q));
  return v;
}

}  // namespace

ErrorDraw draw_errors(const Machine& machine, const ErrorDrawOptions& o) {
  const SourceLocation size_at{o.size_source, 0, ""};
  for (const auto& [lo, hi, what] : {std::tuple{o.length_lo, o.length_hi, "length"}, {o.angle_lo, o.angle_hi, "angle"}})
    if (!std::isfinite(lo) || !std::isfinite(hi) || lo < 0 || hi < lo)
      throw InputError(size_at, fmt::format("expected {} sizes 0 <= lo <= hi, found lo {:g}, hi {:g}", what, lo, hi));
  if (o.table_points < 2)
    throw InputError({o.tables_source, 0, ""}, fmt::format("expected at least 2 table points, found {}", o.table_points));

  ErrorDraw d;
  d.seed = o.seed;
  d.nominal = machine;
  d.nominal.clear_errors();

  // Tables first: they change the nominal machine's forms (and so its parameter names).
  std::set<std::string> table_errors;
  for (const auto& name : o.tables) {
    const auto en = ErrorName::parse(name);
    if (!en || en->kind != ErrorKind::Motion || !machine.axis_index(en->body))
      throw InputError({o.tables_source, 0, name},
                       "expected a motion error of the machine's axes (e.g. ECC, EXX) to draw as a table, found '" +
                           printable(name) + "'" + name_hint(machine, name) + " for topology " +
                           machine.topology.chain);
    Axis& ax = d.nominal.axes[*d.nominal.axis_index(en->body)];
    if (!ax.travel)
      throw InputError({o.tables_source, 0, name},
                       fmt::format("expected a travel of axis {} (the table's positions span it), found none", ax.letter));
    auto& f = ax.motion[static_cast<std::size_t>(index_of(en->component))];
    if (const auto* t = std::get_if<Table>(&f.form()); !t) {
      Table t2;
      for (std::size_t i = 0; i < o.table_points; ++i)
        t2.positions.push_back(ax.travel->min + (ax.travel->max - ax.travel->min) * static_cast<double>(i) /
                                                    static_cast<double>(o.table_points - 1));
      t2.forward.assign(o.table_points, 0.0);
      f = MotionFunction(t2);
    } else {
      Table t2{t->positions, std::vector<double>(t->positions.size(), 0.0), {}};
      f = MotionFunction(t2);
    }
    ax.motion_given[static_cast<std::size_t>(index_of(en->component))] = true;
    table_errors.insert(en->str());
  }

  // The selection: parameters by name, or whole errors.
  std::set<std::string> errors, params;
  for (const auto& n : o.only) {
    if (n.find('.') != std::string::npos) {
      if (!d.nominal.parameter_index(n))
        throw InputError({o.only_source, 0, n}, "unknown parameter '" + printable(n) + "'" + name_hint(d.nominal, n) +
                                                   " (" + parameter_naming(d.nominal) + ")");
      params.insert(n);
    } else {
      const auto en = ErrorName::parse(n);
      if (!en || !d.nominal.has_error(*en))
        throw InputError({o.only_source, 0, n}, "unknown error name '" + printable(n) + "'" + name_hint(d.nominal, n) +
                                                   " for topology " + d.nominal.topology.chain);
      errors.insert(en->str());
    }
  }
  const bool all_locations = o.only.empty();

  d.truth = d.nominal;
  std::mt19937_64 rng(o.seed);
  const auto all = d.truth.parameters();
  for (std::size_t i = 0; i < all.size();) {
    const ErrorName en = all[i].error;
    std::size_t end = i;
    while (end < all.size() && all[end].error == en) ++end;
    const std::string ename = en.str();
    std::vector<std::size_t> chosen;  // parameter indices of this error to draw
    const bool whole = errors.count(ename) || table_errors.count(ename) ||
                       (all_locations && en.kind == ErrorKind::Location);
    for (std::size_t k = i; k < end; ++k) {
      const std::string suffix = all[k].name.substr(std::min(all[k].name.size(), ename.size() + 1));
      // A whole polynomial or Fourier error: its shape, not its constant or reversal.
      const bool shape = en.kind != ErrorKind::Motion || table_errors.count(ename) ||
                         (suffix != "0" && suffix != "c0" && suffix != "b");
      if (params.count(all[k].name) || (whole && shape)) chosen.push_back(k);
    }
    if (chosen.empty()) {
      i = end;
      continue;
    }
    const bool rot = is_rotation(en.component);
    const double size = uniform(rng, rot ? o.angle_lo : o.length_lo, rot ? o.angle_hi : o.length_hi) * sign(rng);
    DrawnError de{en, std::abs(size), rot, false, {}};
    for (std::size_t k : chosen) de.parameters.push_back(all[k].name);
    if (en.kind != ErrorKind::Motion) {
      d.truth.set_parameter(chosen.front(), size);
    } else {
      Axis& ax = d.truth.axes[*d.truth.axis_index(en.body)];
      if (!ax.travel)
        throw InputError({o.only_source, 0, ename},
                         fmt::format("expected a travel of axis {} (a motion error's size is taken over it), found none",
                                     ax.letter));
      auto& f = ax.motion[static_cast<std::size_t>(index_of(en.component))];
      auto* t = std::get_if<Table>(&f.form());
      if (t && table_errors.count(ename)) {
        de.table = true;
        std::vector<double> v = smooth_curve(ax, t->positions, rng);
        // Zero at the axis' zero (or at the travel's start when zero is outside it): the
        // interpolation is affine in the values, so subtracting its value there makes it zero.
        const double at = (ax.travel->min <= 0 && ax.travel->max >= 0) ? 0.0 : ax.travel->min;
        t->forward = v;
        const double v0 = f.value(at, 0);
        double big = 0.0;
        for (auto& x : v) big = std::max(big, std::abs(x -= v0));
        for (auto& x : v) x *= big > 0 ? size / big : 0.0;
        t->forward = v;
      } else {
        // Random shape of the chosen parameters, scaled to the size over the travel.
        const auto q = travel_samples(ax);
        // Each coefficient of power p scaled by 1/reach^p, so that no power dominates by its unit.
        const double reach = std::max({std::abs(ax.travel->min), std::abs(ax.travel->max), 1e-300});
        for (std::size_t k : chosen)
          d.truth.set_parameter(k, uniform(rng, -1, 1) / std::pow(reach, f.argument_power(k - i)));
        const double big = largest(f, q);
        for (std::size_t k : chosen) d.truth.set_parameter(k, big > 0 ? d.truth.parameter(k) * std::abs(size) / big : 0.0);
      }
    }
    d.drawn.push_back(std::move(de));
    i = end;
  }
  return d;
}

}  // namespace mtcal
