#include "mtcal/compensation/heidenhain.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "mtcal/compensation/tables.hpp"
#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {

HeidenhainCompensation compensate_heidenhain(const Machine& m, const CompensationOptions& o) {
  constexpr const char* kTarget = "heidenhain";
  const auto sampling = resolve_sampling(m, o, 51, kHeidenhainMaxPoints, kTarget);
  const ErrorModel model(m);
  const ErrorModel linear_model(linear_axis_errors(m));  // what the tables are sampled on
  std::vector<double> reference = o.reference;
  if (reference.empty()) reference.assign(m.axes.size(), 0.0);
  std::vector<std::size_t> linear;
  for (std::size_t a = 0; a < m.axes.size(); ++a)
    if (m.axes[a].kind == AxisKind::Linear) linear.push_back(a);
  // The tool point's error at the reference configuration, mean of both directions: held once, by
  // each axis's own table.
  std::vector<std::int8_t> plus(m.axes.size(), 1), minus(m.axes.size(), -1);
  const Vec3 e_ref =
      0.5 * (linear_model.evaluate(reference, plus).translation + linear_model.evaluate(reference, minus).translation);
  HeidenhainCompensation out;
  double reversal = 0.0;
  for (const std::size_t a : linear) {
    const JointErrorTable t = sample_joint_error(linear_model, sampling[a], reference, kTarget);
    HeidenhainComTable table;
    table.axis = m.axes[a].letter;
    table.position = t.position;
    for (const std::size_t k : linear) {
      const Vec3 u = m.axes[k].direction();
      std::vector<double> v(t.position.size());
      bool any = false;
      for (std::size_t i = 0; i < v.size(); ++i) {
        const double f = t.forward[i].translation.dot(u), r = t.reverse[i].translation.dot(u);
        v[i] = 0.5 * (f + r) - (k == a ? 0.0 : e_ref.dot(u));
        reversal = std::max(reversal, 0.5 * std::abs(f - r));
        any = any || std::abs(v[i]) > 1e-12;
      }
      if (!any) continue;
      table.columns += m.axes[k].letter;
      table.values.push_back(std::move(v));
    }
    if (!table.columns.empty()) out.tables.push_back(std::move(table));
  }
  if (out.tables.empty())
    throw InputError({m.source, 0, ""},
                     "nothing to compensate for HEIDENHAIN: the model has no error along a linear axis that a "
                     "linear axis's motion causes");
  // The control moves the column's axis by minus the value (assumed sign, docs), indexed by the
  // table's axis (*.CMA), one column for both directions.
  std::vector<ControllerTable> applied;
  for (const auto& t : out.tables)
    for (std::size_t col = 0; col < t.columns.size(); ++col)
      applied.push_back({.input = *m.axis_index(t.axis), .output = *m.axis_index(t.columns[col]), .position = t.position,
                         .forward = t.values[col], .sign = -1.0});
  out.summary.residual = residual_before_after(model, model, residual_grid(m, sampling, o.residual_points),
                                               table_rule(std::move(applied), m.axes.size()), o.threads);
  out.summary.target = kTarget;
  out.summary.quantity = TableQuantity::Error;
  out.summary.sign_source =
      "HEIDENHAIN nonlinear axis error compensation: *.COM tables (NR, AXISPOS, a column per compensated axis) "
      "assigned by *.CMA, [axis of the *.COM column] = F(axis of the *.CMA column) (MANUALplus 620 Technical Manual "
      "01/2012, pp. 716-718); values written as the measured error, as the manuals' example tabulates 'Error in Z' "
      "(TNC 407 Technical Manual 01/98, 4-28): the sign the control applies is NOT confirmed publicly and must be "
      "checked on the control";
  out.summary.not_compensated = errors_not_held(
      m, residual_grid(m, sampling, std::min<std::size_t>(o.residual_points, 5)),
      [&](const ErrorName& n) {
        if (n.kind != ErrorKind::Motion || is_rotation(n.component)) return false;
        const auto i = m.axis_index(n.body);
        return i && m.axes[*i].kind == AxisKind::Linear;
      },
      o.threads);
  if (reversal > 0.0)
    out.summary.not_compensated.push_back(
        {"reversal (half the forward/reverse difference; the *.COM BACKLASH column is not written)", reversal, "mm"});
  out.summary.warnings.push_back(
      "the values are errors and the control is assumed to move each axis by minus the value: this sign is not "
      "confirmed by a public HEIDENHAIN document, check it on the control (move to a table point and compare); "
      "angular errors are held only where they act at the compensation's reference position; the table editor may "
      "round the values");
  return out;
}

}  // namespace mtcal
