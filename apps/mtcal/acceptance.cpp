#include "acceptance.hpp"

#include <filesystem>
#include <iostream>

#include <fmt/format.h>

#include "mtcal/io/system/headless_browser.hpp"
#include "mtcal/report/report.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/util/parse.hpp"

namespace mtcal::cli {

namespace {
// What the options shared by every command hold, filled by CLI11 when the command line is parsed.
struct SharedOptions {
  std::vector<std::string> meta;  // --meta
  std::string file;               // --meta-file
  std::string pdf, png_dir;       // --report-pdf, --report-png
  double timeout_s = 120;         // --browser-timeout
};
SharedOptions& meta_options() {
  static SharedOptions o;
  return o;
}
SharedOptions& copy_options() { return meta_options(); }
}  // namespace

void add_metadata_options(CLI::App& app) {
  for (auto* sub : app.get_subcommands({})) {
    if (!sub->get_option_no_throw("--report") && !sub->get_option_no_throw("--json")) continue;
    sub->add_option("--meta", meta_options().meta,
                    "Test metadata shown on the report and kept in the JSON, key=value, repeatable: machine, "
                    "serial, owner, location, operator, date, axis, temperature, temperature_air, "
                    "temperature_machine, temperature_material, humidity, instrument, instrument_serial, "
                    "calibration_certificate, calibration_date, feed, dwell, direction, start, data_capture, "
                    "compensation, centre, conditions, notes (e.g. --meta serial=4711 --meta \"operator=A. Smith\")");
    sub->add_option("--meta-file", meta_options().file,
                    "Test metadata from a YAML file of key: value lines (same keys as --meta, which wins)");
  }
}

void load_session_metadata() {
  const auto& o = meta_options();
  ReportMetadata m;
  if (!o.file.empty()) m = read_report_metadata(o.file);
  for (const auto& kv : o.meta) {
    const auto eq = kv.find('=');
    if (eq == std::string::npos)
      throw InputError({"--meta", 0, ""}, "expected key=value, found '" + printable(kv) + "'");
    m.set(kv.substr(0, eq), kv.substr(eq + 1), "--meta");
  }
  set_session_metadata(std::move(m));
}

std::vector<std::string> metadata_inputs() { return {meta_options().file}; }

void warn_missing_metadata(AcceptanceTest test, bool acceptance_run) {
  if (!acceptance_run && session_metadata().empty()) return;
  for (const auto& w : missing_acceptance_fields(session_metadata(), test))
    std::cerr << "mtcal: warning: acceptance report: " << w << " (give it with --meta or --meta-file)\n";
}

void add_static_copy_options(CLI::App& app) {
  for (auto* sub : app.get_subcommands({})) {
    if (!sub->get_option_no_throw("--report")) continue;
    sub->add_option("--report-pdf", copy_options().pdf,
                    "Also write the report printed to PDF (A4, plots as images), for e-mail and where JavaScript "
                    "does not run; made by headless Chromium (Debian package chromium); needs --report");
    sub->add_option("--report-png", copy_options().png_dir,
                    "Also write each plot of the report as a PNG image into this directory (REPORT-plot-N.png; made "
                    "if missing, in an existing folder), by headless Chromium; needs --report");
    sub->add_option("--browser-timeout", copy_options().timeout_s,
                    "Seconds the browser may take for each static copy (default 120)")
        ->check(CLI::PositiveNumber);
  }
}

void load_static_copies(CLI::App& cmd) {
  const SharedOptions& o = copy_options();
  if (o.pdf.empty() && o.png_dir.empty()) return;
  const CLI::Option* report = cmd.get_option_no_throw("--report");
  const std::string which = o.pdf.empty() ? "--report-png" : "--report-pdf";
  if (!report || report->count() == 0)
    throw InputError({which, 0, ""}, "expected --report FILE.html beside it: the static copy is made of that report");
  const std::string report_path = report->as<std::string>();
  if (!o.pdf.empty() && std::filesystem::weakly_canonical(o.pdf) == std::filesystem::weakly_canonical(report_path))
    throw InputError({"--report-pdf", 0, ""}, "names the same file as --report ('" + printable(o.pdf) + "')");
  // Checked before the browser is looked for and before any work. A folder that is not there is
  // made when the images are written, as `compensate --out DIR` makes its folder (and removed
  // again if the command fails); its parent must exist, so that a mistyped path makes nothing.
  // The PDF's folder likewise: found missing only after the work and the browser's print (5-10 s),
  // the same error would cost the user that wait for nothing.
  if (!o.pdf.empty()) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path pdf = fs::path(o.pdf).lexically_normal();
    const fs::path parent = pdf.has_parent_path() ? pdf.parent_path() : fs::path(".");
    if (!pdf.has_filename() || fs::is_directory(pdf, ec))
      throw InputError({"--report-pdf", 0, ""}, "expected a file name for the PDF, found the folder '" + printable(o.pdf) + "'");
    if (!fs::is_directory(parent, ec))
      throw InputError({"--report-pdf", 0, ""},
                       "expected the PDF in an existing folder, found that '" + printable(parent.string()) +
                           "' is not a folder");
  }
  if (!o.png_dir.empty()) {
    namespace fs = std::filesystem;
    std::error_code ec;
    fs::path dir = fs::path(o.png_dir).lexically_normal();
    if (!dir.has_filename()) dir = dir.parent_path();  // "png/" names the folder png
    const fs::path parent = dir.has_parent_path() ? dir.parent_path() : fs::path(".");
    if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
      throw InputError({"--report-png", 0, ""},
                       "expected a directory for the plot images, found a file '" + printable(o.png_dir) + "'");
    if (!fs::exists(dir, ec) && !fs::is_directory(parent, ec))
      throw InputError({"--report-png", 0, ""},
                       "expected a directory for the plot images (a new one is made in an existing folder), found "
                       "that the folder '" +
                           printable(parent.string()) + "' does not exist");
  }
  const HeadlessBrowser b = find_headless_browser(o.timeout_s);
  set_static_copies({o.pdf, o.png_dir, b.program, o.timeout_s});
}

