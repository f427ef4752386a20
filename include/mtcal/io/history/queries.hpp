// What history diff, trend and rank ask of a store: a machine's records, its trends with tolerances, the fleet ranked.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "mtcal/history/analysis.hpp"
#include "mtcal/io/history/store.hpp"
#include "mtcal/io/json/json.hpp"

namespace mtcal {

struct ToleranceFile;  // io/instruments/acceptance_files.hpp

// A tolerance of a recorded quantity: "Q=V" (|value| <= V for a parameter, value <= V for a
// figure) or "Q=LO:HI", in the quantity's recorded unit.
struct HistoryTolerance {
  std::string quantity;
  std::optional<double> limit;         // Q=V
  std::optional<ToleranceBand> range;  // Q=LO:HI
  ToleranceBand band(bool figure) const {
    if (range) return *range;
    return figure ? ToleranceBand::at_most(*limit) : ToleranceBand::symmetric(*limit);
  }
};

// "Q=V" / "Q=LO:HI" texts. Throws InputError located at `where` (field: the quantity) for text
// of another form, a value that is not a number, V <= 0, a band with LO > HI, a quantity given twice.
std::vector<HistoryTolerance> parse_history_tolerances(const std::vector<std::string>& specs,
                                                       const std::string& where = "tolerances");

// One record as `mtcal history show --json` prints it: the fields of its export line (without
// "type" and the result's text) and the result as JSON under "result".
Json record_json(const CalibrationRecord& r);

// The records of one machine in time order; InputError naming the store's machines when it has none.
std::vector<CalibrationRecord> machine_records(HistoryStore& store, const std::string& machine);

// What `mtcal history trend` asks for (docs/history.md).
struct TrendRequest {
  std::string machine;
  std::vector<std::string> parameters, figures;  // neither: every parameter and figure the records have
  std::vector<HistoryTolerance> tolerances;      // each must name one of the quantities
  std::string tolerance_file;                    // acceptance tolerances (docs/reports.md) of the figures, µm
  std::string from, to;                          // ISO 8601; a date as `to` includes its whole day
  // Where errors are located: the tolerances, the period's ends (the command passes its options).
  std::string tolerance_source = "tolerances", from_source = "from", to_source = "to";
};
// The machine's trends: one per quantity, with its band (a tolerance of the request, else the
// file's limit converted from µm into the recorded unit), and its events. records: the
// machine's records (machine_records).
MachineTrends machine_trends(HistoryStore& store, const TrendRequest& request,
                             const std::vector<CalibrationRecord>& records);

// What `mtcal history rank` asks for: tolerances (given or from a file; at least one).
struct RankRequest {
  std::vector<HistoryTolerance> tolerances;
  std::string tolerance_file;
  RankOptions options;
  std::string tolerance_source = "tolerances";
};
struct StoreRanking {
  FleetRanking ranking;
  std::vector<std::string> not_ranked;  // machines of the store without a quantity that has a tolerance
};
// Every machine's series of the quantities with a tolerance, ranked (rank_fleet). Throws
// InputError for no tolerances, a tolerance of a quantity no machine has, or no series at all.
StoreRanking rank_store(HistoryStore& store, const RankRequest& request);

// rank_store kept up to date between calls (mtcal serve's fleet page): each call reads the
// machines' revisions (HistoryStore::machine_revisions) first, returns the last ranking when none
// changed, and otherwise reads and fits again only the series of the machines whose revision
// changed, ranking the kept fits with the new ones (rank_fitted): the same ranking as
// rank_store's. One object is not meant to be shared between threads without a lock.
class FleetRanker {
 public:
  // Reads the tolerance file (InputError as rank_store). lenient: what rank_store refuses is
  // left out instead: a tolerance of a quantity no machine has yet (silently), a series whose
  // unit is not the tolerance file's length or whose samples cannot be fitted (said in notes),
  // no series at all (no machines ranked). Not lenient: rank_store's errors.
  FleetRanker(RankRequest request, bool lenient);
  struct Ranking {
    FleetRanking ranking;
    std::vector<std::string> notes;  // lenient: the series left out and why
    std::size_t fitted = 0;          // series read and fitted for this ranking (the rest kept)
    // The rankings this object returned, counted from 1; `changed`: the machines (sorted) whose
    // entry may differ from the one in ranking `serial - 1` apart from its rank number: a
    // series of theirs fitted again, one added or one left out (every machine when serial is 1).
    // The others' entries are made from the same fits, so equal but for `rank` (mtcal serve
    // makes their JSON again only where the rank moved).
    std::uint64_t serial = 0;
    std::vector<std::string> changed;
  };
  // The ranking of the store now: the same object as the last call's while no machine's revision changed.
  std::shared_ptr<const Ranking> rank(HistoryStore& store);

 private:
  struct Entry;
  RankRequest request_;
  bool lenient_;
  std::shared_ptr<const ToleranceFile> file_;  // read once
  std::vector<MachineRevision> revisions_;
  std::shared_ptr<const Ranking> last_;
  std::uint64_t serial_ = 0;
  std::map<std::pair<std::string, std::string>, std::shared_ptr<const Entry>> entries_;  // (machine, quantity)
};

}  // namespace mtcal
