// JSON lines of the history store (export, import) and records built from a command's result JSON.
#include <cmath>
#include <istream>
#include <ostream>
#include <set>

#include <nlohmann/json.hpp>

#include "internal.hpp"
#include "mtcal/io/json/json.hpp"

namespace mtcal {

namespace {

using nlohmann::ordered_json;

ordered_json optional_number(const std::optional<double>& v) { return v ? ordered_json(*v) : ordered_json(nullptr); }

ordered_json record_json(const CalibrationRecord& r) {
  ordered_json j;
  j["type"] = "record";
  j["id"] = r.id;
  j["machine_name"] = r.machine_name;
  j["machine_serial"] = r.machine_serial;
  j["command"] = r.command;
  j["recorded_at"] = r.recorded_at;
  j["measured_at"] = r.measured_at;
  j["metadata"] = ordered_json::object();
  for (const auto& [k, v] : r.metadata) j["metadata"][k] = v;
  j["inputs"] = ordered_json::array();
  for (const auto& i : r.inputs) j["inputs"].push_back({{"path", i.path}, {"sha256", i.sha256}});
  j["parameters"] = ordered_json::array();
  for (const auto& p : r.parameters)
    j["parameters"].push_back(
        {{"name", p.name}, {"value", p.value}, {"uncertainty", optional_number(p.uncertainty)}, {"unit", p.unit}});
  j["figures"] = ordered_json::array();
  for (const auto& f : r.figures)
    j["figures"].push_back(
        {{"name", f.name}, {"value", f.value}, {"uncertainty", optional_number(f.uncertainty)}, {"unit", f.unit}});
  j["result_json"] = r.result_json;
  j["content_hash"] = r.content_hash;
  // Only where known (schema version 6): older exports and records without it read the same.
  if (!r.invocation.empty()) j["invocation"] = r.invocation;
  return j;
}

ordered_json event_json(const Event& e) {
  ordered_json j;
  j["type"] = "event";
  j["id"] = e.id;
  j["machine"] = e.machine;
  j["date"] = e.date;
  j["kind"] = std::string(to_string(e.kind));
  j["note"] = e.note;
  return j;
}

ordered_json model_file_json(const ModelFile& f) {
  ordered_json j;
  j["type"] = "model_file";
  j["sha256"] = f.sha256;
  j["kind"] = f.kind;
  j["content"] = f.content;
  return j;
}

// Strict field access of one JSON line: every key expected, of its type, and no other.
class Fields {
 public:
  Fields(const ordered_json& j, const std::string& source, int line, std::set<std::string> keys)
      : j_(j), source_(source), line_(line) {
    for (const auto& [k, v] : j.items())
      if (!keys.count(k)) fail(k, "unexpected key '" + printable(k) + "'");
    for (const auto& k : keys)
      if (!j.contains(k)) fail(k, "expected the key '" + k + "', found none");
  }
  std::string text(const std::string& key) const { return text_of(j_.at(key), key); }
  std::string text_of(const ordered_json& v, const std::string& key) const {
    if (!v.is_string()) fail(key, "expected text, found " + std::string(v.type_name()));
    return v.get<std::string>();
  }
  double number(const ordered_json& v, const std::string& key) const {
    if (!v.is_number()) fail(key, "expected a number, found " + std::string(v.type_name()));
    return v.get<double>();
  }
  std::optional<double> optional(const ordered_json& v, const std::string& key) const {
    if (v.is_null()) return std::nullopt;
    return number(v, key);
  }
  const ordered_json& array(const std::string& key) const {
    if (!j_.at(key).is_array()) fail(key, "expected an array, found " + std::string(j_.at(key).type_name()));
    return j_.at(key);
  }
  const ordered_json& object(const ordered_json& v, const std::string& key) const {
    if (!v.is_object()) fail(key, "expected an object, found " + std::string(v.type_name()));
    return v;
  }
  [[noreturn]] void fail(const std::string& field, const std::string& what) const {
    throw InputError({source_, line_, field}, what);
  }

