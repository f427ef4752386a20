#include "mtcal/compensation/isg.hpp"

#include <fmt/format.h>

#include "mtcal/compensation/tables.hpp"
#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/model/joints.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {

namespace {
constexpr const char* kIsgTarget = "isg";
}  // namespace

IsgCompensation compensate_isg(const Machine& m, const CompensationOptions& o) {
  for (const char l : {'X', 'Y', 'Z'})
    if (!m.axis_index(l) || m.axis(l).kind != AxisKind::Linear)
      throw InputError({m.source, 0, std::string(1, l)},
                       fmt::format("ISG volumetric compensation needs linear axes X, Y and Z; {} has no {}",
                                   m.topology.chain, l));
  const auto sampling = resolve_sampling(m, o, 51, 100000, kIsgTarget);
  IsgCompensation out;
  // What the control evaluates: the machine with the tables in place of the motion functions
  // (linear interpolation, one table for both directions) and without set-up errors.
  Machine emulated = m;
  emulated.tool_mounting = {};
  emulated.workpiece_mounting = {};
  double reversal = 0.0;
  for (std::size_t a = 0; a < m.axes.size(); ++a) {
    const Axis& ax = m.axes[a];
    IsgComponentTable table;
    table.axis = ax.letter;
    for (std::size_t c = 0; c < 6; ++c) {
      const Component comp = static_cast<Component>(c);
      const ComponentTable t = sample_component(m, comp, sampling[a], kIsgTarget);
      std::vector<double> mean(t.position.size());
      bool any = false;
      for (std::size_t i = 0; i < mean.size(); ++i) {
        mean[i] = 0.5 * (t.forward[i] + t.reverse[i]);
        any = any || t.forward[i] != 0.0 || t.reverse[i] != 0.0;
        if (!is_rotation(comp)) reversal = std::max(reversal, 0.5 * std::abs(t.forward[i] - t.reverse[i]));
      }
      if (!any) continue;
      table.position = t.position;
      table.names.push_back(t.error.str());
      Table form;
      for (const double p : t.position) form.positions.push_back(p * joint_unit_factor(ax));
      form.forward = mean;
      emulated.axes[a].motion[c] = MotionFunction(form);
      table.values.push_back(std::move(mean));
    }
    if (!table.names.empty()) out.tables.push_back(std::move(table));
  }
  for (const auto& p : m.parameters())
    if (p.error.kind == ErrorKind::Location && p.value != 0.0)
      out.position_errors.push_back({p.name.substr(1), p.value});
  if (out.tables.empty() && out.position_errors.empty())
    throw InputError({m.source, 0, ""}, "nothing to compensate for ISG: the model has no motion or location error");

  // The control moves the tool by minus its model's position error (it corrects the axis
  // setpoints for the tool position, TF5280 manual "Overview").
  const ErrorModel control(emulated);
  const ErrorModel model(m);
  out.summary.residual = residual_before_after(
      model, model, residual_grid(m, sampling, o.residual_points),
      [&](std::span<const double> q, std::span<const std::int8_t>) {
        AppliedCorrection c;
        c.cartesian = -control.evaluate(q).translation;
        return c;
      },
      o.threads);
  out.summary.target = kIsgTarget;
  out.summary.quantity = TableQuantity::Error;
  out.summary.sign_source =
      "Beckhoff TF5280 Volumetric Compensation (ISG kernel manual): the parameters of the ISO 230-1/-7 machine model "
      "(errors, e = actual - nominal), mm or rad, arguments mm or deg ('Units of measure', 'ISG CSV format'); the "
      "control corrects the axis setpoints for the tool position ('Overview')";
  out.summary.not_compensated = errors_not_held(
      m, residual_grid(m, sampling, std::min<std::size_t>(o.residual_points, 5)),
      [](const ErrorName& n) { return n.kind != ErrorKind::Mounting; }, o.threads);
  if (reversal > 0.0)
    out.summary.not_compensated.push_back(
        {"reversal (half the forward/reverse difference of the motion errors; one table serves both directions)",
         reversal, "mm"});
  out.summary.warnings.push_back(
      "the control corrects the tool position, not its orientation; position errors are named as mtcal's without "
      "the leading E (EC0Y -> C0Y), after the manual's example 'Y0A Z0A X0B': check the names against the control's "
      "parameter list; the .lis configuration that names this file is not written");
  return out;
}

IsgCompensation compensate_etalon(const Machine& m, const CompensationOptions& o) {
  IsgCompensation out = compensate_isg(m, o);
  out.summary.target = "etalon";
  out.summary.sign_source =
      "Beckhoff TF5280 Volumetric Compensation (ISG kernel manual), 'Etalon Exchange Format' (vendor variant): one "
      "block per parameter, [C0B] VALUE = ... for position errors, [EXY] Gridpoints = { argument value ... } for "
      "component errors; errors (e = actual - nominal) in mm or rad, arguments in mm or deg as for the ISG CSV format "
      "('Units of measure'; the Etalon page gives no units: assumed the same)";
  for (auto& w : out.summary.warnings)
    if (w.find(".lis") != std::string::npos)
      w = "the control corrects the tool position, not its orientation; position errors are named without the "
          "leading E ([C0B]) and component errors with it ([EXY]), as in the manual's Etalon example; the .lis "
          "configuration that names this file is not written";
  return out;
}

}  // namespace mtcal
