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
  double reversal = 0.0;  // largest half difference forward/reverse: what one table cannot hold
  for (const PositioningTable& t : positioning_tables(model, sampling, o.reference, kTarget)) {
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
  if (out.tables.empty())
    throw InputError({m.source, 0, ""},
                     "nothing to compensate for Siemens EEC: the model has no error along a "
                     "linear axis");
  // The control moves the axis by -value (808D Function Manual p. 106): the joint correction is
  // minus the interpolated error.
  std::vector<std::vector<double>> positions;
  for (const auto& t : out.tables) {
    std::vector<double> p(t.values.size());
    for (std::size_t i = 0; i < p.size(); ++i) p[i] = t.min + t.step * static_cast<double>(i);
    p.back() = t.max;
    positions.push_back(std::move(p));
  }
  out.summary.residual = residual_before_after(
      model, model, residual_grid(m, sampling, o.residual_points),
      [&](std::span<const double> q, std::span<const std::int8_t>) {
        AppliedCorrection c;
        c.joint.assign(m.axes.size(), 0.0);
        for (std::size_t k = 0; k < out.tables.size(); ++k) {
          const std::size_t a = *m.axis_index(out.tables[k].axis);
          c.joint[a] = -interpolate_held(positions[k], out.tables[k].values, q[a]);
        }
        return c;
      },
      o.threads);
  out.summary.target = kTarget;
  out.summary.quantity = TableQuantity::Error;
  out.summary.sign_source =
      "SINUMERIK 808D Function Manual 01/2017, leadscrew error compensation (LEC), p. 106: a positive compensation "
      "value causes the machine axis to move in the negative direction; %_N_AX_EEC_INI system variables "
      "$AA_ENC_COMP, _STEP, _MIN, _MAX, _IS_MODULO";
  out.summary.not_compensated = errors_not_held(
      m, residual_grid(m, sampling, std::min<std::size_t>(o.residual_points, 5)),
      [&](const ErrorName& n) {
        if (n.kind != ErrorKind::Motion) return false;
        const auto i = m.axis_index(n.body);
        return i && m.axes[*i].kind == AxisKind::Linear && index_of(n.component) == m.axes[*i].direction_axis;
      },
      o.threads);
  if (reversal > 0.0) {
    out.summary.not_compensated.push_back(
        {"reversal (half the forward/reverse difference of the tables; backlash compensation MD32450 $MA_BACKLASH "
         "holds its constant part)",
         reversal, "mm"});
  }
  out.summary.warnings.push_back(
      "the tables name machine axes AX1, AX2, ... in the order X Y Z A B C: rename them to the control's machine axis "
      "names ($MN_AXCONF_MACHAX_NAME_TAB) if they differ; enable with MD32700 $MA_ENC_COMP_ENABLE[0] = 1");
  return out;
}

}  // namespace mtcal
