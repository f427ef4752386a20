// Python bindings of acceptance and reports: test metadata, tolerances and the verdict, HTML reports with static copies.
#include <functional>

#include "common.hpp"
#include "results.hpp"
#include "mtcal/evaluation/compare.hpp"
#include "mtcal/evaluation/iso230_2.hpp"
#include "mtcal/evaluation/metadata.hpp"
#include "mtcal/evaluation/tolerance.hpp"
#include "mtcal/io/instruments/acceptance_files.hpp"
#include "mtcal/io/instruments/laser_files.hpp"
#include "mtcal/io/json/acceptance_json.hpp"
#include "mtcal/io/system/headless_browser.hpp"
#include "mtcal/report/evaluation.hpp"
#include "mtcal/report/history.hpp"
#include "mtcal/report/compensation.hpp"
#include "mtcal/report/probing.hpp"
#include "mtcal/report/error_map.hpp"
#include "mtcal/evaluation/contributions.hpp"
#include "mtcal/io/compensation/output.hpp"
#include "mtcal/probing/rotary_axis.hpp"
#include "mtcal/report/report.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal::python {

using namespace pybind11::literals;

py::dict metadata_dict(const ReportMetadata& m) {
  py::dict d;
  for (const auto& [k, v] : m.entries()) d[py::str(k)] = v;
  return d;
}

namespace {

// Test metadata from a mapping key -> value (keys of metadata_fields(); values shown as text).
ReportMetadata metadata_of(py::handle metadata) {
  ReportMetadata m;
  if (metadata.is_none()) return m;
  for (auto item : metadata.cast<py::dict>())
    m.set(py::str(item.first).cast<std::string>(), py::str(item.second).cast<std::string>(), "metadata");
  return m;
}

// The quantities of a result the tolerances judge, and which test it is.
std::pair<std::vector<std::pair<std::string, double>>, AcceptanceTest> judged(py::handle result) {
  if (py::isinstance<PositioningEvaluation>(result))
    return {tolerance_values(result.cast<const PositioningEvaluation&>()), AcceptanceTest::Iso230_2};
  if (py::isinstance<BallbarResult>(result))
    return {tolerance_values(result.cast<const BallbarResult&>().evaluation), AcceptanceTest::Iso230_4};
  if (py::hasattr(result, "_tolerance_values"))  // a VolumetricResult (evaluation.cpp): VA, VAx, VAy, VAz
    return {result.attr("_tolerance_values")().cast<std::vector<std::pair<std::string, double>>>(),
            AcceptanceTest::Volumetric};
  throw py::type_error("result: expected a PositioningEvaluation (iso230_2), a BallbarResult (ballbar) or a "
                       "VolumetricResult (volumetric), found " +
                       std::string(py::str(py::type::of(result).attr("__name__"))));
}

// The session's metadata and static copies for one report, put back afterwards: the library's
// reports read both from process-wide settings that the command sets once.
class ReportSession {
 public:
  ReportSession(ReportMetadata m, StaticCopies copies)
      : metadata_(session_metadata()), copies_(static_copies()), note_(static_copy_note()) {
    set_session_metadata(std::move(m));
    set_static_copies(std::move(copies));
    set_static_copy_note(
        "<p>A PDF of this page and PNG images of its plots: <code>mtcal.write_report(result, path, "
        "pdf=\"report.pdf\", png_dir=\"plots\")</code> (headless Chromium).</p>");
  }
  ~ReportSession() {
    set_session_metadata(std::move(metadata_));
    set_static_copies(std::move(copies_));
    set_static_copy_note(std::move(note_));
  }
  ReportSession(const ReportSession&) = delete;
  ReportSession& operator=(const ReportSession&) = delete;

 private:
  ReportMetadata metadata_;
  StaticCopies copies_;
  std::string note_;
};

StaticCopies copies_of(py::handle pdf, py::handle png_dir, const std::string& path, double timeout) {
  StaticCopies c;
  if (!pdf.is_none()) c.pdf = pdf.cast<std::string>();
  if (!png_dir.is_none()) c.png_dir = png_dir.cast<std::string>();
  if (c.empty()) return c;
  if (!c.pdf.empty() && c.pdf == path) throw py::value_error("pdf: names the same file as the report ('" + path + "')");
  c.browser = find_headless_browser(timeout).program;
  c.timeout_s = timeout;
  return c;
}

}  // namespace

