// ISO 230-1 / ISO 230-7 names of geometric errors (EXX, EC0Y, EX0C ...) and mounting errors.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace mtcal {

// Direction of an error: translations along X, Y, Z or rotations A, B, C about them.
// The numeric value is the row of the error in a 6-vector (dx dy dz rx ry rz).
enum class Component : std::uint8_t { X = 0, Y = 1, Z = 2, A = 3, B = 4, C = 5 };

constexpr bool is_rotation(Component c) { return static_cast<int>(c) >= 3; }
constexpr int index_of(Component c) { return static_cast<int>(c); }
char letter_of(Component c);
std::optional<Component> component_from_letter(char letter);

enum class ErrorKind {
  Motion,    // E + direction + axis: function of the axis's own position (ISO 230-1 3.4)
  Location,  // E + direction + 0 + axis: position/orientation of the axis line, zero position
  Mounting,  // E + direction + t|w: set-up of tool (t) or workpiece (w), mtcal's own names
};

std::string_view to_string(ErrorKind k);

struct ErrorName {
  ErrorKind kind = ErrorKind::Motion;
  Component component = Component::X;
  char body = 'X';  // axis letter, or 't' / 'w' for mounting errors

  std::string str() const;
  // Parses "EXX", "EX0C", "EC0Y", "EXt", "EAw". nullopt for anything else.
  static std::optional<ErrorName> parse(std::string_view s);
  friend bool operator==(const ErrorName&, const ErrorName&) = default;
};

}  // namespace mtcal
