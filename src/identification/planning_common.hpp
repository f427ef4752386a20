// Internal: small helpers the planning units share (candidates, design, probing program).
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "mtcal/identification/planning.hpp"
#include "mtcal/kinematics/error_model.hpp"

namespace mtcal::planning_detail {

inline std::vector<std::size_t> rotary_axes(const Machine& m) {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < m.axes.size(); ++i)
    if (m.axes[i].kind == AxisKind::Rotary) out.push_back(i);
  return out;
}
inline std::vector<std::size_t> linear_axes(const Machine& m) {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < m.axes.size(); ++i)
    if (m.axes[i].kind == AxisKind::Linear) out.push_back(i);
  return out;
}

inline Machine nominal_of(const Machine& m) {
  Machine n = m;
  n.clear_errors();
  return n;
}

// Unit vector from the probe's tip to the spindle in the workpiece frame: the tool points along
// -(tool axis) of the tool frame (model/machine.hpp, ToolSetup).
inline Vec3 tool_axis(const ErrorModel& nominal, const ProbingRecord& r) {
  return nominal.nominal_pose(r.q).R.col(nominal.machine().tool.tool_axis).normalized();
}

// How match_contacts words its messages and checks each contact's distance: the program the log
// must follow ("the plan", "the locating program"), its probing moves ("the program's probing
// moves for 3 records"), what follows the missing-contact sentence, and per contact (index into
// the touches) the touch ("touch 2 of the plan's record 3, line 5") and its owner ("the plan's
// record 3 (line 5)", "locating ball B1").
struct ContactWording {
  std::string program, moves, missing_tail;
  std::function<std::string(std::size_t contact)> touch, owner;
  // The distance check: with on_move > 0, a contact farther than that (mm) off its probing move
  // (across it, or before its start or beyond its end); else farther than from_expected from the
  // expected contact.
  double on_move = 0.0, from_expected = 0.0;
};
// The contacts of a program's log against its touches, in order: the count (a short log names the
// first contact missing; an extra one is located at its line), the rotary axes at the record's
// values (1e-6 rad; an axis the log does not have is not checked), X Y Z present, the distance
// (ContactWording). Returns the X Y Z of each contact (the linear axes' values, chain order among
// them). Throws InputError located at the log's lines (log_source when it holds no contact).
std::vector<Vec3> match_contacts(const Machine& m, const ProbingPlan& plan, const std::vector<ProbeTouch>& touches,
                                 const std::vector<LoggedContact>& contacts, const ContactWording& wording,
                                 const std::string& log_source);

}  // namespace mtcal::planning_detail
