#include "mtcal/io/json/json.hpp"

#include <string>

#include "mtcal/model/joints.hpp"

namespace mtcal {

std::string json_text(const Json& j, int indent) {
  return j.dump(indent, ' ', false, Json::error_handler_t::replace);
}

std::string json_text(const nlohmann::json& j, int indent) {
  return j.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
}

std::string utf8_text(std::string_view text) {
  if (is_utf8(text)) return std::string(text);
  // The serializer's own replacement, read back: the same U+FFFD wherever json_text puts one.
  return nlohmann::json::parse(json_text(nlohmann::json(std::string(text)))).get<std::string>();
}

bool is_utf8(std::string_view text) {
  // RFC 3629, section 4: the lead byte gives the length; the second byte's range excludes
  // overlong forms, surrogates (U+D800..U+DFFF) and code points above U+10FFFF.
  std::size_t i = 0;
  while (i < text.size()) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c < 0x80) {
      ++i;
      continue;
    }
    std::size_t n = 0;  // continuation bytes
    unsigned lo = 0x80, hi = 0xBF;
    if (c >= 0xC2 && c <= 0xDF) {
      n = 1;
    } else if (c >= 0xE0 && c <= 0xEF) {
      n = 2;
      if (c == 0xE0) lo = 0xA0;
      if (c == 0xED) hi = 0x9F;
    } else if (c >= 0xF0 && c <= 0xF4) {
      n = 3;
      if (c == 0xF0) lo = 0x90;
      if (c == 0xF4) hi = 0x8F;
    } else {
      return false;
    }
    if (i + n >= text.size()) return false;
    for (std::size_t k = 1; k <= n; ++k) {
      const auto b = static_cast<unsigned char>(text[i + k]);
      if (b < (k == 1 ? lo : 0x80u) || b > (k == 1 ? hi : 0xBFu)) return false;
    }
    i += n + 1;
  }
  return true;
}

Json joint_json(const Machine& m, std::span<const double> q) {
  Json j = Json::object();
  for (std::size_t k = 0; k < m.axes.size(); ++k) j[std::string(1, m.axes[k].letter)] = to_user_units(m.axes[k], q[k]);
  return j;
}

}  // namespace mtcal
