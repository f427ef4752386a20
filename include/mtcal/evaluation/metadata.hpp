// Who tested what, where, when and with which instrument: the header of an acceptance report.
#pragma once

#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace mtcal {

// One field an acceptance report may carry: its key (as typed in --meta key=value or a metadata
// file) and the label a report shows.
struct MetadataField {
  std::string_view key, label;
};

// The known fields in the order a report lists them. What ISO 230-2:2014 clause 7 (test report)
// and ISO 230-4:2005 clause 6 (recording conditions) ask a report to state, and what a service
// engineer's certificate carries (instrument and its calibration).
const std::vector<MetadataField>& metadata_fields();

// Test metadata: text values by key, kept in metadata_fields() order. Values are text because
// they are shown, not computed with (a temperature may read "20.1 °C air, 20.4 °C machine").
// Hook for instrument files: a reader that knows the machine, serial, date or temperatures (a
// laser file's header) fills a ReportMetadata and the CLI merges it with fill_missing_from(), so
// what the user typed wins.
class ReportMetadata {
 public:
  // Throws InputError located at `where` (a file, line, or option) for an unknown key or an
  // empty value.
  void set(const std::string& key, const std::string& value, const std::string& where = "metadata", int line = 0);
  // The value, or nullptr when not given.
  const std::string* get(std::string_view key) const;
  // Adds the fields of other that this one lacks.
  void fill_missing_from(const ReportMetadata& other);
  bool empty() const { return values_.empty(); }
  // (key, value) in metadata_fields() order.
  const std::vector<std::pair<std::string, std::string>>& entries() const { return values_; }
  // Some temperature field (temperature, temperature_air, _machine, _material) is given.
  bool has_temperature() const;

 private:
  std::vector<std::pair<std::string, std::string>> values_;
};

// The label of a known key ("serial" -> "Serial number"); the key itself when unknown.
std::string_view metadata_label(std::string_view key);

// Which test a report is for, to know which fields acceptance asks for.
enum class AcceptanceTest { None, Iso230_2, Iso230_4, Volumetric };

// The fields an acceptance report of this test should state and that m lacks, as sentences
// ("no test date (date)"). Empty for AcceptanceTest::None.
std::vector<std::string> missing_acceptance_fields(const ReportMetadata& m, AcceptanceTest test);

// Process-wide metadata of this run (set once by the program after reading its options); every
// Report made afterwards shows it. Default: empty.
void set_session_metadata(ReportMetadata m);
const ReportMetadata& session_metadata();

}  // namespace mtcal
