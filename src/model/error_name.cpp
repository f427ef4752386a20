#include "mtcal/model/error_name.hpp"

namespace mtcal {

char letter_of(Component c) { return "XYZABC"[index_of(c)]; }

std::optional<Component> component_from_letter(char letter) {
  switch (letter) {
    case 'X': return Component::X;
    case 'Y': return Component::Y;
    case 'Z': return Component::Z;
    case 'A': return Component::A;
    case 'B': return Component::B;
    case 'C': return Component::C;
    default: return std::nullopt;
  }
}

std::string_view to_string(ErrorKind k) {
  switch (k) {
    case ErrorKind::Motion: return "motion";
    case ErrorKind::Location: return "location";
    case ErrorKind::Mounting: return "mounting";
  }
  return "?";
}

std::string ErrorName::str() const {
  std::string s = "E";
  s += letter_of(component);
  if (kind == ErrorKind::Location) s += '0';
  s += body;
  return s;
}

std::optional<ErrorName> ErrorName::parse(std::string_view s) {
  if (s.size() < 3 || s.size() > 4 || s[0] != 'E') return std::nullopt;
  auto comp = component_from_letter(s[1]);
  if (!comp) return std::nullopt;
  ErrorName n;
  n.component = *comp;
  if (s.size() == 4) {
    if (s[2] != '0' || !component_from_letter(s[3])) return std::nullopt;
    n.kind = ErrorKind::Location;
    n.body = s[3];
    return n;
  }
  if (s[2] == 't' || s[2] == 'w') {
    n.kind = ErrorKind::Mounting;
    n.body = s[2];
    return n;
  }
  if (!component_from_letter(s[2])) return std::nullopt;
  n.kind = ErrorKind::Motion;
  n.body = s[2];
  return n;
}

}  // namespace mtcal
