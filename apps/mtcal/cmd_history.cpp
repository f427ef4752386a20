// mtcal history list|show|import|export|event add, and --record on the result commands.
#include <algorithm>
#include <cstdlib>
#include <iostream>
#include <sstream>

#include <fmt/format.h>

#include "acceptance.hpp"
#include "history.hpp"
#include "mtcal/evaluation/metadata.hpp"
#include "mtcal/io/json/history_json.hpp"
#include "mtcal/io/system/files.hpp"
#include "mtcal/io/history/config.hpp"
#include "mtcal/io/history/import_files.hpp"
#include "mtcal/io/history/queries.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal::cli {

namespace {

struct RecordState {
  bool refused = false;
  CLI::Option* option = nullptr;
  std::string store;  // --record's value; empty: the default store
  std::optional<Json> result;
  std::vector<std::string> inputs;
  std::vector<std::pair<std::string, std::string>> model_files;  // kind, path
  std::string measurements;                                      // the report's measurement file
  std::optional<Json> invocation;
  std::string machine;
  std::unique_ptr<HistoryStore> open;
  std::string open_name;
};

RecordState& state() {
  static RecordState s;
  return s;
}

bool asked() { return state().option && state().option->count() > 0; }

std::string env(const char* name) {
  const char* v = std::getenv(name);
  return v ? v : "";
}

std::optional<HistoryConfig> config() {
  static const std::optional<HistoryConfig> c = read_history_config(config_path());
  return c;
}

// A value of --record that is no store: most likely the command's input, taken by --record
// because it came right after it.
bool looks_like_store(const std::string& s) {
  for (const char* prefix : {"sqlite:", "postgresql:", "postgres://"})
    if (s.rfind(prefix, 0) == 0) return true;
  for (const char* ext : {".db", ".sqlite", ".sqlite3"})
    if (s.size() > std::string(ext).size() &&
        s.compare(s.size() - std::string(ext).size(), std::string::npos, ext) == 0)
      return true;
  return false;
}

}  // namespace

std::string config_path() {
  if (const auto p = env("MTCAL_CONFIG"); !p.empty()) return p;
  if (const auto x = env("XDG_CONFIG_HOME"); !x.empty()) return x + "/mtcal/config.yaml";
  if (const auto h = env("HOME"); !h.empty()) return h + "/.config/mtcal/config.yaml";
  return "";
}

void add_record_options(CLI::App& app) {
  state().option =
      app.add_option("--record", state().store,
                     "Record the command's result in the calibration history (docs/history.md): in STORE (a SQLite "
                     "file *.db, sqlite:PATH or postgresql://...; write --record=STORE) or, without a value, in the "
                     "default store ($MTCAL_HISTORY, or history.store in ~/.config/mtcal/config.yaml)")
          ->expected(0, 1);
  app.add_flag("--no-record", state().refused,
               "Do not record this result, even where the configuration says history.record: always");
}

bool recording() {
  auto& s = state();
  if (s.refused) return false;
  if (asked()) return true;
  return config() && config()->always;
}

bool emit_json(Json j, bool json_out) {
  if (json_out) {
    print_json(j);  // adds the user's metadata
  }
  state().result = std::move(j);
  return json_out;
}

void note_inputs(const std::vector<std::string>& inputs) {
  for (const auto& i : inputs)
    if (!i.empty() && i != "-") state().inputs.push_back(i);
}

void note_model_files(const std::string& machine, const std::vector<std::string>& params) {
  auto& files = state().model_files;
  if (!machine.empty() && machine != "-") files.emplace_back("machine", machine);
  for (const auto& p : params)
    if (!p.empty() && p != "-") files.emplace_back("parameters", p);
}

void note_report_source(const std::string& measurements, Json invocation) {
  if (measurements.empty() || measurements == "-") return;  // standard input: nothing to keep
  state().measurements = measurements;
  state().invocation = std::move(invocation);
}

void note_machine(const std::string& name) {
  if (state().machine.empty()) state().machine = name;
}

