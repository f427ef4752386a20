// Self-contained HTML reports: summary block, tables, interactive Plotly plots, all inlined.
#pragma once

#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "mtcal/evaluation/tolerance.hpp"
#include "mtcal/evaluation/metadata.hpp"
#include "mtcal/io/system/sha256.hpp"

namespace mtcal {

struct Machine;

// One report file: a summary block (machine, inputs with their SHA-256, date, mtcal version,
// headline figures with units, warnings), then sections of text, tables and plots. The plotting
// library is inlined, so the file opens offline. Every user-provided string is escaped. Apart
// from the date line, the same inputs give the same bytes.
class Report {
 public:
  // Starts with the session's test metadata (session_metadata()).
  Report(std::string title, std::string command);

  // Test metadata shown in a "Test" table at the top (replaces the session's).
  void set_metadata(ReportMetadata m) { metadata_ = std::move(m); }
  const ReportMetadata& metadata() const { return metadata_; }
  // Tolerances checked: a PASS/FAIL banner at the top and a table of every check (µm).
  void set_verdict(ToleranceVerdict v) { verdict_ = std::move(v); }

  void set_machine(const Machine& m);
  // The machine line as text, where no machine model is at hand (a history report: name, serial).
  void set_machine_label(std::string label) { machine_ = std::move(label); }
  // Hashes the file (SHA-256) now; throws InputError if it cannot be read.
  void add_input(const std::string& label, const std::string& path);
  // An input whose SHA-256 is known already (a recorded result's file kept in the history store).
  void add_input(const std::string& label, const std::string& path, const std::string& sha256);
  // A headline figure: value already formatted by the caller with its unit.
  void add_figure(const std::string& label, const std::string& value, const std::string& unit);
  void add_warning(const std::string& text);

  void add_section(const std::string& title);
  void add_paragraph(const std::string& text);
  // A real HTML table (copyable); cells are text.
  void add_table(const std::string& caption, const std::vector<std::string>& columns,
                 const std::vector<std::vector<std::string>>& rows);
  // A Plotly figure: {"data": [...], "layout": {...}}; caption is shown under it.
  void add_plot(const std::string& caption, nlohmann::json figure);

  std::size_t plot_count() const { return plots_; }
  // The whole document. date: the line's text (e.g. ISO 8601 UTC).
  std::string html(const std::string& date) const;
  // Writes atomically; the date is now in UTC, or SOURCE_DATE_EPOCH when it is set. Then the
  // static copies set with set_static_copies(), through the same output group.
  void write(const std::string& path) const;
  // The date line write() gives: now in UTC, or SOURCE_DATE_EPOCH when it is set ("2026-11-25 10:30:00 UTC").
  static std::string date_now();

 private:
  std::string title_, command_, machine_;
  std::vector<std::pair<std::string, std::string>> inputs_;  // label: "path (sha256)"
  std::vector<std::vector<std::string>> figures_;
  std::vector<std::string> warnings_;
  std::string body_;
  std::size_t plots_ = 0;
  ReportMetadata metadata_;
  ToleranceVerdict verdict_;
};

// Static copies of every report this process writes, for where JavaScript does not run (e-mail):
// the report printed to PDF (pdf) and each plot as a PNG file in png_dir (REPORT-plot-N.png, the
// images the page makes for printing), made by headless Chromium (io/system/headless_browser.hpp) from
// the report's HTML. They join the command's output group: all of its files appear or none.
struct StaticCopies {
  std::string pdf;      // empty: no PDF
  std::string png_dir;  // empty: no PNG files; made (create_output_directory) if missing
  std::string browser;  // the browser's executable (find_headless_browser)
  double timeout_s = 120;
  bool empty() const { return pdf.empty() && png_dir.empty(); }
};
void set_static_copies(StaticCopies copies);
const StaticCopies& static_copies();
// What a report's <noscript> note says about making those copies (HTML): the program that writes
// the report names its own way (the command its options, Python its arguments).
void set_static_copy_note(std::string html);
const std::string& static_copy_note();
// The plots' print images in a page as a browser rendered it (img.plot-print with a
// data:image/png;base64 source), decoded, in page order. Throws Error for a malformed one.
std::vector<std::string> plot_images_from_dom(std::string_view dom);
// The paths write() gives the PNG copies of a report at path with n plots, in png_dir.
std::vector<std::string> plot_image_paths(const std::string& report_path, const std::string& png_dir, std::size_t n);

// HTML text escaping of & < > " '.
std::string html_escape(std::string_view s);
// JSON text safe inside a <script> element ("</" and "<!--" cannot end it).
std::string script_safe_json(const nlohmann::json& j);
// The Plotly library bundled at build time (plotly.js-dist-min from npm).
std::string_view plotly_js();
// Plotly layout of a 3D scene in machine coordinates: x, y, z in mm at true aspect, no legend.
nlohmann::json machine_scene_layout();

}  // namespace mtcal
