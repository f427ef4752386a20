#include "mtcal/model/machine_builder.hpp"

#include <cmath>
#include <optional>
#include <variant>

#include <fmt/format.h>

#include "mtcal/util/errors.hpp"
#include "mtcal/util/units.hpp"

namespace mtcal {
namespace {

bool located(const SourceLocation& w) { return !w.file.empty() || w.line > 0 || !w.field.empty(); }

// A reader's location names the item; code gets the item's name in the message.
[[noreturn]] void fail(const SourceLocation& where, const std::string& item, const std::string& what) {
  if (located(where)) throw InputError(where, what);
  throw ModelError(item + ": " + what);
}

std::string axis_item(char letter) { return fmt::format("axis '{}'", letter); }

bool is_linear_letter(char c) { return c == 'X' || c == 'Y' || c == 'Z'; }
AxisKind kind_of_letter(char c) { return is_linear_letter(c) ? AxisKind::Linear : AxisKind::Rotary; }
int direction_of_letter(char c) { return is_linear_letter(c) ? c - 'X' : c - 'A'; }
const char* kind_name(AxisKind k) { return k == AxisKind::Linear ? "linear" : "rotary"; }

bool finite(const Vec3& v) { return v.allFinite(); }

// What is wrong with a motion function of an axis of the given kind, or nothing.
std::optional<std::string> motion_problem(const MotionFunction& f, AxisKind kind) {
  for (std::size_t i = 0; i < f.parameter_count(); ++i)
    if (!std::isfinite(f.parameter(i)))
      return fmt::format("coefficient '{}' is {}, expected a finite value", f.parameter_suffix(i), f.parameter(i));
  if (const auto* t = std::get_if<Table>(&f.form())) {
    if (t->positions.size() < 2) return fmt::format("expected at least 2 positions, found {}", t->positions.size());
    for (std::size_t i = 0; i < t->positions.size(); ++i) {
      if (!std::isfinite(t->positions[i])) return fmt::format("position {} is not finite", i);
      if (i > 0 && !(t->positions[i] > t->positions[i - 1]))
        return fmt::format("positions must increase strictly; position {} ({}) follows {}", i, t->positions[i],
                           t->positions[i - 1]);
    }
    if (t->forward.size() != t->positions.size())
      return fmt::format("expected {} forward values (one per position), found {}", t->positions.size(),
                         t->forward.size());
    if (!t->backward.empty() && t->backward.size() != t->positions.size())
      return fmt::format("expected {} backward values (one per position), found {}", t->positions.size(),
                         t->backward.size());
  }
  if (std::holds_alternative<Fourier>(f.form()) && kind != AxisKind::Rotary)
    return std::string("a Fourier series is for rotary axes; this axis is linear");
  return std::nullopt;
}

}  // namespace

MachineBuilder::MachineBuilder(const Machine& start) : m_(start), has_topology_(true) { validate(start); }

MachineBuilder& MachineBuilder::name(std::string name) {
  m_.name = std::move(name);
  return *this;
}

MachineBuilder& MachineBuilder::description(std::string description) {
  m_.description = std::move(description);
  return *this;
}

MachineBuilder& MachineBuilder::source(std::string file) {
  m_.source = std::move(file);
  return *this;
}

MachineBuilder& MachineBuilder::topology(std::string_view chain, const SourceLocation& where) {
  Topology t;
  try {
    t = Topology::parse(chain);
  } catch (const ModelError& e) {
    if (located(where)) throw InputError(where, e.what());
    throw;  // its message names the topology already
  }
  m_.topology = t;
  m_.axes.clear();
  for (std::size_t i = 0; i < t.axes.size(); ++i) {
    Axis ax;
    ax.letter = t.axes[i];
    ax.kind = kind_of_letter(ax.letter);
    ax.direction_axis = direction_of_letter(ax.letter);
    ax.moves_workpiece = i < t.frame_index;
    for (auto& f : ax.motion) f = MotionFunction(Polynomial{});
    m_.axes.push_back(std::move(ax));
  }
  m_.tool_mounting = {};
  m_.workpiece_mounting = {};
  has_topology_ = true;
  return *this;
}

Axis& MachineBuilder::axis(char letter, const SourceLocation& where) {
  if (!has_topology_) fail(where, axis_item(letter), "no topology given yet (give the topology first)");
  const auto i = m_.axis_index(letter);
  if (!i) fail(where, axis_item(letter), fmt::format("axis '{}' is not in topology {}", letter, m_.topology.chain));
  return m_.axes[*i];
}

MachineBuilder& MachineBuilder::axis_kind(char letter, AxisKind kind, const SourceLocation& where) {
  Axis& ax = axis(letter, where);
  if (kind != kind_of_letter(letter))
    fail(where, axis_item(letter),
         fmt::format("kind {}, but {} is a {} axis ({})", kind_name(kind), letter, kind_name(kind_of_letter(letter)),
                     is_linear_letter(letter) ? "X, Y, Z are linear" : "A, B, C are rotary"));
  ax.kind = kind;
  return *this;
}

MachineBuilder& MachineBuilder::axis_direction(char letter, int direction_axis, double sign,
                                               const SourceLocation& where) {
  Axis& ax = axis(letter, where);
  const int own = direction_of_letter(letter);
  const char c = static_cast<char>('x' + own);
  if (direction_axis != own)
    fail(where, axis_item(letter),
         fmt::format("axis {} {} machine {}: its direction is '+{}' or '-{}'", letter,
                     ax.kind == AxisKind::Linear ? "moves along" : "turns about", c, c, c));
  if (sign != 1.0 && sign != -1.0)
    fail(where, axis_item(letter), fmt::format("direction sign {}, expected +1 or -1", sign));
  ax.direction_axis = direction_axis;
  ax.direction_sign = sign;
  return *this;
}

MachineBuilder& MachineBuilder::axis_travel(char letter, double min, double max, const SourceLocation& where) {
  Axis& ax = axis(letter, where);
  if (!std::isfinite(min) || !std::isfinite(max) || !(min < max))
    fail(where, axis_item(letter) + " travel", "expected [min, max] with min < max");
  ax.travel = Travel{min, max};
  return *this;
}

MachineBuilder& MachineBuilder::axis_point(char letter, const Vec3& point, const SourceLocation& where) {
  Axis& ax = axis(letter, where);
  if (!finite(point)) fail(where, axis_item(letter) + " point", "expected finite coordinates");
  ax.point = point;
  return *this;
}

MachineBuilder& MachineBuilder::tool_length(double length, const SourceLocation& where) {
  if (!std::isfinite(length) || length < 0) fail(where, "tool length", "expected a tool length >= 0");
  m_.tool.length = length;
  return *this;
}

MachineBuilder& MachineBuilder::tool_spindle_point(const Vec3& point, const SourceLocation& where) {
  if (!finite(point)) fail(where, "tool spindle point", "expected finite coordinates");
  m_.tool.spindle_point = point;
  return *this;
}

MachineBuilder& MachineBuilder::tool_axis(int axis, const SourceLocation& where) {
  if (axis < 0 || axis > 2) fail(where, "tool axis", fmt::format("{} is not a machine axis (0 x, 1 y, 2 z)", axis));
  m_.tool.tool_axis = axis;
  return *this;
}

MachineBuilder& MachineBuilder::workpiece_origin(const Vec3& origin, const SourceLocation& where) {
  if (!finite(origin)) fail(where, "workpiece origin", "expected finite coordinates");
  m_.workpiece.origin = origin;
  return *this;
}

ErrorName MachineBuilder::error_name(std::string_view name, const SourceLocation& where) const {
  const std::string key(name);
  const std::string item = "error '" + printable(key) + "'";
  if (!has_topology_) fail(where, item, "no topology given yet (give the topology first)");
  const auto en = ErrorName::parse(name);
  if (!en)
    fail(where, item,
         "unknown error name '" + key +
             "' (expected ISO 230 names such as EXX, EYX, EC0Y, EX0C, or EXt / EXw for tool / workpiece mounting)");
  if (!m_.has_error(*en)) {
    if (en->kind == ErrorKind::Location && m_.axis_index(en->body))
      fail(where, item,
           "'" + printable(key) + "' is not a location error of axis " + std::string(1, en->body) +
               " (a linear axis has its zero position and two orientation errors, a rotary axis "
               "two position, two orientation errors and its zero position)");
    fail(where, item,
         "error '" + printable(key) + "' names axis '" + printable(std::string(1, en->body)) +
             "', which is not in topology " + m_.topology.chain);
  }
  return *en;
}

MachineBuilder& MachineBuilder::motion(std::string_view error, MotionFunction f, const SourceLocation& where) {
  const ErrorName en = error_name(error, where);
  const std::string item = "error '" + printable(std::string(error)) + "'";
  if (en.kind != ErrorKind::Motion)
    fail(where, item, "is a location or mounting error: a single value, not a motion function");
  Axis& ax = m_.axes[*m_.axis_index(en.body)];
  if (auto problem = motion_problem(f, ax.kind)) fail(where, item, *problem);
  ax.motion[static_cast<std::size_t>(index_of(en.component))] = std::move(f);
  ax.motion_given[static_cast<std::size_t>(index_of(en.component))] = true;
  return *this;
}

MachineBuilder& MachineBuilder::error_value(std::string_view error, double value, const SourceLocation& where) {
  const ErrorName en = error_name(error, where);
  const std::string item = "error '" + printable(std::string(error)) + "'";
  if (en.kind == ErrorKind::Motion)
    fail(where, item, "is a motion error: a function of the axis position, not a single value");
  if (!std::isfinite(value)) fail(where, item, fmt::format("{} is not a finite value", value));
  const auto c = static_cast<std::size_t>(index_of(en.component));
  if (en.kind == ErrorKind::Location)
    m_.axes[*m_.axis_index(en.body)].location[c] = value;
  else
    (en.body == 't' ? m_.tool_mounting : m_.workpiece_mounting)[c] = value;
  return *this;
}

MachineBuilder& MachineBuilder::parameter(std::string_view name, double value, std::string_view unit,
                                          const SourceLocation& where) {
  const std::string item = "parameter '" + printable(std::string(name)) + "'";
  if (!has_topology_) fail(where, item, "no topology given yet (give the topology first)");
  const auto i = m_.parameter_index(name);
  if (!i) {
    try {
      m_.set_parameter(name, value);  // its message says what a valid name looks like
    } catch (const ModelError& e) {
      if (located(where)) throw InputError(where, e.what());
      throw;
    }
    throw ModelError(item + ": unknown parameter");  // set_parameter has thrown already
  }
  const ErrorParameter p = m_.parameters()[*i];
  double factor = 1.0;
  if (!unit.empty() && unit != p.unit) {
    const bool plain = p.unit == "mm" || p.unit == "rad";
    const auto u = find_unit(unit);
    const Dimension dim = p.unit == "mm" ? Dimension::Length : Dimension::Angle;
    if (!plain || !u || u->dimension != dim)
      fail(where, item,
           fmt::format("unit '{}' does not fit; its unit is {}{}", unit, p.unit,
                       plain ? " or another " + std::string(dim == Dimension::Length ? "length" : "angle") +
                                   " unit: " + accepted_units(dim, dim == Dimension::Angle)
                             : ""));
    factor = u->to_internal;
  }
  if (!std::isfinite(value * factor)) fail(where, item, fmt::format("{} is not a finite value", value));
  m_.set_parameter(*i, value * factor);
  return *this;
}

Machine MachineBuilder::build() const {
  if (!has_topology_) throw ModelError("topology: none given (e.g. wCBXfYZt)");
  validate(m_);
  return m_;
}

void validate(const Machine& m) {
  const SourceLocation none;
  const Topology t = Topology::parse(m.topology.chain);  // its message names the topology
  if (t.axes != m.topology.axes || t.frame_index != m.topology.frame_index)
    throw ModelError(
        fmt::format("topology '{}': its axes or frame position differ from those of the chain ({} "
                    "axes, {} of them between w and f)",
                    m.topology.chain, t.axes.size(), t.frame_index));
  if (m.axes.size() != t.axes.size())
    throw ModelError(
        fmt::format("axes: {} given, but topology {} has {}", m.axes.size(), m.topology.chain, t.axes.size()));
  for (std::size_t i = 0; i < m.axes.size(); ++i) {
    const Axis& ax = m.axes[i];
    const char L = t.axes[i];
    if (ax.letter != L)
      throw ModelError(fmt::format("axis '{}': at position {} of the axes, where topology {} has {}", ax.letter, i + 1,
                                   m.topology.chain, L));
    const std::string item = axis_item(L);
    if (ax.kind != kind_of_letter(L))
      fail(none, item,
           fmt::format("kind {}, but {} is a {} axis ({})", kind_name(ax.kind), L, kind_name(kind_of_letter(L)),
                       is_linear_letter(L) ? "X, Y, Z are linear" : "A, B, C are rotary"));
    if (ax.direction_axis != direction_of_letter(L)) {
      const char c = static_cast<char>('x' + direction_of_letter(L));
      fail(none, item,
           fmt::format("direction along machine {}, but axis {} {} machine {}",
                       static_cast<char>('x' + ax.direction_axis), L,
                       ax.kind == AxisKind::Linear ? "moves along" : "turns about", c));
    }
    if (ax.direction_sign != 1.0 && ax.direction_sign != -1.0)
      fail(none, item, fmt::format("direction sign {}, expected +1 or -1", ax.direction_sign));
    if (ax.moves_workpiece != (i < t.frame_index))
      fail(none, item,
           fmt::format("moves_workpiece is {}, but in topology {} it {} the workpiece", ax.moves_workpiece,
                       m.topology.chain, i < t.frame_index ? "moves" : "does not move"));
    if (!finite(ax.point)) fail(none, item + " point", "expected finite coordinates");
    if (ax.travel &&
        (!std::isfinite(ax.travel->min) || !std::isfinite(ax.travel->max) || !(ax.travel->min < ax.travel->max)))
      fail(none, item + " travel", fmt::format("[{}, {}]: expected min < max", ax.travel->min, ax.travel->max));
    for (int c = 0; c < 6; ++c) {
      const auto comp = static_cast<Component>(c);
      if (auto problem = motion_problem(ax.motion[static_cast<std::size_t>(c)], ax.kind))
        fail(none, "error '" + printable(ErrorName{ErrorKind::Motion, comp, L}.str()) + "'", *problem);
      const double v = ax.location[static_cast<std::size_t>(c)];
      const std::string loc = "error '" + printable(ErrorName{ErrorKind::Location, comp, L}.str()) + "'";
      if (ax.allows_location(comp)) {
        if (!std::isfinite(v)) fail(none, loc, fmt::format("{} is not a finite value", v));
      } else if (v != 0.0) {
        fail(none, loc, fmt::format("{}, but it is not a location error of axis {}, so it must be 0", v, L));
      }
    }
  }
  if (!std::isfinite(m.tool.length) || m.tool.length < 0) fail(none, "tool length", "expected a tool length >= 0");
  if (!finite(m.tool.spindle_point)) fail(none, "tool spindle point", "expected finite coordinates");
  if (m.tool.tool_axis < 0 || m.tool.tool_axis > 2)
    fail(none, "tool axis", fmt::format("{} is not a machine axis (0 x, 1 y, 2 z)", m.tool.tool_axis));
  if (!finite(m.workpiece.origin)) fail(none, "workpiece origin", "expected finite coordinates");
  for (char body : {'t', 'w'})
    for (int c = 0; c < 6; ++c) {
      const double v = (body == 't' ? m.tool_mounting : m.workpiece_mounting)[static_cast<std::size_t>(c)];
      if (!std::isfinite(v))
        fail(none, "error '" + printable(ErrorName{ErrorKind::Mounting, static_cast<Component>(c), body}.str()) + "'",
             fmt::format("{} is not a finite value", v));
    }
}

}  // namespace mtcal
