// Test metadata of acceptance reports (evaluation/metadata.hpp).
#include "mtcal/evaluation/metadata.hpp"

#include <algorithm>

#include "mtcal/util/errors.hpp"

namespace mtcal {

const std::vector<MetadataField>& metadata_fields() {
  // ISO 230-2:2014 clause 7 asks for the machine, the axis and its position, the date, the
  // temperatures (air, machine, material nominal expansion), the instrument and the feed and
  // dwell; ISO 230-4:2005 clause 6 for the radius, feed, direction, start position, data capture,
  // compensation, position of the centre and temperature.
  static const std::vector<MetadataField> fields = {
      {"machine", "Machine"},
      {"serial", "Serial number"},
      {"owner", "Owner"},
      {"location", "Location"},
      {"operator", "Operator"},
      {"date", "Test date"},
      {"axis", "Axis tested"},
      {"temperature", "Temperature"},
      {"temperature_air", "Air temperature"},
      {"temperature_machine", "Machine temperature"},
      {"temperature_material", "Material temperature"},
      {"humidity", "Humidity"},
      {"instrument", "Instrument"},
      {"instrument_serial", "Instrument serial number"},
      {"calibration_certificate", "Calibration certificate"},
      {"calibration_date", "Calibration date"},
      {"feed", "Feed"},
      {"dwell", "Dwell"},
      {"direction", "Direction"},
      {"start", "Start position"},
      {"data_capture", "Data capture"},
      {"compensation", "Compensation"},
      {"centre", "Position of the centre"},
      {"conditions", "Test conditions"},
      {"notes", "Notes"},
  };
  return fields;
}

std::string_view metadata_label(std::string_view key) {
  for (const auto& f : metadata_fields())
    if (f.key == key) return f.label;
  return key;
}

void ReportMetadata::set(const std::string& key, const std::string& value, const std::string& where, int line) {
  const auto& fields = metadata_fields();
  const auto it = std::find_if(fields.begin(), fields.end(), [&](const MetadataField& f) { return f.key == key; });
  if (it == fields.end()) {
    std::string list;
    for (const auto& f : fields) list += (list.empty() ? "" : ", ") + std::string(f.key);
    throw InputError({where, line, key},
                     "unknown metadata field '" + printable(key) + "' (expected one of: " + list + ")");
  }
  if (value.find_first_not_of(" \t") == std::string::npos)
    throw InputError({where, line, key}, "expected a value for metadata field '" + key + "', found nothing");
  const auto rank = [&](const std::string& k) {
    return std::find_if(fields.begin(), fields.end(), [&](const MetadataField& f) { return f.key == k; }) -
           fields.begin();
  };
  for (auto& kv : values_)
    if (kv.first == key) {
      kv.second = value;
      return;
    }
  const auto pos =
      std::find_if(values_.begin(), values_.end(), [&](const auto& kv) { return rank(kv.first) > rank(key); });
  values_.insert(pos, {key, value});
}

const std::string* ReportMetadata::get(std::string_view key) const {
  for (const auto& kv : values_)
    if (kv.first == key) return &kv.second;
  return nullptr;
}

void ReportMetadata::fill_missing_from(const ReportMetadata& other) {
  for (const auto& [k, v] : other.values_)
    if (!get(k)) set(k, v);
}

bool ReportMetadata::has_temperature() const {
  return get("temperature") || get("temperature_air") || get("temperature_machine") || get("temperature_material");
}

std::vector<std::string> missing_acceptance_fields(const ReportMetadata& m, AcceptanceTest test) {
  std::vector<std::string> out;
  if (test == AcceptanceTest::None) return out;
  if (!m.get("date")) out.emplace_back("no test date (date)");
  // A volumetric study names its machine through the machine file.
  if (test != AcceptanceTest::Volumetric && !m.get("machine")) out.emplace_back("no machine (machine)");
  if (!m.has_temperature()) out.emplace_back("no temperature (temperature, temperature_air, temperature_machine)");
  if (test == AcceptanceTest::Iso230_2) {
    // ISO 230-2:2014 clause 7: feed and dwell at each target are part of the test conditions.
    if (!m.get("feed")) out.emplace_back("no feed (feed)");
    if (!m.get("dwell")) out.emplace_back("no dwell time at the targets (dwell)");
  }
  if (test == AcceptanceTest::Iso230_4) {
    // ISO 230-4:2005 clause 6 lists the recording conditions; radius and direction come from
    // the command and the trace.
    if (!m.get("feed")) out.emplace_back("no feed (feed)");
    if (!m.get("start")) out.emplace_back("no start position (start)");
    if (!m.get("data_capture")) out.emplace_back("no data capture method (data_capture)");
    if (!m.get("compensation")) out.emplace_back("no statement whether compensation was on (compensation)");
    if (!m.get("centre")) out.emplace_back("no position of the centre (centre)");
  }
  return out;
}

namespace {
ReportMetadata& session() {
  static ReportMetadata m;
  return m;
}
}  // namespace

void set_session_metadata(ReportMetadata m) { session() = std::move(m); }
const ReportMetadata& session_metadata() { return session(); }

}  // namespace mtcal
