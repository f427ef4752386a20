#include "mtcal/compensation/fanuc.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <span>

#include <fmt/format.h>

#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/model/joints.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/util/request_error.hpp"

namespace mtcal {

namespace {

constexpr const char* kFanucTarget = "fanuc";

// A rotary axis that turns through a whole revolution gets a table over one turn (parameter 3625);
// a tilting axis with a limited travel is tabulated as a linear one, in deg.
bool full_turn(const Axis& ax) {
  return ax.kind == AxisKind::Rotary && (!ax.travel || ax.travel->max - ax.travel->min >= 2 * std::numbers::pi - 1e-9);
}

// The error the axis's table holds at user position p (mm or deg), mean of both directions, in
// the axis's user unit: the tool point's error along a linear axis when it alone moves, or the
// positioning error of a rotary axis about its own direction (deg).
double axis_error(const ErrorModel& model, std::size_t a, std::span<const double> reference, double p) {
  const Axis& ax = model.machine().axes[a];
  std::vector<double> q(reference.begin(), reference.end());
  q[a] = p * joint_unit_factor(ax);
  if (ax.kind == AxisKind::Linear) {
    std::vector<std::int8_t> d(q.size(), 0);
    double sum = 0.0;
    for (const std::int8_t dir : {std::int8_t{1}, std::int8_t{-1}}) {
      d[a] = dir;
      sum += model.evaluate(q, d).translation.dot(ax.direction());
    }
    return 0.5 * sum;
  }
  const MotionFunction& f = ax.motion[static_cast<std::size_t>(3 + ax.direction_axis)];
  return 0.5 * (f.value(q[a], 1) + f.value(q[a], -1)) * ax.direction_sign * 180.0 / std::numbers::pi;
}

}  // namespace

FanucCompensation compensate_fanuc(const Machine& m, const CompensationOptions& o) {
  const double u = o.detection_unit;
  if (!std::isfinite(u) || u <= 0.0 || u > 1.0)
    throw InputError({kFanucTarget, 0, "detection unit"},
                     fmt::format("expected a detection unit in (0, 1] mm/deg, found {}", u));
  const auto sampling = resolve_sampling(m, o, 51, kFanucMaxPoints, kFanucTarget);
  const ErrorModel model(m);
  const ErrorModel linear_model(linear_axis_errors(m));  // what the linear axes' tables are sampled on
  std::vector<double> reference = o.reference;
  if (reference.empty()) reference.assign(m.axes.size(), 0.0);
  std::string order;
  for (const char c : std::string("XYZABC"))
    if (m.axis_index(c)) order += c;
  FanucCompensation out;
  double reversal = 0.0, rounding = 0.0;
  for (std::size_t a = 0; a < m.axes.size(); ++a) {
    const Axis& ax = m.axes[a];
    FanucPitchAxis t;
    t.axis = ax.letter;
    t.axis_number = static_cast<int>(order.find(ax.letter)) + 1;
    t.rotary = ax.kind == AxisKind::Rotary;
    t.detection_unit = u;
    const int first = (t.axis_number - 1) * static_cast<int>(kFanucMaxPoints);
    const AxisSampling& s = sampling[a];
    const std::size_t wanted = s.points - 1;
    long jmin = 0, jmax = 0;
    const ErrorModel& source = ax.kind == AxisKind::Linear ? linear_model : model;
    // One turn only where the model's error closes over it (to half a count): a polynomial
    // positioning error does not, and tabulating it modulo 360 deg would put its jump into the table.
    const bool turn = full_turn(ax) && std::abs(axis_error(model, a, reference, 360.0) -
                                                axis_error(model, a, reference, 0.0)) <= 0.5 * u;
    if (full_turn(ax) && !turn)
      out.summary.warnings.push_back(
          fmt::format("{}: its positioning error in the model does not close over one turn ({:.3g} deg between 0 and "
                      "360 deg); tabulated over its travel as a linear axis (3625 = 0)",
                      ax.letter,
                      std::abs(axis_error(model, a, reference, 360.0) - axis_error(model, a, reference, 0.0))));
    if (turn) {
      // Whole detection units per interval that divide the turn (3625 = 360 deg).
      const long counts_per_turn = std::lround(360.0 / u);
      std::size_t n = std::min<std::size_t>(wanted, kFanucMaxPoints - 1);
      while (n > 1 && counts_per_turn % static_cast<long>(n) != 0) --n;
      t.interval = static_cast<double>(counts_per_turn / static_cast<long>(n)) * u;
      t.travel_per_rev = 360.0;
      jmax = static_cast<long>(n);
    } else {
      long units =
          std::max(1L, static_cast<long>(std::ceil((s.end - s.start) / static_cast<double>(wanted) / u - 1e-9)));
      for (;; ++units) {
        t.interval = static_cast<double>(units) * u;
        jmin = std::min(-1L, static_cast<long>(std::floor(s.start / t.interval + 1e-9)));
        jmax = std::max(1L, static_cast<long>(std::ceil(s.end / t.interval - 1e-9)));
        if (static_cast<std::size_t>(jmax - jmin + 1) <= kFanucMaxPoints) break;
      }
    }
    // Corrections at the section ends, relative to the reference position (the control's
    // coordinates are set there): C_j = -(e(p_j) - e(0)), e at the position clamped to the sampling.
    const double e0 = axis_error(source, a, reference, std::clamp(0.0, s.start, s.end));
    std::vector<double> c;
    for (long j = jmin; j <= jmax; ++j) {
      const double p = static_cast<double>(j) * t.interval;
      t.node.push_back(p);
      const double pe = turn ? p : std::clamp(p, s.start, s.end);
      c.push_back(-(axis_error(source, a, reference, pe) - e0));
      if (ax.kind == AxisKind::Linear) {
        std::vector<double> q(reference.begin(), reference.end());
        q[a] = pe;
        std::vector<std::int8_t> d(q.size(), 1);
        const double f = linear_model.evaluate(q, d).translation.dot(ax.direction());
        std::fill(d.begin(), d.end(), std::int8_t{-1});
        const double r = linear_model.evaluate(q, d).translation.dot(ax.direction());
        reversal = std::max(reversal, 0.5 * std::abs(f - r));
      }
    }
    // Counts: the absolute correction rounded to whole counts, then differenced, so that rounding
    // does not accumulate along the axis; a full turn closes (its values sum to zero).
    std::vector<long> counts;
    bool fits = false;
    for (t.magnification = 1; t.magnification <= kFanucMaxMagnification && !fits; ++t.magnification) {
      const double step = u * t.magnification;
      counts.clear();
      for (const double v : c) counts.push_back(std::lround(v / step));
      if (turn) counts.back() = counts.front();
      fits = true;
      for (std::size_t i = 1; i < counts.size(); ++i)
        fits = fits && std::abs(counts[i] - counts[i - 1]) <= kFanucMaxValue;
      if (fits) break;
    }
    if (!fits)
      throw RequestError({kFanucTarget, 0, std::string(1, ax.letter)},
                         fmt::format("expected the correction of {} to change by at most {} counts x magnification {} "
                                     "per interval of {:g} {}; use a shorter interval: more table points",
                                     ax.letter, kFanucMaxValue, kFanucMaxMagnification, t.interval, joint_unit_name(ax)),
                         {"points"});
    const double step = u * t.magnification;
    if (ax.kind == AxisKind::Rotary) {
      // A rotary axis's reversal is in deg: named in a warning (the list of errors not held is in mm).
      const MotionFunction& f = ax.motion[static_cast<std::size_t>(3 + ax.direction_axis)];
      double rev = 0.0;
      for (const double p : t.node) {
        const double q = (turn ? p : std::clamp(p, s.start, s.end)) * joint_unit_factor(ax);
        rev = std::max(rev, 0.5 * std::abs(f.value(q, 1) - f.value(q, -1)) * 180.0 / std::numbers::pi);
      }
      if (rev > 0.0)
        out.summary.warnings.push_back(fmt::format(
            "{}: reversal of its positioning error up to {:.3g} deg is not held (bidirectional compensation is not "
            "written)",
            ax.letter, rev));
    }
    bool any = false;
    for (std::size_t i = 0; i < counts.size(); ++i) {
      t.absolute.push_back(static_cast<double>(counts[i]) * step);
      if (ax.kind == AxisKind::Linear) rounding = std::max(rounding, std::abs(t.absolute[i] - c[i]));
      any = any || counts[i] != 0;
    }
    if (!any) continue;
    if (turn) {
      t.reference_number = first;
      t.min_number = first;  // "always equal to the compensation position No. of the reference position"
      t.max_number = first + static_cast<int>(jmax);
      t.values.assign(static_cast<std::size_t>(jmax) + 1, 0);
      for (std::size_t i = 1; i < counts.size(); ++i) t.values[i] = static_cast<int>(counts[i] - counts[i - 1]);
      t.values[0] = t.values.back();  // "set the same compensation value as for" the last point (p. 100)
    } else {
      t.min_number = first;
      t.reference_number = first - static_cast<int>(jmin) - 1;
      t.max_number = t.reference_number + static_cast<int>(jmax);
      for (std::size_t i = 1; i < counts.size(); ++i) t.values.push_back(static_cast<int>(counts[i] - counts[i - 1]));
    }
    if (ax.kind == AxisKind::Rotary) {
      double rounding_deg = 0.0;
      for (std::size_t i = 0; i < counts.size(); ++i)
        rounding_deg = std::max(rounding_deg, std::abs(t.absolute[i] - c[i]));
      out.summary.warnings.push_back(fmt::format(
          "{}: not held, in deg: its error at the reference position, {:.3g} deg (the reference position shift holds "
          "it), and the rounding to counts, up to {:.3g} deg",
          ax.letter, std::abs(e0), rounding_deg));
    }
    if (std::abs(e0) > 0.0 && ax.kind == AxisKind::Linear)
      out.summary.not_compensated.push_back(
          {fmt::format("{}: error at the reference position (the control's coordinates start there; the reference "
                       "position shift holds it, not the pitch error compensation)",
                       ax.letter),
           std::abs(e0), "mm"});
    out.axes.push_back(std::move(t));
  }
  if (out.axes.empty())
    throw InputError({m.source, 0, ""},
                     "nothing to compensate for FANUC pitch error compensation: no axis has a positioning error "
                     "of a detection unit or more");
  // The control adds the correction at the axis's position in its own unit (mm, deg); a rotary
  // axis's table covers one turn (parameter 3624), its position taken modulo 360 deg.
  std::vector<ControllerTable> applied;
  for (const auto& t : out.axes) {
    const std::size_t a = *m.axis_index(t.axis);
    applied.push_back({.input = a, .output = a, .position = t.node, .forward = t.absolute,
                       .unit = joint_unit_factor(m.axes[a]), .wrap_turn = t.travel_per_rev > 0});
  }
  out.summary.residual = residual_before_after(model, model, residual_grid(m, sampling, o.residual_points),
                                               table_rule(std::move(applied), m.axes.size()), o.threads);
  out.summary.target = kFanucTarget;
  out.summary.quantity = TableQuantity::Correction;
  out.summary.sign_source =
      "FANUC pitch error compensation, parameters 3620-3625 and incremental values per interval x magnification "
      "(FANUC Series 0i-PB Parameter Manual B-63980EN/01, parameters 3620-3625, p. 100: values per section from the "
      "reference position, a rotary axis's values sum to zero); written as corrections (c = -e, added by the "
      "control): this sign is NOT confirmed by a public FANUC source and must be checked on the control";
  for (auto n : errors_not_held(
           m, residual_grid(m, sampling, std::min<std::size_t>(o.residual_points, 5)),
           [&](const ErrorName& n) {
             if (n.kind != ErrorKind::Motion) return false;
             const auto i = m.axis_index(n.body);
             if (!i) return false;
             const Axis& ax = m.axes[*i];
             return index_of(n.component) == (ax.kind == AxisKind::Linear ? 0 : 3) + ax.direction_axis;
           },
           o.threads))
    out.summary.not_compensated.push_back(std::move(n));
  if (reversal > 0.0)
    out.summary.not_compensated.push_back(
        {"reversal (half the forward/reverse difference; bidirectional pitch error compensation 3605#0, 3626, 3627 "
         "is not written, backlash 1851 holds its constant part)",
         reversal, "mm"});
  if (rounding > 0.0)
    out.summary.not_compensated.push_back(
        {"rounding of the values to whole counts of detection unit x magnification", rounding, "mm"});
  out.summary.warnings.push_back(
      "the values are corrections (c = -e) by assumption: no public FANUC document confirms the sign, check it on the "
      "control; the residual assumes the control interpolates linearly between compensation positions, a control "
      "that outputs each value at once at its position leaves up to one value's step in between; the reference "
      "position is taken at axis position 0");
  return out;
}

}  // namespace mtcal