void bind_acceptance_reports(py::module_& m) {
  m.def(
      "metadata_fields",
      []() {
        py::dict d;
        for (const auto& f : metadata_fields()) d[py::str(std::string(f.key))] = std::string(f.label);
        return d;
      },
      "The test metadata an acceptance report may carry: key -> label, in the order a report lists them "
      "(the keys of --meta and of metadata= arguments).");
  m.def(
      "read_metadata_file", [](const std::string& path) { return metadata_dict(read_report_metadata(path)); },
      "path"_a, "A metadata YAML file (key: value lines; --meta-file) as a dict, keys checked.");

  py::class_<Acceptance>(m, "AcceptanceVerdict", "Tolerances checked against a result, with the test's metadata.")
      .def_property_readonly(
          "checks",
          [](const Acceptance& a) {
            py::list l;
            for (const auto& c : a.verdict.checks)
              l.append(py::make_tuple(c.quantity, c.value, c.limit, c.pass));
            return l;
          },
          "(quantity, value, limit, pass) per limit, µm")
      .def_property_readonly("passed", [](const Acceptance& a) { return a.verdict.pass(); },
                             "Every check passed (False when nothing was checked)")
      .def_property_readonly("empty", [](const Acceptance& a) { return a.verdict.empty(); })
      .def_property_readonly("metadata", [](const Acceptance& a) { return metadata_dict(a.metadata); })
      .def_property_readonly(
          "missing_metadata", [](const Acceptance& a) { return missing_acceptance_fields(a.metadata, a.test); },
          "What the test's report should state and the metadata lacks, as sentences")
      .def(
          "to_dict", [](const Acceptance& a) { return to_py(to_json(a.verdict)); },
          "As the command's --json 'tolerances' (verdict, unit, checks).")
      .def("__bool__", [](const Acceptance& a) { return a.verdict.pass(); });
  m.def(
      "evaluate_tolerances",
      [](py::handle result, py::handle tolerances, const std::string& tolerance_file, py::handle metadata,
         const std::string& axis) {
        auto [values, test] = judged(result);
        Acceptance a;
        a.test = test;
        a.metadata = metadata_of(metadata);
        Tolerances t;
        if (!tolerance_file.empty()) {
          const ToleranceFile f = read_tolerance_file(tolerance_file);
          const std::string* meta_axis = a.metadata.get("axis");
          if (test == AcceptanceTest::Iso230_2) t = f.iso230_2_for(!axis.empty() ? axis : meta_axis ? *meta_axis : "");
          if (test == AcceptanceTest::Iso230_4) t = f.iso230_4;
          if (test == AcceptanceTest::Volumetric) t = f.volumetric;
        }
        if (!tolerances.is_none())
          for (auto item : tolerances.cast<py::dict>()) {
            const double v = item.second.cast<double>();
            const std::string q = py::str(item.first).cast<std::string>();
            if (!(v >= 0)) throw py::value_error("tolerances['" + q + "']: expected a permitted value >= 0 in µm");
            t.set(q, v);
          }
        if (!t.empty()) a.verdict = check_tolerances(values, t, "tolerances");
        return a;
      },
      "result"_a, "tolerances"_a = py::none(), py::kw_only(), "tolerance_file"_a = "", "metadata"_a = py::none(),
      "axis"_a = "",
      R"(Acceptance: the quantities of an ISO 230-2 (A, E, M, R, B), ISO 230-4 (G, F, H) or volumetric
(VA, VAx, VAy, VAz) result
against permitted values in µm, as the commands' --tolerance / --tolerance-file: tolerances
{Q: µm} over the file's section (ISO 230-2: the entry of axis, else of metadata['axis'], else
'any'). A quantity passes when its value is at most its limit. metadata: the test's fields
(machine, serial, date, operator, temperature ...; --meta), checked. Returns AcceptanceVerdict.)");

  m.def(
      "write_report",
      [](py::handle result, const std::string& path, py::handle pdf, py::handle png_dir, py::handle runs,
         py::handle acceptance, py::handle metadata, const std::string& command, double browser_timeout,
         py::handle machine, double max_rms, bool nonzero_only) {
        ReportMetadata meta = metadata_of(metadata);
        ToleranceVerdict verdict;
        if (!acceptance.is_none()) {
          const auto& a = acceptance.cast<const Acceptance&>();
          verdict = a.verdict;
          if (metadata.is_none()) meta = a.metadata;
        }
        std::function<void()> write;
        const std::string cmd = command.empty() ? "mtcal (Python) write_report" : command;
        if (py::isinstance<PositioningEvaluation>(result)) {
          if (runs.is_none())
            throw py::value_error("runs: expected the PositioningRuns the evaluation was made of (the report shows "
                                  "every deviation)");
          const auto& r = runs.cast<const PositioningRuns&>();
          meta.fill_missing_from(laser_report_metadata(r));  // what the file's header states, under the user's
          const auto& e = result.cast<const PositioningEvaluation&>();
          write = [&] { write_positioning_report(path, cmd, r, e, verdict); };
        } else if (py::isinstance<BallbarResult>(result)) {
          const auto& b = result.cast<const BallbarResult&>();
          if (b.feed > 0 && !meta.get("feed")) meta.set("feed", py::str(py::str("{:g} mm/min").attr("format")(b.feed)).cast<std::string>());
          write = [&] {
            write_ballbar_report(path, cmd, b.trace, b.evaluation, b.diagnosis, b.plane, b.radius, b.feed, verdict);
          };
        } else if (py::isinstance<MethodComparison>(result)) {
          const auto& c = result.cast<const MethodComparison&>();
          write = [&] { write_comparison_report(path, cmd, c); };
        } else if (py::isinstance<HistoryTrends>(result)) {
          const auto& t = result.cast<const HistoryTrends&>();
          write = [&] { write_trend_report(path, cmd, t.trends, t.records, t.store); };
        } else if (py::isinstance<RotaryAxisResult>(result)) {
          const auto& r = result.cast<const RotaryAxisResult&>();
          const Machine* mm = machine.is_none() ? nullptr : &machine.cast<const Machine&>();
          write = [&, mm] { write_rotary_report(path, cmd, mm, r, max_rms); };
        } else if (py::isinstance<TargetOutput>(result)) {
          if (machine.is_none())
            throw py::value_error("machine: expected the Machine the compensation was made of (the report shows "
                                  "its errors before and after)");
          const auto& mm = machine.cast<const Machine&>();
          const auto& out = result.cast<const TargetOutput&>();
          write = [&] { write_compensation_report(path, cmd, mm, {}, "", out); };
        } else if (py::isinstance<Machine>(result)) {
          // mtcal errors --report: every parameter (nonzero_only: the command's --nonzero).
          const auto& mm = result.cast<const Machine&>();
          write = [&] {
            const auto listed = listed_parameters(mm, nonzero_only);
            write_parameters_report(path, mm, listed, mm.parameter_count(), nonzero_only, {cmd, {}, "", ""});
          };
        } else if (py::hasattr(result, "_tolerance_values")) {
          // A VolumetricResult (evaluation.cpp): the verdict on VA, VAx, VAy, VAz as the command's
          // `volumetric --tolerance ... --report` shows it.
          if (!verdict.empty() && acceptance.cast<const Acceptance&>().test != AcceptanceTest::Volumetric)
            throw py::value_error(
                "acceptance: expected the verdict on this result (evaluate_tolerances of it), found "
                "one of another test");
          write = [&] { result.attr("_write_report")(path, cmd, acceptance); };
        } else if (py::hasattr(result, "_write_report")) {
          // The results the other binding units keep (contributions, diagonals, effects, eval, toolpath,
          // regress, identify, predict): their reports show no verdict.
          if (!verdict.empty())
            throw py::value_error(
                "acceptance: this result's report shows no verdict (ISO 230-2, ballbar, volumetric only)");
          write = [&] { result.attr("_write_report")(path, cmd); };
        } else {
          throw py::type_error("result: expected a result that has a report (docs/python.md, 'Acceptance and "
                               "reports'), found " +
                               std::string(py::str(py::type::of(result).attr("__name__"))));
        }
        ReportSession session(std::move(meta), copies_of(pdf, png_dir, path, browser_timeout));
        write();
      },
      "result"_a, "path"_a, "pdf"_a = py::none(), "png_dir"_a = py::none(), py::kw_only(), "runs"_a = py::none(),
      "acceptance"_a = py::none(), "metadata"_a = py::none(), "command"_a = "", "browser_timeout"_a = 120.0,
      "machine"_a = py::none(), "max_rms"_a = 0.01, "nonzero_only"_a = false,
      R"(The HTML report of a result, as the command's --report (written complete or not at all):
iso230_2 (PositioningEvaluation; runs= the PositioningRuns), ballbar (BallbarResult), compare_methods
(MethodComparison), HistoryStore.trend (HistoryTrends), volumetric, contributions, diagonals,
effects, identify, predict, rotary_axis (RotaryAxisResult; machine= optional, max_rms= as given
to it), compensate (TargetOutput; machine= required) and a Machine (mtcal errors --report;
nonzero_only as --nonzero). pdf: also the report printed to PDF,
png_dir: each plot as PNG (--report-pdf, --report-png; headless Chromium). acceptance: an
AcceptanceVerdict shown as PASS/FAIL (its metadata unless metadata= is given); metadata: the test's
fields; command: the line shown as how the report was made.)");
}

}  // namespace mtcal::python
