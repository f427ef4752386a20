// Python bindings of the calibration history: a store (SQLite or PostgreSQL), records, diff, trend, rank, events.
#include <algorithm>
#include <memory>
#include <sstream>

#include "common.hpp"
#include "results.hpp"
#include "mtcal/evaluation/metadata.hpp"
#include "mtcal/history/analysis.hpp"
#include "mtcal/io/history/import_files.hpp"
#include "mtcal/io/history/queries.hpp"
#include "mtcal/io/history/store.hpp"
#include "mtcal/io/json/history_json.hpp"
#include "mtcal/io/system/files.hpp"
#include "mtcal/io/system/sha256.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal::python {

using namespace pybind11::literals;

namespace {

// One open store; the library's store is not meant to be shared between threads, and every
// method holds the GIL, so one Python object is used by one thread at a time.
struct PyStore {
  std::unique_ptr<HistoryStore> store;
  HistoryStore& operator*() const {
    if (!store) throw py::value_error("the history store is closed");
    return *store;
  }
};

// A result as JSON text: a str as it is, else json.dumps of the object (Python's float repr reads
// back as the same double, so a result's to_dict() keeps full precision).
std::string result_text(py::handle result) {
  if (py::isinstance<py::str>(result)) return result.cast<std::string>();
  return py::module_::import("json").attr("dumps")(result).cast<std::string>();
}

std::map<std::string, std::string> metadata_map(py::handle metadata) {
  std::map<std::string, std::string> out;
  if (metadata.is_none()) return out;
  ReportMetadata m;  // checks the keys and values
  for (auto item : metadata.cast<py::dict>())
    m.set(py::str(item.first).cast<std::string>(), py::str(item.second).cast<std::string>(), "metadata");
  for (const auto& [k, v] : m.entries()) out[k] = v;
  return out;
}

// Tolerances as "Q=V" / "Q=LO:HI" texts, or a mapping quantity -> V or (LO, HI).
std::vector<HistoryTolerance> tolerances_of(py::handle t) {
  std::vector<std::string> specs;
  if (t.is_none()) return {};
  if (py::isinstance<py::dict>(t)) {
    for (auto item : t.cast<py::dict>()) {
      const std::string q = py::str(item.first).cast<std::string>();
      if (py::isinstance<py::tuple>(item.second) || py::isinstance<py::list>(item.second)) {
        const auto v = as_std_vector(item.second, ("tolerances['" + q + "']").c_str(), 2);
        specs.push_back(q + "=" + py::repr(py::float_(v[0])).cast<std::string>() + ":" +
                        py::repr(py::float_(v[1])).cast<std::string>());
      } else {
        specs.push_back(q + "=" + py::repr(py::float_(item.second.cast<double>())).cast<std::string>());
      }
    }
  } else {
    specs = t.cast<std::vector<std::string>>();
  }
  return parse_history_tolerances(specs, "tolerances");
}

}  // namespace

