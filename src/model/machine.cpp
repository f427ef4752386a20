#include "mtcal/model/machine.hpp"

#include <algorithm>
#include <set>
#include <type_traits>

#include "mtcal/util/errors.hpp"
#include "mtcal/util/suggest.hpp"

namespace mtcal {

Topology Topology::parse(std::string_view chain) {
  auto fail = [&](const std::string& what) {
    throw ModelError("topology '" + std::string(chain) + "': " + what +
                     " (expected w<axes>f<axes>t read from workpiece to tool, e.g. wCBXfYZt)");
  };
  if (chain.size() < 3 || chain.front() != 'w' || chain.back() != 't') fail("must start with 'w' and end with 't'");
  Topology t;
  t.chain = std::string(chain);
  int frames = 0, linear = 0, rotary = 0;
  for (std::size_t i = 1; i + 1 < chain.size(); ++i) {
    char c = chain[i];
    if (c == 'f') {
      if (++frames > 1) fail("more than one 'f'");
      t.frame_index = t.axes.size();
      continue;
    }
    if (std::string_view("XYZ").find(c) != std::string_view::npos) {
      ++linear;
    } else if (std::string_view("ABC").find(c) != std::string_view::npos) {
      ++rotary;
    } else {
      fail(std::string("unknown character '") + c + "' at position " + std::to_string(i + 1));
    }
    if (std::find(t.axes.begin(), t.axes.end(), c) != t.axes.end()) fail(std::string("axis '") + c + "' appears twice");
    t.axes.push_back(c);
  }
  if (frames != 1) fail("needs exactly one 'f' (the machine frame)");
  if (linear > 3 || rotary > 3) fail("at most 3 linear and 3 rotary axes");
  if (t.axes.empty()) fail("no axis");
  return t;
}

bool Axis::allows_location(Component c) const {
  const int i = index_of(c);
  const bool rot = is_rotation(c);
  const int dir = rot ? i - 3 : i;
  if (kind == AxisKind::Linear) {
    // Zero position along the axis; orientation about the two perpendicular directions.
    return rot ? dir != direction_axis : dir == direction_axis;
  }
  // Rotary: position across the axis line, orientation about perpendiculars, zero position.
  return rot ? true : dir != direction_axis;
}

std::optional<std::size_t> Machine::axis_index(char letter) const {
  for (std::size_t i = 0; i < axes.size(); ++i)
    if (axes[i].letter == letter) return i;
  return std::nullopt;
}

const Axis& Machine::axis(char letter) const {
  auto i = axis_index(letter);
  if (!i) throw ModelError(std::string("axis '") + letter + "' is not in topology " + topology.chain);
  return axes[*i];
}

bool Machine::has_error(const ErrorName& n) const {
  if (n.kind == ErrorKind::Mounting) return true;
  auto i = axis_index(n.body);
  if (!i) return false;
  if (n.kind == ErrorKind::Motion) return true;
  return axes[*i].allows_location(n.component);
}

namespace {

std::string unit_for(bool rotation, bool argument_rotary, int power) {
  std::string u = rotation ? "rad" : "mm";
  if (power == 0) return u;
  u += argument_rotary ? "/rad" : "/mm";
  if (power > 1) u += "^" + std::to_string(power);
  return u;
}

// Calls fn(parameter, setter) for every parameter in canonical order until fn returns false.
// The setter writes the parameter; for a const machine it does nothing.
template <class M, class Fn>
void walk(M& m, Fn&& fn) {
  constexpr bool writable = !std::is_const_v<M>;
  for (auto& ax : m.axes) {
    for (int c = 0; c < 6; ++c) {
      auto comp = static_cast<Component>(c);
      ErrorName en{ErrorKind::Motion, comp, ax.letter};
      auto& f = ax.motion[c];
      for (std::size_t i = 0; i < f.parameter_count(); ++i) {
        ErrorParameter p{en.str() + "." + f.parameter_suffix(i), en,
                         unit_for(is_rotation(comp), ax.kind == AxisKind::Rotary, f.argument_power(i)), f.parameter(i)};
        if (!fn(p, [&f, i](double v) {
              if constexpr (writable)
                f.set_parameter(i, v);
              else
                (void)f, (void)i;  // read-only walk: the setter is never called (clang: unused capture)
            }))
          return;
      }
    }
    for (int c = 0; c < 6; ++c) {
      auto comp = static_cast<Component>(c);
      if (!ax.allows_location(comp)) continue;
      ErrorName en{ErrorKind::Location, comp, ax.letter};
      ErrorParameter p{en.str(), en, unit_for(is_rotation(comp), false, 0), ax.location[c]};
      auto* slot = &ax.location[c];
      if (!fn(p, [slot](double v) {
            if constexpr (writable)
              *slot = v;
            else
              (void)slot;
          }))
        return;
    }
  }
  for (char body : {'t', 'w'}) {
    auto& arr = body == 't' ? m.tool_mounting : m.workpiece_mounting;
    for (int c = 0; c < 6; ++c) {
      auto comp = static_cast<Component>(c);
      ErrorName en{ErrorKind::Mounting, comp, body};
      ErrorParameter p{en.str(), en, unit_for(is_rotation(comp), false, 0), arr[c]};
      auto* slot = &arr[c];
      if (!fn(p, [slot](double v) {
            if constexpr (writable)
              *slot = v;
            else
              (void)slot;
          }))
        return;
    }
  }
}

}  // namespace

std::string parameter_naming(const Machine& m) {
  std::string motion, location;
  walk(m, [&](const ErrorParameter& p, auto&&) {
    if (motion.empty() && p.error.kind == ErrorKind::Motion && p.name.back() == '1') motion = p.name;
    if (location.empty() && p.error.kind == ErrorKind::Location) location = p.name;
    return motion.empty() || location.empty();
  });
  std::string s = "expected a parameter of topology " + m.topology.chain + ": a motion error with its coefficient";
  if (!motion.empty()) s += " such as " + motion;
  if (!location.empty()) s += ", a location error such as " + location;
  return s + " or a mounting error such as EXt, EAw";
}

std::string name_hint(const Machine& m, std::string_view typed) {
  std::vector<std::string> names;
  walk(m, [&](const ErrorParameter& p, auto&&) {
    const std::string e = p.error.str();
    if (std::find(names.begin(), names.end(), e) == names.end()) names.push_back(e);
    if (p.name != e) names.push_back(p.name);
    return true;
  });
  return did_you_mean(typed, names);
}

std::vector<ErrorParameter> Machine::parameters() const {
  std::vector<ErrorParameter> out;
  walk(*this, [&](const ErrorParameter& p, auto&&) {
    out.push_back(p);
    return true;
  });
  return out;
}

std::size_t Machine::parameter_count() const {
  std::size_t n = 0;
  for (const auto& ax : axes) {
    for (const auto& f : ax.motion) n += f.parameter_count();
    for (int c = 0; c < 6; ++c) n += ax.allows_location(static_cast<Component>(c)) ? 1 : 0;
  }
  return n + 12;
}

std::optional<std::size_t> Machine::parameter_index(std::string_view param) const {
  std::optional<std::size_t> found;
  std::size_t i = 0;
  walk(*this, [&](const ErrorParameter& p, auto&&) {
    if (p.name == param) {
      found = i;
      return false;
    }
    ++i;
    return true;
  });
  return found;
}

double Machine::parameter(std::size_t index) const {
  double v = 0.0;
  std::size_t i = 0;
  walk(*this, [&](const ErrorParameter& p, auto&&) {
    if (i++ != index) return true;
    v = p.value;
    return false;
  });
  return v;
}

void Machine::set_parameter(std::size_t index, double value) {
  std::size_t i = 0;
  bool done = false;
  walk(*this, [&](const ErrorParameter&, auto&& set) {
    if (i++ != index) return true;
    set(value);
    done = true;
    return false;
  });
  if (!done) throw ModelError("parameter index " + std::to_string(index) + " out of range");
}

void Machine::set_parameter(std::string_view param, double value) {
  auto i = parameter_index(param);
  if (!i)
    throw ModelError("unknown parameter '" + std::string(param) + "'" + name_hint(*this, param) + " for machine '" +
                     name + "' (" + parameter_naming(*this) + ")");
  set_parameter(*i, value);
}

void Machine::keep_only(const std::vector<std::string>& names) {
  std::set<std::string> errors, params;
  for (const auto& n : names) {
    if (n.find('.') != std::string::npos) {
      if (!parameter_index(n))
        throw ModelError("unknown parameter '" + n + "'" + name_hint(*this, n) + " for machine '" + name + "' (" +
                         parameter_naming(*this) + ")");
      params.insert(n);
    } else {
      auto en = ErrorName::parse(n);
      if (!en || !has_error(*en))
        throw ModelError("unknown error name '" + n + "'" + name_hint(*this, n) + " for topology " + topology.chain);
      errors.insert(n);
    }
  }
  walk(*this, [&](const ErrorParameter& p, auto&& set) {
    if (!errors.count(p.error.str()) && !params.count(p.name)) set(0.0);
    return true;
  });
}

void Machine::clear_errors() {
  walk(*this, [&](const ErrorParameter&, auto&& set) {
    set(0.0);
    return true;
  });
}

}  // namespace mtcal