 private:
  const ordered_json& j_;
  const std::string& source_;
  int line_;
};

CalibrationRecord parse_record(const ordered_json& j, const std::string& source, int line) {
  // "invocation" is optional (exports of schema version 6 have it where the record has one).
  std::set<std::string> keys{"type",       "id",     "machine_name", "machine_serial", "command",
                             "recorded_at", "measured_at", "metadata", "inputs",         "parameters",
                             "figures",    "result_json", "content_hash"};
  if (j.contains("invocation")) keys.insert("invocation");
  const Fields f(j, source, line, std::move(keys));
  CalibrationRecord r;
  r.id = f.text("id");
  r.machine_name = f.text("machine_name");
  r.machine_serial = f.text("machine_serial");
  r.command = f.text("command");
  r.recorded_at = f.text("recorded_at");
  r.measured_at = f.text("measured_at");
  for (const auto& [k, v] : f.object(j.at("metadata"), "metadata").items())
    r.metadata[k] = f.text_of(v, "metadata." + k);
  for (const auto& i : f.array("inputs")) {
    const Fields fi(f.object(i, "inputs"), source, line, {"path", "sha256"});
    r.inputs.push_back({fi.text("path"), fi.text("sha256")});
  }
  for (const char* key : {"parameters", "figures"})
    for (const auto& p : f.array(key)) {
      const Fields fp(f.object(p, key), source, line, {"name", "value", "uncertainty", "unit"});
      const std::string k = key;
      if (k == "parameters")
        r.parameters.push_back({fp.text("name"), fp.number(p.at("value"), "value"),
                                fp.optional(p.at("uncertainty"), "uncertainty"), fp.text("unit")});
      else
        r.figures.push_back({fp.text("name"), fp.number(p.at("value"), "value"), fp.text("unit"),
                             fp.optional(p.at("uncertainty"), "uncertainty")});
    }
  r.result_json = f.text("result_json");
  r.content_hash = f.text("content_hash");
  if (j.contains("invocation")) r.invocation = f.text("invocation");
  if (r.id.empty()) f.fail("id", "expected the record's id, found an empty one");
  if (r.recorded_at.empty()) f.fail("recorded_at", "expected the time it was recorded, found none");
  try {
    history_detail::check_record(r);
  } catch (const InputError& e) {
    f.fail(e.where().field, e.what());
  }
  if (r.measured_at.empty()) f.fail("measured_at", "expected the time it was measured, found none");
  if (history_detail::content_hash(r) != r.content_hash)
    f.fail("content_hash", "expected " + history_detail::content_hash(r) +
                               " (the SHA-256 of the record's content), found '" + printable(r.content_hash) +
                               "': the line was changed after it was exported");
  return r;
}

Event parse_event(const ordered_json& j, const std::string& source, int line) {
  const Fields f(j, source, line, {"type", "id", "machine", "date", "kind", "note"});
  Event e;
  e.id = f.text("id");
  e.machine = f.text("machine");
  e.date = f.text("date");
  const std::string kind = f.text("kind");
  const auto k = parse_event_kind(kind);
  if (!k) f.fail("kind", "expected compensation-loaded, crash, repair or other, found '" + printable(kind) + "'");
  e.kind = *k;
  e.note = f.text("note");
  if (e.id.empty()) f.fail("id", "expected the event's id, found an empty one");
  try {
    history_detail::check_event(e);
  } catch (const InputError& err) {
    f.fail(err.where().field, err.what());
  }
  return e;
}

ModelFile parse_model_file(const ordered_json& j, const std::string& source, int line) {
  const Fields f(j, source, line, {"type", "sha256", "kind", "content"});
  ModelFile m{f.text("sha256"), f.text("kind"), f.text("content")};
  try {
    history_detail::check_model_file(m, source);
  } catch (const InputError& e) {
    f.fail(e.where().field, e.what());
  }
  return m;
}

}  // namespace

std::string record_to_json_line(const CalibrationRecord& r) { return json_text(record_json(r)); }
std::string event_to_json_line(const Event& e) { return json_text(event_json(e)); }

void export_jsonl(HistoryStore& store, std::ostream& out) {
  for (const auto& r : store.list({})) out << json_text(record_json(r)) << '\n';
  for (const auto& e : store.events()) out << json_text(event_json(e)) << '\n';
  for (const auto& f : store.model_files()) out << json_text(model_file_json(f)) << '\n';
}

ImportSummary import_jsonl(HistoryStore& store, std::istream& in, const std::string& source) {
  std::vector<CalibrationRecord> records;
  std::vector<int> record_lines;
  std::vector<Event> events;
  std::vector<ModelFile> files;
  std::string text;
  int line = 0;
  while (std::getline(in, text)) {
    ++line;
    if (!text.empty() && text.back() == '\r') text.pop_back();
    if (text.find_first_not_of(" \t") == std::string::npos) continue;
    const auto j = ordered_json::parse(text, nullptr, false);
    if (j.is_discarded())
      throw InputError({source, line, ""}, "expected one JSON object per line, found text that is not JSON");
    if (!j.is_object())
      throw InputError({source, line, ""}, "expected a JSON object, found " + std::string(j.type_name()));
    if (!j.contains("type") || !j["type"].is_string())
      throw InputError({source, line, "type"},
                       "expected the key 'type' (\"record\", \"event\" or \"model_file\"), found none");
    const std::string type = j["type"].get<std::string>();
    if (type == "record") {
      records.push_back(parse_record(j, source, line));
      record_lines.push_back(line);
    } else if (type == "event") {
      events.push_back(parse_event(j, source, line));
    } else if (type == "model_file") {
      files.push_back(parse_model_file(j, source, line));
    } else {
      throw InputError({source, line, "type"},
                       "expected \"record\", \"event\" or \"model_file\", found '" + printable(type) + "'");
    }
  }
  if (in.bad()) throw InputError({source, line, ""}, "cannot read the file");
  ImportSummary summary;
  const std::size_t event_count = events.size();
  std::size_t known_events = 0;
  {
    std::set<std::string> existing;
    for (const auto& e : store.events()) existing.insert(e.id);
    for (const auto& e : events) known_events += existing.count(e.id);
  }
  std::size_t new_files = 0;
  {
    std::set<std::string> seen;
    for (const auto& f : files)
      if (seen.insert(f.sha256).second && !store.model_file(f.sha256)) ++new_files;
  }
  std::vector<std::size_t> skipped;
  const auto ids = store.record_all(records, std::move(events), &skipped, std::move(files));
  for (const auto i : skipped)
    summary.skipped.push_back("line " + std::to_string(record_lines[i]) + ": duplicate of record " + ids[i] +
                              " (content hash " + records[i].content_hash.substr(0, 12) + "…)");
  summary.records = records.size() - skipped.size();
  summary.events = event_count - known_events;
  summary.model_files = new_files;
  return summary;
}

// ---- records from result JSON -----------------------------------------------------------

namespace {

// Figures a command's result states at its top level: the keys of docs/history.md's table.
struct FigureKeys {
  const char* command;
  std::vector<const char*> keys;
  const char* unit = nullptr;  // the keys' unit where the result has no "unit" key (default mm)
};
const std::vector<FigureKeys>& figure_keys() {
  static const std::vector<FigureKeys> kKeys{
      // ISO 230-2:2014 clause 2: A, B, E, M, R (and per direction).
      {"iso230-2", {"A", "A_up", "A_down", "B", "E", "E_up", "E_down", "M", "R", "R_up", "R_down"}},
      // ISO 230-4:2005: circular deviation G per direction and bidirectional, hysteresis H, F.
      {"ballbar", {"G_cw", "G_ccw", "G_b", "H", "F_max", "F_min"}},
      {"volumetric", {"va", "va_x", "va_y", "va_z"}},
      // The tool point a controller reached (docs/campaign.md): max |e|, RMS |e|, VA over the poses.
      {"pose-check", {"max_um", "rms_um", "va_um"}, "um"},
  };
  return kKeys;
}

std::string unit_of(const ordered_json& j) {
  for (const char* k : {"unit", "units"})
    if (j.contains(k) && j[k].is_string()) return j[k].get<std::string>();
  return "";
}

std::optional<double> uncertainty_of(const ordered_json& v) {
  for (const char* k : {"u", "uncertainty", "std", "sigma"})
    if (v.contains(k) && v[k].is_number()) return v[k].get<double>();
  return std::nullopt;
}

// {"EC0Y": {"value": .., "u": .., "unit": ..}, ...} or [{"name": .., "value": ..}, ...]
void take_parameters(const ordered_json& j, std::vector<RecordedParameter>& out, const std::string& default_unit) {
  auto take = [&](const std::string& name, const ordered_json& v) {
    if (!v.is_object() || !v.contains("value") || !v["value"].is_number()) return;
    const double value = v["value"].get<double>();
    if (!std::isfinite(value)) return;
    auto u = uncertainty_of(v);
    if (u && !std::isfinite(*u)) u.reset();
    const std::string unit = v.contains("unit") && v["unit"].is_string() ? v["unit"].get<std::string>() : default_unit;
    out.push_back({name, value, u, unit});
  };
  if (j.is_object())
    for (const auto& [k, v] : j.items()) take(k, v);
  else if (j.is_array())
    for (const auto& v : j)
      if (v.is_object() && v.contains("name") && v["name"].is_string()) take(v["name"].get<std::string>(), v);
}

}  // namespace

CalibrationRecord record_from_result(const std::string& command, const std::string& result_json,
                                     const std::map<std::string, std::string>& metadata, std::vector<InputHash> inputs,
                                     const std::string& source) {
  const auto j = ordered_json::parse(result_json, nullptr, false);
  if (j.is_discarded())
    throw InputError({source, 0, ""}, "expected a command's JSON result, found text that is not JSON");
  if (!j.is_object())
    throw InputError({source, 0, ""},
                     "expected a command's JSON result (an object), found " + std::string(j.type_name()));
  CalibrationRecord r;
  r.command = command;
  // The result's own "metadata" (an instrument file's header, the user's --meta) under the
  // metadata given here, which wins.
  // Text that is not UTF-8 (a file name, a --meta value) is kept as the JSON output has it: with
  // U+FFFD for the bytes that are not (json_text; docs/reliability.md).
  if (j.contains("metadata") && j["metadata"].is_object())
    for (const auto& [k, v] : j["metadata"].items())
      if (v.is_string()) r.metadata[k] = v.get<std::string>();
  for (const auto& [k, v] : metadata) r.metadata[utf8_text(k)] = utf8_text(v);
  r.inputs = std::move(inputs);
  for (auto& i : r.inputs) i.path = utf8_text(i.path);
  r.result_json = json_text(j);
  if (const auto it = r.metadata.find("machine"); it != r.metadata.end())
    r.machine_name = it->second;
  else if (j.contains("machine") && j["machine"].is_string())
    r.machine_name = j["machine"].get<std::string>();
  if (const auto it = r.metadata.find("serial"); it != r.metadata.end()) r.machine_serial = it->second;
  if (const auto it = r.metadata.find("date"); it != r.metadata.end()) {
    if (!is_iso8601(it->second))
      throw InputError({source, 0, "metadata date"},
                       "expected the test date as ISO 8601 (2026-11-25 or "
                       "2026-11-25T10:30:00Z) to place the result in time, found '" +
                           printable(it->second) + "'");
    r.measured_at = it->second;
  }
  const std::string unit = unit_of(j);
  for (const char* key : {"parameters", "diagnostics", "estimates"})
    if (j.contains(key)) take_parameters(j[key], r.parameters, unit);
  // The axis an ISO 230-2 figure belongs to: metadata "axis", so that A of X and of Y differ ("A_X").
  std::string suffix;
  if (const auto it = r.metadata.find("axis"); it != r.metadata.end()) suffix = "_" + it->second;
  for (const auto& fk : figure_keys()) {
    if (command != fk.command) continue;
    for (const char* key : fk.keys)
      if (j.contains(key) && j[key].is_number() && std::isfinite(j[key].get<double>()))
        r.figures.push_back(
            {std::string(key) + suffix, j[key].get<double>(), !unit.empty() ? unit : fk.unit ? fk.unit : "mm",
             std::nullopt});
  }
  return r;
}

}  // namespace mtcal
