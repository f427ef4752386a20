#include "mtcal/io/json/toolpath_json.hpp"

#include "mtcal/io/text/error_keys.hpp"

namespace mtcal {

Json to_json(const Machine& m, const ToolpathSummary& s) {
  Json j;
  j["points"] = s.points;
  j["blocks"] = s.blocks;
  j["path_length"] = s.path_length;
  j["ignored_words"] = s.counts.ignored_words;
  j["words"] = {{"m", s.counts.m_words},     {"s", s.counts.s_words},
                {"t", s.counts.t_words},     {"tool_changes", s.counts.tool_changes},
                {"cycles", s.counts.cycles}, {"warnings", s.counts.warnings}};
  j["rapids_skipped"] = s.rapids_skipped;
  const Json at = s.max_at.empty() ? Json::object() : joint_json(m, s.max_at);
  j["max_error"] = {{"value", s.max_error}, {"line", s.points ? Json(s.max_line) : Json(nullptr)}, {"at", at}};
  Json range = Json::object();
  for (std::size_t c = 0; c < 6; ++c)
    range[kErrorKeys[c]] = s.points ? Json::array({s.range[c][0], s.range[c][1]}) : Json::array({nullptr, nullptr});
  j["range"] = range;
  return j;
}

}  // namespace mtcal