void print_json(Json j) {
  // The user's fields join (and win over) what an input file's header gave under "metadata".
  if (j.is_object() && !session_metadata().empty()) {
    if (!j.contains("metadata") || !j["metadata"].is_object()) j["metadata"] = Json::object();
    for (const auto& [k, v] : session_metadata().entries()) j["metadata"][k] = v;
  }
  std::cout << json_text(j, 2) << "\n";
}

void add_tolerance_options(CLI::App* cmd, ToleranceOptions& o, const std::string& quantities) {
  cmd->add_option("--tolerance", o.limits,
                  "Permitted value of a quantity, Q=V in µm (suffix um or mm allowed), repeatable; quantities: " +
                      quantities + ". Each gets pass/fail and the run an overall verdict");
  cmd->add_option("--tolerance-file", o.file,
                  "Tolerances from a YAML file (docs/reports.md; --tolerance wins over it)");
  cmd->add_flag("--fail-on-tolerance", o.fail_exit,
                "Exit with status 3 when a quantity exceeds its tolerance (default: the verdict is a result "
                "and the exit status 0)");
}

Tolerances tolerances_for(const ToleranceOptions& o, AcceptanceTest test, const std::string& axis) {
  Tolerances t;
  if (!o.file.empty()) {
    const ToleranceFile f = read_tolerance_file(o.file);
    if (test == AcceptanceTest::Iso230_2) t = f.iso230_2_for(axis);
    if (test == AcceptanceTest::Iso230_4) t = f.iso230_4;
    if (test == AcceptanceTest::Volumetric) t = f.volumetric;
  }
  for (const auto& kv : o.limits) {
    const auto eq = kv.find('=');
    if (eq == std::string::npos || eq == 0)
      throw InputError({"--tolerance", 0, ""}, "expected Q=V (e.g. A=8), found '" + printable(kv) + "'");
    std::string v = kv.substr(eq + 1);
    double scale = 1;
    for (const auto& [suffix, s] : {std::pair{"µm", 1.0}, {"um", 1.0}, {"mm", 1000.0}})
      if (v.size() > std::string(suffix).size() && v.ends_with(suffix)) {
        v.resize(v.size() - std::string(suffix).size());
        scale = s;
        break;
      }
    const auto x = parse_number(v);
    if (!x || *x < 0)
      throw InputError({"--tolerance", 0, kv.substr(0, eq)},
                       "expected a permitted value >= 0 in µm, found '" + printable(kv.substr(eq + 1)) + "'");
    t.set(kv.substr(0, eq), *x * scale);
  }
  return t;
}

ToleranceVerdict checked_verdict(const std::vector<std::pair<std::string, double>>& values, const Tolerances& t) {
  return check_tolerances(values, t, "--tolerance");
}

void print_verdict(const ToleranceVerdict& v) {
  if (v.empty()) return;
  std::cout << "verdict " << (v.pass() ? "PASS" : "FAIL") << ":";
  for (const auto& c : v.checks)
    std::cout << fmt::format("  {} {:.2f} {} {:g} um{}", c.quantity, c.value, c.pass ? "<=" : ">", c.limit,
                             c.pass ? "" : " FAIL");
  std::cout << "\n";
}

int verdict_exit_code(const ToleranceOptions& o, const ToleranceVerdict& v) {
  return o.fail_exit && !v.empty() && !v.pass() ? 3 : 0;
}

}  // namespace mtcal::cli