std::unique_ptr<HistoryStore> open_cli_store(const std::string& given) {
  std::string where = given;
  if (where.empty()) where = env("MTCAL_HISTORY");
  if (where.empty() && config()) where = config()->store;
  if (where.empty())
    throw InputError({"--store", 0, ""},
                     "no history store given: name one (--store FILE.db or postgresql://...), or set MTCAL_HISTORY, "
                     "or history.store in " +
                         (config_path().empty() ? std::string("~/.config/mtcal/config.yaml") : config_path()));
  return open_history_store(where);
}

void prepare_recording() {
  auto& s = state();
  if (!recording()) return;
  if (!s.store.empty() && !looks_like_store(s.store))
    throw InputError({"--record", 0, s.store},
                     "expected a store (a *.db file, sqlite:PATH or postgresql://...), found '" + printable(s.store) +
                         "'; write --record=STORE, or put --record after the command's inputs");
  if (const std::string* date = session_metadata().get("date"); date && !is_iso8601(*date))
    throw InputError({"--meta", 0, "date"},
                     "expected the test date as ISO 8601 (2026-11-25 or 2026-11-25T10:30:00Z) "
                     "to place the recorded result in time, found '" +
                         printable(*date) + "'");
  s.open = open_cli_store(s.store);
}

std::optional<std::string> record_result(const std::string& command) {
  auto& s = state();
  if (!recording()) return std::nullopt;
  if (!s.result) {
    if (!asked()) return std::nullopt;  // history.record: always, and a command without a result
    throw InputError({"--record", 0, ""}, "'" + command +
                                              "' produces no calibration result to record (see "
                                              "docs/history.md for the commands that do)");
  }
  std::map<std::string, std::string> meta;
  for (const auto& [k, v] : session_metadata().entries()) meta[k] = v;
  std::vector<InputHash> inputs;
  for (const auto& path : s.inputs) inputs.push_back({path, sha256_file(path)});
  CalibrationRecord r = record_from_result(command, json_text(*s.result), meta, std::move(inputs), command);
  if (r.machine_name.empty()) r.machine_name = utf8_text(s.machine);
  if (r.machine_name.empty())
    throw InputError({"--meta", 0, "machine"},
                     "the result names no machine to record it under: give --meta machine=NAME (and serial=...)");
  // The model's files, so that the record's model can be made again (docs/history.md, "Model
  // files"); a file that is not UTF-8 text cannot be kept.
  std::vector<ModelFile> files;
  for (const auto& [kind, path] : s.model_files) {
    auto file = read_model_file(kind, path);
    if (!file) {
      warn("the " + std::string(kind == "machine" ? "machine file" : "parameter file") + " '" + printable(path) +
           "' is not UTF-8 text: it is not kept in the history store with the record");
      continue;
    }
    files.push_back(std::move(*file));
  }
  // The measurements and options its report is made from again (docs/history.md, "Measurement
  // files"); without them (not UTF-8 text) the record holds no invocation.
  if (!s.measurements.empty() && s.invocation) {
    if (auto file = read_model_file("measurements", s.measurements)) {
      files.push_back(std::move(*file));
      r.invocation = json_text(*s.invocation);
    } else {
      warn("the measurement file '" + printable(s.measurements) +
           "' is not UTF-8 text: it is not kept in the history store, and the record's report cannot be made from it");
    }
  }
  if (!s.open) s.open = open_cli_store(s.store);
  std::vector<std::size_t> skipped;
  const auto ids = s.open->record_all({r}, {}, &skipped, std::move(files));
  if (!skipped.empty()) {
    std::cerr << "mtcal: this result is recorded already as " << ids[0] << " in " << s.open->describe()
              << " (same content hash): not recorded again\n";
    return std::nullopt;
  }
  std::cerr << "mtcal: recorded " << ids[0] << " in " << s.open->describe() << "\n";
  return ids[0];
}

void unrecord(const std::string& id) {
  if (state().open) state().open->remove(id);
}

// ---- mtcal history ... --------------------------------------------------------------------------