void bind_history(py::module_& m) {
  py::class_<HistoryTrends>(m, "HistoryTrends", "One machine's trends: series with their drift fits, and events.")
      .def_property_readonly("machine", [](const HistoryTrends& t) { return t.trends.machine; })
      .def_property_readonly("serial", [](const HistoryTrends& t) { return t.trends.serial; })
      .def_property_readonly(
          "series",
          [](const HistoryTrends& t) {
            py::list l;
            for (const auto& q : t.trends.series) l.append(to_py(to_json(q)));
            return l;
          },
          "Per quantity: {quantity, kind, unit, samples, trend} (as in to_dict())")
      .def_property_readonly("records", [](const HistoryTrends& t) { return t.records.size(); },
                             "How many calibrations of the machine the store has")
      .def(
          "to_dict", [](const HistoryTrends& t) { return to_py(to_json(t.trends)); },
          "As `mtcal history trend --json` (docs/history.md).");

  py::class_<PyStore>(m, "HistoryStore", R"(The calibration history (docs/history.md): SQLite or PostgreSQL.

HistoryStore(connection): "FILE.db", "sqlite:PATH" (created when absent) or "postgresql://user@host/db";
migrated to the current schema on opening. Every write is one transaction.)")
      .def(py::init([](const std::string& connection) { return PyStore{open_history_store(connection)}; }),
           "connection"_a)
      .def_property_readonly("description", [](const PyStore& s) { return (*s).describe(); },
                             "'sqlite:/path' or 'postgresql://host:port/db' (without a password)")
      .def_property_readonly("schema_version", [](const PyStore& s) { return (*s).schema_version(); })
      .def("machines", [](const PyStore& s) { return (*s).machines(); }, "Machine names, sorted.")
      .def(
          "record",
          [](const PyStore& s, const std::string& command, py::handle result, py::handle metadata,
             const std::vector<std::string>& inputs, const std::string& machine_file,
             const std::vector<std::string>& parameter_files) {
            // The model's files first among the inputs, as the command lists them (the server makes a
            // record's model again from them, in that order), then the other inputs.
            std::vector<std::pair<std::string, std::string>> model;
            if (!machine_file.empty()) model.emplace_back("machine", machine_file);
            for (const auto& p : parameter_files) model.emplace_back("parameters", p);
            std::vector<std::string> paths;
            for (const auto& kp : model) paths.push_back(kp.second);
            for (const auto& p : inputs)
              if (std::find(paths.begin(), paths.end(), p) == paths.end()) paths.push_back(p);
            std::vector<InputHash> hashes;
            for (const auto& p : paths) hashes.push_back({p, sha256_file(p)});
            std::vector<ModelFile> files;
            for (const auto& [kind, path] : model) {
              auto file = read_model_file(kind, path);
              if (!file) {
                const std::string why = "the " + std::string(kind == "machine" ? "machine file" : "parameter file") +
                                        " '" + printable(path) +
                                        "' is not UTF-8 text: it is not kept in the history store with the record";
                if (PyErr_WarnEx(PyExc_UserWarning, why.c_str(), 1) != 0) throw py::error_already_set();
                continue;
              }
              files.push_back(std::move(*file));
            }
            CalibrationRecord r = record_from_result(command, result_text(result), metadata_map(metadata),
                                                     std::move(hashes), command);
            if (r.machine_name.empty())
              throw InputError({"metadata", 0, "machine"},
                               "the result names no machine to record it under: give metadata={'machine': NAME}");
            std::vector<std::size_t> skipped;
            const auto ids = (*s).record_all({r}, {}, &skipped, std::move(files));
            return ids.at(0);
          },
          "command"_a, "result"_a, py::kw_only(), "metadata"_a = py::none(),
          "inputs"_a = std::vector<std::string>{}, "machine_file"_a = "",
          "parameter_files"_a = std::vector<std::string>{},
          R"(Records a command's result, as `mtcal COMMAND --record`: command ('iso230-2', 'ballbar',
'volumetric', 'identify', 'fit-motion', ...), result: its to_dict() (or the --json text), metadata:
the test's fields (machine, serial, date ...; docs/reports.md), inputs: the input files (their
SHA-256 is kept). machine_file, parameter_files: the machine file (-m) and parameter files
(--params) the result was made with: listed first among the inputs and their text kept in the
store (docs/history.md, "Model files"; what `mtcal serve` writes compensation of a record from;
a file that is not UTF-8 is not kept, with a UserWarning). Returns the record's id; a result
stored already (same content hash) is not stored again and its id is returned.)")
      .def(
          "list",
          [](const PyStore& s, const std::string& machine, const std::string& command, const std::string& from,
             const std::string& to) {
            py::list l;
            for (const auto& r : (*s).list({machine, command, from, to})) l.append(to_py(record_summary_json(r)));
            return l;
          },
          py::kw_only(), "machine"_a = "", "command"_a = "", "from_"_a = "", "to"_a = "",
          "The records in time order (measured), as `mtcal history list --json`'s records.")
      .def(
          "show",
          [](const PyStore& s, const std::string& id) {
            const auto r = (*s).get(id);
            if (!r) throw InputError({(*s).describe(), 0, "id"}, "no record with id '" + printable(id) + "'");
            return to_py(record_json(*r));
          },
          "id"_a, "One record, as `mtcal history show --json`.")
      .def(
          "diff",
          [](const PyStore& s, const std::string& first, const std::string& second, double k) {
            auto get = [&](const std::string& id) {
              auto r = (*s).get(id);
              if (!r) throw InputError({(*s).describe(), 0, "id"}, "no record '" + printable(id) + "' in the store");
              return *r;
            };
            const CalibrationRecord a = get(first), b = get(second);
            DiffOptions d;
            d.coverage_factor = k;
            Json j = to_json(diff_records(a, b, d));
            j["machines"] = {a.machine_name, b.machine_name};
            j["measured_at"] = {a.measured_at, b.measured_at};
            return to_py(j);
          },
          "first"_a, "second"_a, py::kw_only(), "coverage_factor"_a = 2.0,
          "What changed between two records (E_n with U = k u), as `mtcal history diff --json`.")
      .def(
          "trend",
          [](const PyStore& s, const std::string& machine, const std::vector<std::string>& parameters,
             const std::vector<std::string>& figures, py::handle tolerances, const std::string& tolerance_file,
             const std::string& from, const std::string& to) {
            TrendRequest r;
            r.machine = machine;
            r.parameters = parameters;
            r.figures = figures;
            r.tolerances = tolerances_of(tolerances);
            r.tolerance_file = tolerance_file;
            r.from = from;
            r.to = to;
            HistoryTrends t;
            t.records = machine_records(*s, machine);
            t.trends = machine_trends(*s, r, t.records);
            t.store = (*s).describe();
            return t;
          },
          "machine"_a, py::kw_only(), "parameters"_a = std::vector<std::string>{},
          "figures"_a = std::vector<std::string>{}, "tolerances"_a = py::none(), "tolerance_file"_a = "",
          "from_"_a = "", "to"_a = "",
          R"(Drift of parameters / figures of one machine, as `mtcal history trend`: neither parameters
nor figures: all of both. tolerances: {Q: V} (|value| <= V for a parameter, value <= V for a
figure) or {Q: (LO, HI)}, or ["Q=V", "Q=LO:HI"], in the recorded unit; tolerance_file: acceptance
tolerances (µm) of the figures. Returns HistoryTrends (to_dict(), write_report(trends, path)).)")
      .def(
          "rank",
          [](const PyStore& s, py::handle tolerances, const std::string& tolerance_file, const std::string& by,
             int threads) {
            if (by != "utilisation" && by != "time")
              throw py::value_error("by: expected 'utilisation' or 'time', found '" + by + "'");
            RankRequest r;
            r.tolerances = tolerances_of(tolerances);
            r.tolerance_file = tolerance_file;
            r.options.threads = threads;
            r.options.order = by == "time" ? RankOrder::TimeToLimit : RankOrder::Utilisation;
            const StoreRanking ranked = rank_store(*s, r);
            Json j = to_json(ranked.ranking);
            j["not_ranked"] = ranked.not_ranked;
            return to_py(j);
          },
          py::kw_only(), "tolerances"_a = py::none(), "tolerance_file"_a = "", "by"_a = "utilisation",
          "threads"_a = 0, "The machines ranked by how far they are from tolerance, as `mtcal history rank --json`.")
      .def(
          "add_event",
          [](const PyStore& s, const std::string& machine, const std::string& date, const std::string& kind,
             const std::string& note) {
            const auto k = parse_event_kind(kind);
            if (!k)
              throw InputError({"kind", 0, kind},
                               "expected compensation-loaded, crash, repair or other, found '" + printable(kind) + "'");
            return (*s).add_event({"", machine, date, *k, note});
          },
          "machine"_a, "date"_a, "kind"_a, "note"_a = "",
          "Adds an event (compensation-loaded, crash, repair, other) to a machine's time line, as `mtcal history "
          "event add`; returns its id.")
      .def(
          "events",
          [](const PyStore& s, const std::string& machine) {
            py::list l;
            for (const auto& e : (*s).events(machine)) {
              py::dict d;
              d["id"] = e.id;
              d["machine"] = e.machine;
              d["date"] = e.date;
              d["kind"] = std::string(to_string(e.kind));
              d["note"] = e.note;
              l.append(d);
            }
            return l;
          },
          "machine"_a = "", "Events in date order (machine '': all).")
      .def(
          "export",
          [](const PyStore& s, py::handle path) -> py::object {
            std::ostringstream out;
            export_jsonl(*s, out);
            const std::string text = out.str();
            if (path.is_none()) return py::str(text);
            write_file_atomically(path.cast<std::string>(), text);
            return py::int_(std::count(text.begin(), text.end(), '\n'));
          },
          "path"_a = py::none(),
          "The store as JSON lines (records then events), as `mtcal history export`: written to path (all or "
          "nothing; returns the line count), or returned as text without a path.")
      .def(
          "import_",
          [](const PyStore& s, py::handle files, const std::string& command, py::handle metadata) {
            std::vector<std::string> paths;
            if (py::isinstance<py::str>(files))
              paths.push_back(files.cast<std::string>());
            else
              paths = files.cast<std::vector<std::string>>();
            return to_py(to_json(import_files(*s, paths, command, metadata_map(metadata)), (*s).describe()));
          },
          "files"_a, py::kw_only(), "command"_a = "", "metadata"_a = py::none(),
          R"(Imports files as `mtcal history import FILE... --json` does: result JSON files (what a command's
--json printed; command: the command that made them, or "" to tell it from their keys: iso230-2,
ballbar, volumetric, identify), instrument files of positioning runs (evaluated to ISO 230-2)
and JSON-lines exports (*.jsonl, what export wrote: ids kept). files: a path or a list of
paths; metadata: the test's fields, over what the files say (machine, date ...; --meta). Every
result file is read before anything is stored; records stored already (same content hash) are
skipped and listed. Returns {store, records_added, events_added, model_files_added, skipped, records:
[{file, id}]}.)")
      .def(
          "close", [](PyStore& s) { s.store.reset(); }, "Closes the connection (also when the object goes).")
      .def("__enter__", [](PyStore& s) -> PyStore& { return s; }, py::return_value_policy::reference)
      .def("__exit__", [](PyStore& s, py::args) { s.store.reset(); });

}

}  // namespace mtcal::python
