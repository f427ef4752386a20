// The user's configuration file of the calibration history: the default store and when to record.
#pragma once

#include <optional>
#include <string>

namespace mtcal {

struct HistoryConfig {
  std::string store;    // history.store: a SQLite file or a PostgreSQL connection string
  bool always = false;  // history.record: "always" records every result; "on-request" (default) only with --record
  std::string source;   // the file it came from
};

// Reads
//   history:
//     store: /srv/mtcal/history.db     # or postgresql://mtcal@db.example/shop
//     record: on-request               # or always
// nullopt when the file does not exist; InputError (file, line, field) for anything else wrong.
// Keys other than history are left to other readers.
std::optional<HistoryConfig> read_history_config(const std::string& path);

}  // namespace mtcal