namespace {

CLI::App* g_history = nullptr;

struct ListOptions {
  std::string store, machine, command, from, to;
  bool json_out = false;
};

int run_list(const ListOptions& o) {
  auto store = open_cli_store(o.store);
  const auto records = store->list({o.machine, o.command, o.from, o.to});
  if (o.json_out) {
    Json j;
    j["store"] = store->describe();
    j["records"] = Json::array();
    for (const auto& r : records) j["records"].push_back(record_summary_json(r));
    print_json(j);
    return 0;
  }
  std::cout << fmt::format("{:<16}  {:<24}  {:<20}  {:<10}  {}\n", "id", "measured", "machine", "command", "figures");
  for (const auto& r : records) {
    std::string figs;
    for (const auto& f : r.figures)
      if (figs.size() < 60) figs += fmt::format("{}{}={:.4g} {}", figs.empty() ? "" : ", ", f.name, f.value, f.unit);
    if (figs.empty() && !r.parameters.empty()) figs = fmt::format("{} parameters", r.parameters.size());
    std::cout << fmt::format("{:<16}  {:<24}  {:<20}  {:<10}  {}\n", r.id, r.measured_at, r.machine_name, r.command,
                             figs);
  }
  std::cout << fmt::format("{} record(s) in {}\n", records.size(), store->describe());
  return 0;
}

struct ShowOptions {
  std::string store, id;
  bool json_out = false;
};

int run_show(const ShowOptions& o) {
  auto store = open_cli_store(o.store);
  const auto r = store->get(o.id);
  if (!r) throw InputError({store->describe(), 0, "id"}, "no record with id '" + printable(o.id) + "'");
  if (o.json_out) {
    print_json(record_json(*r));
    return 0;
  }
  std::cout << fmt::format("record      {}\nmachine     {}{}\ncommand     {}\nmeasured    {}\nrecorded    {}\n", r->id,
                           r->machine_name, r->machine_serial.empty() ? "" : " (serial " + r->machine_serial + ")",
                           r->command, r->measured_at, r->recorded_at);
  for (const auto& [k, v] : r->metadata) std::cout << fmt::format("  {:<22} {}\n", metadata_label(k), v);
  for (const auto& i : r->inputs) std::cout << fmt::format("input       {}  (SHA-256 {})\n", i.path, i.sha256);
  if (!r->parameters.empty()) {
    std::cout << fmt::format("{:<28} {:>16} {:>14} {}\n", "parameter", "value", "u (k=1)", "unit");
    for (const auto& p : r->parameters)
      std::cout << fmt::format("{:<28} {:>16.8g} {:>14} {}\n", p.name, p.value,
                               p.uncertainty ? fmt::format("{:.3g}", *p.uncertainty) : "-", p.unit);
  }
  if (!r->figures.empty()) {
    std::cout << fmt::format("{:<28} {:>16} {}\n", "figure", "value", "unit");
    for (const auto& f : r->figures) std::cout << fmt::format("{:<28} {:>16.8g} {}\n", f.name, f.value, f.unit);
  }
  std::cout << "content hash " << r->content_hash << "\n";
  return 0;
}

struct ImportOptions {
  std::string store, command;
  std::vector<std::string> files, meta;
  bool json_out = false;
};

// --meta key=value pairs, checked as report metadata keys.
std::map<std::string, std::string> import_metadata(const std::vector<std::string>& pairs) {
  ReportMetadata m;  // validates keys
  for (const auto& kv : pairs) {
    const auto eq = kv.find('=');
    if (eq == std::string::npos) throw InputError({"--meta", 0, ""}, "expected key=value, found '" + printable(kv) + "'");
    m.set(kv.substr(0, eq), kv.substr(eq + 1), "--meta");
  }
  std::map<std::string, std::string> meta;
  for (const auto& [k, v] : m.entries()) meta[k] = v;
  return meta;
}

void print_import(const HistoryImport& r, const std::string& store, bool json_out) {
  if (json_out) {
    print_json(to_json(r, store));
    return;
  }
  for (std::size_t i = 0; i < r.records.size(); ++i)
    if (std::find(r.duplicates.begin(), r.duplicates.end(), i) == r.duplicates.end())
      std::cout << fmt::format("recorded {}  {}  ({}, {})\n", r.ids[i], r.origin[i], r.records[i].command,
                               r.records[i].machine_name);
  for (const auto& s : r.skipped) std::cout << "skipped  " << s << "\n";
  std::cout << fmt::format("{} record(s) added, {} event(s) added, {} skipped, in {}\n", r.added, r.events,
                           r.skipped.size(), store);
  if (r.model_files > 0) std::cout << fmt::format("{} model file(s) added\n", r.model_files);
}

int run_import(const ImportOptions& o) {
  const auto meta = import_metadata(o.meta);
  auto store = open_cli_store(o.store);
  try {
    print_import(import_files(*store, o.files, o.command, meta), store->describe(), o.json_out);
  } catch (const InputError& e) {
    rethrow_for_options(e, {{"command", "--command"}, {"machine", "--meta machine=NAME"}});
  }
  return 0;
}

struct ExportOptions {
  std::string store, out;
  bool json_out = false;
};

int run_export(const ExportOptions& o) {
  check_outputs({}, {o.out});
  auto store = open_cli_store(o.store);
  std::ostringstream stream;
  export_jsonl(*store, stream);
  const std::string text = stream.str();
  AtomicFile f(o.out);
  f.stream() << text;
  f.commit();
  const auto lines = std::count(text.begin(), text.end(), '\n');
  if (o.json_out) {
    print_json({{"store", store->describe()}, {"out", o.out}, {"lines", lines}});
    return 0;
  }
  std::cout << fmt::format("wrote {} ({} lines: records then events) from {}\n", o.out, lines, store->describe());
  return 0;
}

struct EventOptions {
  std::string store, machine, date, kind, note;
  bool json_out = false;
};

int run_event_add(const EventOptions& o) {
  const auto kind = parse_event_kind(o.kind);
  if (!kind)
    throw InputError({"--kind", 0, o.kind},
                     "expected compensation-loaded, crash, repair or other, found '" + printable(o.kind) + "'");
  auto store = open_cli_store(o.store);
  const auto id = store->add_event({"", o.machine, o.date, *kind, o.note});
  if (o.json_out) {
    print_json({{"id", id},
                {"machine", o.machine},
                {"date", o.date},
                {"kind", o.kind},
                {"note", o.note},
                {"store", store->describe()}});
    return 0;
  }
  std::cout << fmt::format("event {} added: {} {} {}{}\n", id, o.machine, o.date, o.kind,
                           o.note.empty() ? "" : " \"" + o.note + "\"");
  return 0;
}

void add_store_option(CLI::App* c, std::string& store) {
  c->add_option("--store", store,
                "The history store: a SQLite file (created when absent), sqlite:PATH or postgresql://user@host/db; "
                "default $MTCAL_HISTORY, then history.store in the configuration file");
}

}  // namespace

