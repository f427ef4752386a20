#include "mtcal/compensation/siemens.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "mtcal/compensation/tables.hpp"
#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {

SiemensCompensation compensate_siemens(const Machine& m, const CompensationOptions& o) {
  constexpr const char* kTarget = "siemens";
  const auto sampling = resolve_sampling(m, o, 51, kSiemensMaxPoints, kTarget);
  SiemensCompensation out;
  std::string coordinates;
  for (const char c : std::string("XYZABC"))
    if (m.axis_index(c)) coordinates += c;
  const ErrorModel model(m);
  // What EEC and CEC hold: positioning (EXX ...), straightness (EYX ...) and squareness (EC0Y ...)
  // of the linear axes, which move the tool point along a linear axis as a function of one axis.
  auto held = [&](const ErrorName& n) {
    const auto i = m.axis_index(n.body);
    if (!i || m.axes[*i].kind != AxisKind::Linear) return false;
    if (n.kind == ErrorKind::Motion) return !is_rotation(n.component);
    return n.kind == ErrorKind::Location && is_rotation(n.component);
  };
  // The tables are sampled on those errors alone: sampled on the whole model at the reference they
  // would also take the effect of the other errors there (a tilted rotary table looks like a
  // squareness at C = 0 and is the opposite one at C = 180 deg; an angular error's Abbe offset
  // changes with the other axes), which a table of a linear axis would then add elsewhere. On the
  // 5-axis examples that made the residual larger than the error before.
  Machine held_only = m;
  {
    std::vector<std::string> names;
    for (const auto& p : m.parameters())
      if (p.value != 0.0 && held(p.error)) names.push_back(p.error.str());
    held_only.keep_only(names);
  }
  const ErrorModel held_model(held_only);
  double reversal = 0.0;  // largest half difference forward/reverse: what one table cannot hold
  for (const PositioningTable& t : positioning_tables(held_model, sampling, o.reference, kTarget)) {
    SiemensEecTable table;
    table.axis = t.axis;
    table.machine_axis = static_cast<int>(coordinates.find(t.axis)) + 1;
    table.min = t.position.front();
    table.max = t.position.back();
    table.step = (table.max - table.min) / static_cast<double>(t.position.size() - 1);
    for (std::size_t i = 0; i < t.position.size(); ++i) {
      table.values.push_back(0.5 * (t.forward[i] + t.reverse[i]));
      reversal = std::max(reversal, 0.5 * std::abs(t.forward[i] - t.reverse[i]));
    }
    out.tables.push_back(std::move(table));
  }
  // Cross-axis tables: base I, compensation O (both linear), the tool point's error along O while I
  // alone moves, as a correction, zero at I's reference (the EEC table of O holds the error there).
  for (std::size_t i = 0; i < m.axes.size(); ++i) {
    if (m.axes[i].kind != AxisKind::Linear) continue;
    const JointErrorTable t = sample_joint_error(held_model, sampling[i], o.reference, kTarget);
    const double ref_i = o.reference.empty() ? 0.0 : o.reference[i];
    for (std::size_t k = 0; k < m.axes.size(); ++k) {
      const Axis& out_axis = m.axes[k];
      if (k == i || out_axis.kind != AxisKind::Linear) continue;
      const Vec3 u = out_axis.direction();
      std::vector<double> mean(t.position.size());
      double cross_reversal = 0.0;
      for (std::size_t n = 0; n < t.position.size(); ++n) {
        const double f = t.forward[n].translation.dot(u), r = t.reverse[n].translation.dot(u);
        mean[n] = 0.5 * (f + r);
        cross_reversal = std::max(cross_reversal, 0.5 * std::abs(f - r));
      }
      const double at_ref = interpolate_held(t.position, mean, ref_i);
      SiemensCecTable table;
      table.input = m.axes[i].letter;
      table.output = out_axis.letter;
      table.input_machine_axis = static_cast<int>(coordinates.find(table.input)) + 1;
      table.output_machine_axis = static_cast<int>(coordinates.find(table.output)) + 1;
      table.min = t.position.front();
      table.max = t.position.back();
      table.step = (table.max - table.min) / static_cast<double>(t.position.size() - 1);
      double largest = 0.0;
      for (const double e : mean) {
        table.values.push_back(-(e - at_ref));
        largest = std::max(largest, std::abs(table.values.back()));
      }
      if (largest < 0.5e-9) continue;  // below the file's resolution (nine decimals of a mm)
      reversal = std::max(reversal, cross_reversal);
      out.cec.push_back(std::move(table));
    }
  }
  if (out.tables.empty() && out.cec.empty())
    throw InputError({m.source, 0, ""},
                     "nothing to compensate for Siemens EEC/CEC: the model has no error of the tool point along a "
                     "linear axis");
  if (out.cec.size() > kSiemensMaxCecTables)
    throw InputError({m.source, 0, ""}, fmt::format("expected at most {} sag/angularity (CEC) tables, found {} "
                                                    "pairs of linear axes with a cross error",
                                                    kSiemensMaxCecTables, out.cec.size()));
  // The control moves the axis by -value of its EEC table (808D Function Manual p. 106) and by
  // +value of every CEC table whose compensation axis it is (K3 4.4.3: the values of all tables of
  // an axis are summed). Both tables: linear interpolation, ends held.
  auto node_positions = [](double min, double max, double step, std::size_t count) {
    std::vector<double> p(count);
    for (std::size_t i = 0; i < count; ++i) p[i] = min + step * static_cast<double>(i);
    p.back() = max;
    return p;
  };
  std::vector<ControllerTable> applied;
  for (const auto& t : out.tables) {
    const std::size_t a = *m.axis_index(t.axis);
    applied.push_back({.input = a, .output = a, .position = node_positions(t.min, t.max, t.step, t.values.size()),
                       .forward = t.values, .sign = -1.0});
  }
  for (const auto& t : out.cec)
    applied.push_back({.input = *m.axis_index(t.input), .output = *m.axis_index(t.output),
                       .position = node_positions(t.min, t.max, t.step, t.values.size()), .forward = t.values});
  out.summary.residual = residual_before_after(model, model, residual_grid(m, sampling, o.residual_points),
                                               table_rule(std::move(applied), m.axes.size()), o.threads);
  out.summary.target = kTarget;
  out.summary.quantity = TableQuantity::Error;
  out.summary.sign_source =
      "AX_EEC.INI: SINUMERIK 808D Function Manual 01/2017, leadscrew error compensation (LEC), p. 106: a positive "
      "compensation value causes the machine axis to move in the negative direction (values are errors); "
      "NC_CEC.INI: SINUMERIK Function Manual Extended Functions 03/2013 (6FC5397-1BP40-3BA1), K3 4.4.3 sag and "
      "angularity compensation: the table's value is applied to the position of the compensation axis "
      "$AN_CEC_OUTPUT_AXIS (values are corrections, -e)";
  out.summary.not_compensated =
      errors_not_held(m, residual_grid(m, sampling, std::min<std::size_t>(o.residual_points, 5)), held, o.threads);
  if (reversal > 0.0) {
    out.summary.not_compensated.push_back(
        {"reversal (half the forward/reverse difference of the tables; backlash compensation MD32450 $MA_BACKLASH "
         "holds its constant part)",
         reversal, "mm"});
  }
  out.summary.warnings.push_back(
      "the tables name machine axes AX1, AX2, ... in the order X Y Z A B C: rename them to the control's machine axis "
      "names ($MN_AXCONF_MACHAX_NAME_TAB) if they differ; enable with MD32700 $MA_ENC_COMP_ENABLE[0] = 1");
  if (!out.cec.empty())
    out.summary.warnings.push_back(fmt::format(
        "NC_CEC.INI has {} sag/angularity tables of {} points: they need the option \"sag compensation, "
        "multi-dimensional\", MD18342 $MN_MM_CEC_MAX_POINTS[t] >= the points (840D sl), MD32710 $MA_CEC_ENABLE = 1 on "
        "the compensation axes and $SN_CEC_TABLE_ENABLE[t] = 1 per table",
        out.cec.size(), out.cec.front().values.size()));
  return out;
}

}  // namespace mtcal
