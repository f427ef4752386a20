// Building a Machine item by item with every inconsistency refused, and validating one made by hand.
#pragma once

#include <string>
#include <string_view>

#include "mtcal/model/error_name.hpp"
#include "mtcal/model/machine.hpp"
#include "mtcal/model/motion_function.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {

// Assembles a Machine from its items in internal units (mm, rad): topology first, then axes,
// tool, workpiece and errors in any order. Each call checks its item at once and throws,
// naming the item:
//  - with a SourceLocation that names a file (a reader passes the file, line and key of the
//    item): InputError at that location, the location naming the item;
//  - without one (code): ModelError "<item>: <what is wrong>", e.g.
//    "axis 'B': kind linear, but B is a rotary axis (A, B, C are rotary)".
// Axes the calls do not mention keep their defaults: kind from the letter, direction + along
// the machine axis of the letter (X and A: x ...), point at the origin, no travel limit. Every
// motion error starts as a zero cubic polynomial with reversal, so each of its coefficients is
// a parameter whether or not it is given.
class MachineBuilder {
 public:
  MachineBuilder() = default;
  // Starts from an existing machine (validated), e.g. to apply a parameter file to it.
  explicit MachineBuilder(const Machine& start);

  MachineBuilder& name(std::string name);
  MachineBuilder& description(std::string description);
  MachineBuilder& source(std::string file);  // the file the machine comes from, for messages

  // "wCBXfYZt": letters w f t X Y Z A B C, exactly one each of w, f, t (w first, t last), each
  // axis letter at most once, at least one axis. Resets axes and errors.
  MachineBuilder& topology(std::string_view chain, const SourceLocation& where = {});

  // X, Y, Z are linear, A, B, C rotary: a kind is accepted only where it matches the letter.
  MachineBuilder& axis_kind(char axis, AxisKind kind, const SourceLocation& where = {});
  // Machine direction 0 x, 1 y, 2 z, sign +1 or -1. The direction lies along the machine axis of
  // the letter (X and A: x, Y and B: y, Z and C: z); only its sign is free.
  MachineBuilder& axis_direction(char axis, int direction_axis, double sign, const SourceLocation& where = {});
  // min < max, both finite; mm for linear axes, rad for rotary axes.
  MachineBuilder& axis_travel(char axis, double min, double max, const SourceLocation& where = {});
  MachineBuilder& axis_point(char axis, const Vec3& point, const SourceLocation& where = {});

  MachineBuilder& tool_length(double length, const SourceLocation& where = {});  // finite, >= 0
  MachineBuilder& tool_spindle_point(const Vec3& point, const SourceLocation& where = {});
  MachineBuilder& tool_axis(int axis, const SourceLocation& where = {});  // 0 x, 1 y, 2 z
  MachineBuilder& workpiece_origin(const Vec3& origin, const SourceLocation& where = {});

  // The ISO 230 name of an error of this machine's topology ("EXX", "EC0Y", "EXt"), checked:
  // an unknown name, an axis not in the topology, or a location error the axis does not have.
  ErrorName error_name(std::string_view name, const SourceLocation& where = {}) const;
  // A motion error (EXX ...): finite values; a table with >= 2 strictly increasing positions and
  // one value per position; a Fourier series only on a rotary axis.
  MachineBuilder& motion(std::string_view error, MotionFunction f, const SourceLocation& where = {});
  // A location (EC0Y) or mounting (EXt) error, finite, in mm or rad.
  MachineBuilder& error_value(std::string_view error, double value, const SourceLocation& where = {});
  // One parameter by its name ("EXX.1", "EC0Y", "EXt"; see Machine::parameters()), finite. unit
  // empty: the parameter's internal unit (ErrorParameter::unit, e.g. "mm/mm"); otherwise that
  // unit's name, or for a parameter in mm or rad any unit of the same dimension ("um", "urad",
  // "um/m" for angles).
  MachineBuilder& parameter(std::string_view name, double value, std::string_view unit = {},
                            const SourceLocation& where = {});

  // The machine as built so far (e.g. a reader asking an axis's kind).
  const Machine& current() const { return m_; }
  // The machine, after validate(): throws ModelError naming the item if anything is inconsistent
  // (e.g. no topology given).
  Machine build() const;

 private:
  Axis& axis(char letter, const SourceLocation& where);
  Machine m_;
  bool has_topology_ = false;
};

// Checks a machine assembled by hand against the same rules as MachineBuilder, and that its
// records agree with each other (axes in topology order, kinds, directions and which axes move
// the workpiece as the topology says, no value in a location slot the axis does not have).
// Throws ModelError "<item>: <what is wrong>" for the first problem found.
void validate(const Machine& m);

}  // namespace mtcal
