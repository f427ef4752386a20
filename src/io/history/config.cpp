// The user's configuration file of the calibration history (history_config.hpp).
#include "mtcal/io/history/config.hpp"

#include <filesystem>

#include <yaml-cpp/yaml.h>

#include "mtcal/util/errors.hpp"

namespace mtcal {

std::optional<HistoryConfig> read_history_config(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return std::nullopt;
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    throw InputError({path, 0, ""}, "cannot read the configuration file");
  } catch (const YAML::Exception& e) {
    throw InputError({path, e.mark.line + 1, ""}, "expected YAML, found: " + e.msg);
  }
  HistoryConfig c;
  c.source = path;
  if (root.IsNull()) return c;
  if (!root.IsMap()) throw InputError({path, 1, ""}, "expected a mapping of sections (history: ...)");
  const YAML::Node h = root["history"];
  if (!h) return c;
  const int line = h.Mark().line + 1;
  if (!h.IsMap()) throw InputError({path, line, "history"}, "expected a mapping with store: and record:");
  for (const auto& kv : h) {
    const auto key = kv.first.as<std::string>();
    const int at = kv.second.Mark().line + 1;
    if (!kv.second.IsScalar()) throw InputError({path, at, "history." + key}, "expected a single value");
    const auto value = kv.second.as<std::string>();
    if (key == "store") {
      if (value.empty()) throw InputError({path, at, "history.store"}, "expected a SQLite file or a connection string");
      c.store = value;
    } else if (key == "record") {
      if (value != "always" && value != "on-request")
        throw InputError({path, at, "history.record"},
                         "expected always or on-request, found '" + printable(value) + "'");
      c.always = value == "always";
    } else {
      throw InputError({path, at, "history." + key}, "unknown key '" + printable(key) + "' (expected store, record)");
    }
  }
  return c;
}

}  // namespace mtcal