CLI::App* history_app() { return g_history; }

std::vector<Command> add_history_commands(CLI::App& app) {
  auto* h = app.add_subcommand("history",
                               "The calibration history: results recorded with --record, listed, shown, imported, "
                               "exported; events between calibrations (docs/history.md)");
  g_history = h;
  h->require_subcommand(1);
  h->footer(
      "Examples:\n"
      "  mtcal iso230-2 examples/data/iso230-2-x-axis.csv --meta machine=VMC-800 --meta date=2026-11-25 "
      "--meta axis=X --record=history.db\n"
      "  mtcal history list --store history.db\n"
      "  mtcal history export --store history.db --out history.jsonl\n");
  std::vector<Command> out;

  auto lo = std::make_shared<ListOptions>();
  auto* list = h->add_subcommand("list", "The recorded results in time order (measured), optionally of one machine");
  add_store_option(list, lo->store);
  list->add_option("--machine", lo->machine, "Only this machine's results");
  list->add_option("--command", lo->command, "Only results of this command (iso230-2, identify, ballbar ...)");
  list->add_option("--from", lo->from, "Measured on or after this ISO 8601 date");
  list->add_option("--to", lo->to, "Measured on or before this ISO 8601 date");
  list->add_flag("--json", lo->json_out, "Machine-readable output (keys store, records)");
  list->footer(
      "Examples:\n  mtcal history list --store history.db\n  mtcal history list --store history.db --machine "
      "\"VMC 800\" --from 2026-01-01 --json\n");
  out.push_back({list, [lo] { return run_list(*lo); }});

  auto so = std::make_shared<ShowOptions>();
  auto* show = h->add_subcommand("show", "One recorded result: machine, metadata, inputs, parameters, figures");
  show->add_option("id", so->id, "The record's id (from history list)")->required();
  add_store_option(show, so->store);
  show->add_flag("--json", so->json_out,
                 "Machine-readable output (the record, with the command's result under result)");
  show->footer("Examples:\n  mtcal history show 3f2a9c01d4e5b6a7 --store history.db --json\n");
  out.push_back({show, [so] { return run_show(*so); }});

  auto io = std::make_shared<ImportOptions>();
  auto* imp = h->add_subcommand("import",
                                "Load results in bulk: result JSON files (mtcal ... --json), instrument files of "
                                "positioning runs (evaluated to ISO 230-2), JSON-lines exports (*.jsonl); duplicates "
                                "(same content hash) are skipped and listed; all files or none");
  imp->add_option("files", io->files, "The files")->required();
  add_store_option(imp, io->store);
  imp->add_option("--command", io->command,
                  "The command that produced the result JSON files (found from their keys when not given)");
  imp->add_option(
      "--meta", io->meta,
      "Metadata of the imported results, key=value, repeatable (machine, serial, date, axis, operator ...); "
      "wins over what the files say");
  imp->add_flag("--json", io->json_out,
                "Machine-readable output (keys store, records_added, events_added, model_files_added, skipped, "
                "records)");
  imp->footer(
      "Examples:\n  mtcal iso230-2 examples/data/iso230-2-x-axis.csv --json > x.json\n"
      "  mtcal history import x.json --store history.db --meta machine=VMC-800 --meta date=2026-11-25 --meta axis=X\n"
      "  mtcal history import old-export.jsonl --store postgresql://mtcal@db.example/shop\n");
  out.push_back({imp, [io] { return run_import(*io); }});

  auto eo = std::make_shared<ExportOptions>();
  auto* exp = h->add_subcommand("export",
                                "Write the whole store as JSON lines (records, then events): a backup that "
                                "history import reads back losslessly");
  add_store_option(exp, eo->store);
  exp->add_option("--out", eo->out, "The JSON-lines file")->required();
  exp->add_flag("--json", eo->json_out, "Machine-readable output (keys store, out, lines)");
  exp->footer("Examples:\n  mtcal history export --store history.db --out history.jsonl\n");
  out.push_back({exp, [eo] { return run_export(*eo); }});

  auto* ev = h->add_subcommand("event", "Events between calibrations (compensation loaded, crash, repair)");
  ev->require_subcommand(1);
  auto vo = std::make_shared<EventOptions>();
  auto* add = ev->add_subcommand("add", "Add an event to a machine's time line");
  add_store_option(add, vo->store);
  add->add_option("--machine", vo->machine, "The machine")->required();
  add->add_option("--date", vo->date, "When, ISO 8601 (2026-11-25 or 2026-11-25T10:30:00Z)")->required();
  add->add_option("--kind", vo->kind, "compensation-loaded, crash, repair or other")->required();
  add->add_option("--note", vo->note, "What happened");
  add->add_flag("--json", vo->json_out, "Machine-readable output (keys id, machine, date, kind, note, store)");
  add->footer(
      "Examples:\n  mtcal history event add --store history.db --machine VMC-800 --date 2026-11-20 --kind crash "
      "--note \"Z hit the vice\"\n");
  out.push_back({add, [vo] { return run_event_add(*vo); }});
  return out;
}

}  // namespace mtcal::cli
