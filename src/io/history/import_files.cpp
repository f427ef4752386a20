#include "mtcal/io/history/import_files.hpp"

#include <initializer_list>
#include <sstream>

#include "mtcal/evaluation/iso230_2.hpp"
#include "mtcal/io/history/store.hpp"
#include "mtcal/io/instruments/iso230_files.hpp"
#include "mtcal/io/json/evaluation_json.hpp"
#include "mtcal/io/system/files.hpp"
#include "mtcal/io/system/sha256.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/util/request_error.hpp"

namespace mtcal {

std::string result_command(const Json& j) {
  auto has = [&](std::initializer_list<const char*> keys) {
    for (const char* k : keys)
      if (!j.contains(k)) return false;
    return true;
  };
  if (!j.is_object()) return "";
  if (has({"A", "E", "M", "R", "targets"})) return "iso230-2";
  if (has({"G_cw", "G_ccw"})) return "ballbar";
  if (has({"va", "critical_pair"})) return "volumetric";
  if (has({"parameters", "sigma0", "rank"})) return "identify";
  return "";
}

CalibrationRecord record_from_file(const std::string& path, const std::string& command,
                                   const std::map<std::string, std::string>& metadata) {
  const std::string text = read_text_file(path, "history import");
  const InputHash hash{path, sha256_hex(text)};
  const auto j = Json::parse(text, nullptr, false);
  CalibrationRecord r;
  if (!j.is_discarded()) {
    if (!j.is_object())
      throw InputError({path, 0, ""}, "expected a result JSON object, found " + std::string(j.type_name()));
    const std::string which = command.empty() ? result_command(j) : command;
    if (which.empty())
      throw RequestError({path, 0, ""},
                         "cannot tell which command's result this is (expected the keys of iso230-2, ballbar, "
                         "volumetric or identify): give the command that made it",
                         {"command"});
    r = record_from_result(which, text, metadata, {hash}, path);
  } else {
    const PositioningRuns runs = read_positioning_file(path, "auto", "mm", "");
    Json result = to_json(evaluate_positioning(runs));
    Json m = Json::object();
    for (const auto& [k, v] : runs.metadata) m[k] = v;
    result["metadata"] = m;
    r = record_from_result("iso230-2", json_text(result), metadata, {hash}, path);
  }
  if (r.machine_name.empty())
    throw RequestError({path, 0, "machine"}, "the result names no machine: give the machine in the metadata",
                       {"machine"});
  return r;
}

HistoryImport import_files(HistoryStore& store, const std::vector<std::string>& files, const std::string& command,
                           const std::map<std::string, std::string>& metadata) {
  HistoryImport r;
  std::vector<std::string> jsonl;
  for (const auto& path : files) {
    if (path.size() > 6 && path.compare(path.size() - 6, 6, ".jsonl") == 0) {
      jsonl.push_back(path);
      continue;
    }
    r.records.push_back(record_from_file(path, command, metadata));
    r.origin.push_back(path);
  }
  std::size_t jsonl_records = 0;
  for (const auto& path : jsonl) {
    // Read through the formats layer like every other input (its size limit and messages).
    std::istringstream in(read_text_file(path, "history import"));
    const auto s = import_jsonl(store, in, path);
    jsonl_records += s.records;
    r.events += s.events;
    r.model_files += s.model_files;
    for (const auto& k : s.skipped) r.skipped.push_back(path + ": " + k);
  }
  r.ids = store.record_all(r.records, {}, &r.duplicates);
  for (const auto i : r.duplicates)
    r.skipped.push_back(r.origin[i] + ": duplicate of record " + r.ids[i] + " (same content hash)");
  r.added = r.records.size() - r.duplicates.size() + jsonl_records;
  return r;
}

Json to_json(const HistoryImport& r, const std::string& store) {
  Json j;
  j["store"] = store;
  j["records_added"] = r.added;
  j["events_added"] = r.events;
  j["model_files_added"] = r.model_files;
  j["skipped"] = r.skipped;
  Json list = Json::array();
  for (std::size_t i = 0; i < r.records.size(); ++i) list.push_back({{"file", r.origin[i]}, {"id", r.ids[i]}});
  j["records"] = list;
  return j;
}

std::optional<ModelFile> read_model_file(const std::string& kind, const std::string& path) {
  if (kind != "machine" && kind != "parameters" && kind != "measurements")
    throw Error("read_model_file: kind '" + kind + "' is not 'machine', 'parameters' or 'measurements'");
  std::string text = read_text_file(path, kind == "machine"      ? "machine file"
                                          : kind == "parameters" ? "parameter file"
                                                                 : "measurement file");
  if (!is_utf8(text)) return std::nullopt;
  std::string sha = sha256_hex(text);
  return ModelFile{std::move(sha), kind, std::move(text)};
}

}  // namespace mtcal
