// Machine model: topology, axes, tool and workpiece set-up, and every named error parameter.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "mtcal/model/error_name.hpp"
#include "mtcal/model/motion_function.hpp"

namespace mtcal {

using Vec3 = Eigen::Vector3d;

enum class AxisKind { Linear, Rotary };

// Kinematic chain read from workpiece to tool, e.g. "wCBXfYZt": C carries the workpiece, B
// carries C, X carries B and runs on the frame f; Y runs on the frame, Z on Y, the tool on Z.
struct Topology {
  std::string chain;
  std::vector<char> axes;       // axis letters in chain order, workpiece to tool
  std::size_t frame_index = 0;  // number of axes between w and f (they move the workpiece)

  // Throws ModelError naming the offending character if the string is not w<axes>f<axes>t
  // with distinct letters from XYZABC, at most 3 linear and 3 rotary.
  static Topology parse(std::string_view chain);
};

struct Travel {
  double min = 0.0;  // internal units: mm or rad
  double max = 0.0;
};

struct Axis {
  char letter = 'X';
  AxisKind kind = AxisKind::Linear;
  // Nominal direction: +/- machine x, y or z. A positive command moves the tool relative to the
  // workpiece along (linear) or about (rotary, right-hand rule) this direction, whichever body
  // physically moves (ISO 841).
  int direction_axis = 0;     // 0 x, 1 y, 2 z
  double direction_sign = 1;  // +1 or -1
  // Rotary: a point of the nominal axis line. Linear: the point of the moving body at which its
  // translational motion errors are referred (measurement offsets, Fletcher 2009 3.1).
  // Machine coordinates (mm) with every axis at zero.
  Vec3 point = Vec3::Zero();
  std::optional<Travel> travel;
  bool moves_workpiece = false;  // true for axes between w and f in the topology

  std::array<MotionFunction, 6> motion;  // indexed by Component: EXx EYx EZx EAx EBx ECx
  std::array<bool, 6> motion_given{};    // appears in the machine file (for round trip)
  std::array<double, 6> location{};      // indexed by Component; see allowed_location()

  Vec3 direction() const {
    Vec3 u = Vec3::Zero();
    u[direction_axis] = direction_sign;
    return u;
  }
  // Whether E<c>0<letter> is a location error of this axis (ISO 230-1 / ISO 230-7):
  // linear: zero position along the axis and the two orientation errors;
  // rotary: two position errors, two orientation errors and the zero position.
  bool allows_location(Component c) const;
};

struct ToolSetup {
  double length = 0.0;                // mm, from the spindle gauge point along -tool_axis
  Vec3 spindle_point = Vec3::Zero();  // gauge point, machine coordinates at zero
  int tool_axis = 2;                  // tool points along -(this machine axis); 2 = z
};

struct WorkpieceSetup {
  Vec3 origin = Vec3::Zero();  // workpiece frame origin, machine coordinates at zero (axes parallel)
};

// One scalar parameter of the error model, as listed by `mtcal errors` and addressed by --set.
struct ErrorParameter {
  std::string name;  // "EXX.1", "EC0Y", "EXt", "EYX.f3"
  ErrorName error;   // the error it belongs to
  std::string unit;  // internal unit: "mm", "rad", "mm/mm", "rad/mm^2", "mm/rad" ...
  double value = 0.0;
};

struct Machine {
  std::string name;
  std::string description;
  std::string source;  // file it was loaded from, for messages
  Topology topology;
  std::vector<Axis> axes;  // chain order, workpiece to tool
  ToolSetup tool;
  WorkpieceSetup workpiece;
  std::array<double, 6> tool_mounting{};       // EXt EYt EZt EAt EBt ECt
  std::array<double, 6> workpiece_mounting{};  // EXw ... ECw

  // Index in axes of an axis letter, or nullopt.
  std::optional<std::size_t> axis_index(char letter) const;
  const Axis& axis(char letter) const;  // throws ModelError if absent

  // Whether an error name is defined for this machine's axes.
  bool has_error(const ErrorName& n) const;

  // Every parameter of the model in a stable order: per axis (chain order) the six motion
  // errors with their coefficients, then its location errors; then tool and workpiece mounting.
  std::vector<ErrorParameter> parameters() const;
  std::size_t parameter_count() const;
  std::optional<std::size_t> parameter_index(std::string_view name) const;
  double parameter(std::size_t index) const;
  void set_parameter(std::size_t index, double value);
  // Sets by name ("EXX.1", "EC0Y"); throws ModelError for an unknown name.
  void set_parameter(std::string_view name, double value);

  // Zeroes every error not named; names may be errors ("EXX": all its coefficients) or
  // parameters ("EXX.1"). Throws ModelError for a name the machine does not have.
  void keep_only(const std::vector<std::string>& names);
  // Zeroes every error.
  void clear_errors();
};

// What a valid parameter name looks like on this machine, with examples of its own names: the
// expectation half of every "unknown parameter" message.
std::string parameter_naming(const Machine& m);
// " (did you mean 'EC0Y'?)" when one of the machine's parameter or error names is close to typed
// (case-insensitive edit distance, util/suggest.hpp), else "".
std::string name_hint(const Machine& m, std::string_view typed);

}  // namespace mtcal
