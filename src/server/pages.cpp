// The HTML pages of mtcal serve (escaped output everywhere: html_escape of report/).
#include "pages.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "mtcal/evaluation/metadata.hpp"
#include "mtcal/io/compensation/output.hpp"
#include "mtcal/report/report.hpp"
#include "mtcal/version.hpp"

namespace mtcal::server {

namespace {

std::string h(std::string_view s) { return html_escape(s); }

std::string text_of(const Json& j) {
  if (j.is_string()) return j.get<std::string>();
  if (j.is_null()) return "-";
  if (j.is_number_float()) return fmt::format("{:.4g}", j.get<double>());
  return j.dump();
}

// JSON inside <script type="application/json">: "<" as \u003c, so that nothing can close the element.
std::string json_data(const std::string& id, const Json& j) {
  std::string text = j.dump();
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    if (c == '<')
      out += "\\u003c";
    else
      out += c;
  }
  return "<script type=\"application/json\" id=\"" + h(id) + "\">" + out + "</script>\n";
}

std::string csrf_field(const PageUser& u) { return "<input type=\"hidden\" name=\"csrf\" value=\"" + h(u.csrf) + "\">"; }

// A page is layout_head + its content + layout_tail.
std::string layout_head(const std::string& title, const PageUser& u, bool plots = false) {
  std::string p =
      "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
      "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">"
      "<title>" +
      h(title) +
      " - mtcal</title><link rel=\"stylesheet\" href=\"/static/style.css\">";
  if (plots) p += "<script src=\"/static/plotly.min.js\"></script>";
  p += "<script src=\"/static/app.js\" defer></script></head><body>\n<header><nav><strong>mtcal</strong>";
  if (!u.name.empty()) {
    p += " <a href=\"/fleet\">Fleet</a>";
    if (u.engineer) p += " <a href=\"/upload\">Upload</a>";
    if (u.admin) p += " <a href=\"/admin/users\">Users</a> <a href=\"/admin/machines\">Intervals</a>";
    p += "<span class=\"who\">" + h(u.name) + " (" + h(u.role) +
         ")<form method=\"post\" action=\"/logout\" class=\"inline\">" + csrf_field(u) +
         "<button type=\"submit\" id=\"logout\">Log out</button></form></span>";
  }
  p += "</nav></header>\n<main>\n<h1>" + h(title) + "</h1>\n";
  return p;
}
std::string layout_tail() { return "</main>\n<footer>mtcal " + h(version()) + "</footer></body></html>\n"; }

std::string layout(const std::string& title, const PageUser& u, const std::string& body, bool plots = false) {
  std::string p = layout_head(title, u, plots);
  p.reserve(p.size() + body.size() + 64);
  p += body;
  p += layout_tail();
  return p;
}

// The compensation targets as <option>s of a form's select.
std::string format_options() {
  std::string formats;
  for (const auto& t : compensation_targets())
    formats += "<option value=\"" + h(t.name) + "\">" + h(t.name) + " - " + h(t.description) + "</option>";
  return formats;
}

}  // namespace

std::string url_encode(const std::string& s) {
  std::string out;
  for (const unsigned char c : s) {
    if (std::isalnum(c) || c == '-' || c == '_' || c == '.' || c == '~')
      out += static_cast<char>(c);
    else
      out += fmt::format("%{:02X}", c);
  }
  return out;
}

std::string error_page(int status, const std::string& message) {
  return layout(fmt::format("Error {}", status), {},
                "<p class=\"error\">" + h(message) + "</p><p><a href=\"/fleet\">Fleet</a> · <a href=\"/login\">Log in</a></p>");
}

std::string login_page(const std::string& csrf, const std::string& error) {
  std::string b;
  if (!error.empty()) b += "<p class=\"error\" id=\"login-error\">" + h(error) + "</p>";
  b += "<form method=\"post\" action=\"/login\" class=\"stack\"><input type=\"hidden\" name=\"csrf\" value=\"" + h(csrf) +
       "\"><label>User <input name=\"user\" id=\"user\" autocomplete=\"username\" required></label>"
       "<label>Password <input name=\"password\" id=\"password\" type=\"password\" autocomplete=\"current-password\" "
       "required></label><button type=\"submit\" id=\"login\">Log in</button></form>";
  return layout("Log in", {}, b);
}

std::string fleet_machine_rows(const Json& m, bool ranked) {
  const std::string name = m["machine"].get<std::string>();
  std::string rank_cells;
  if (ranked) {
    const Json& r = m["rank"];
    if (r.is_null()) {
      rank_cells = "<td>-</td><td>-</td><td>no quantity with a tolerance</td><td>-</td><td>-</td>";
    } else {
      const Json& q = r["quantities"][0];
      std::string drift = text_of(r["drift"]);
      std::replace(drift.begin(), drift.end(), '_', ' ');
      if (q["rate_per_year"].is_number())
        drift = fmt::format("{:.3g} {}/year, {}", q["rate_per_year"].get<double>(), text_of(q["unit"]), drift);
      rank_cells = fmt::format(
          "<td class=\"num\">{}</td><td class=\"num\">{:.0f}</td><td>{} {} {}</td><td>{}</td><td>{}</td>",
          r["rank"].get<long long>(), 100 * r["utilisation"].get<double>(), h(text_of(q["quantity"])),
          h(text_of(q["latest"])), h(text_of(q["unit"])), h(drift),
          r["outside"].get<bool>() ? std::string("outside now") : h(text_of(r["out_of_tolerance_on"])));
    }
  }
  std::string b;
  for (const auto& c : m["calibrations"]) {
    const bool late = c["overdue"].get<bool>();
    b += fmt::format(
        "<tr class=\"{}\"><td><a href=\"/machine?name={}\">{}</a></td><td>{}</td><td><a href=\"/record?id={}\">{}</a></td>"
        "<td class=\"num\">{}</td><td class=\"num\">{}{}</td><td class=\"num\">{}</td><td>{}</td>{}</tr>\n",
        late ? "overdue" : "", h(url_encode(name)), h(name), h(text_of(c["command"])),
        h(url_encode(text_of(c["record"]))), h(text_of(c["last"])),
        c["age_days"].is_null() ? "-" : fmt::format("{:.0f}", c["age_days"].get<double>()),
        m["interval_days"].get<int>(), m["interval_own"].get<bool>() ? "" : " (default)", c["count"].get<long long>(),
        late ? "overdue" : "ok", rank_cells);
  }
  return b;
}

std::string fleet_page_body(const Json& fleet, std::size_t machines, std::size_t overdue, std::string_view rows) {
  const bool ranked = fleet["ranked"].get<bool>();
  std::string b = fmt::format(
      "<p id=\"summary\">{} machines, {} overdue.</p>"
      "<p>Store <code>{}</code>. A machine is overdue {} days after its last calibration of a kind, unless it has an "
      "interval of its own.{}</p>"
      "<p><label>Filter <input id=\"filter\" data-table=\"fleet\" placeholder=\"machine, kind, overdue\"></label></p>",
      machines, overdue, h(text_of(fleet["store"])), fleet["interval_days"].get<int>(),
      ranked ? " Share of tolerance used, drift and the date out of tolerance are <code>mtcal history rank</code>'s "
               "(the deciding quantity: the largest share used)."
             : " No tolerances given (<code>mtcal serve --tolerance-file</code>): no ranking.");
  for (const auto& n : fleet["rank_notes"]) b += "<p class=\"note\">" + h(text_of(n)) + "</p>";
  b += "<div class=\"wide\"><table id=\"fleet\" class=\"data sortable\"><thead><tr><th>Machine</th><th>Test</th>"
       "<th>Last</th><th>Age (days)</th><th>Interval (days)</th><th>Records</th><th>State</th>";
  if (ranked) b += "<th>Rank</th><th>Tolerance used (%)</th><th>Deciding quantity</th><th>Drift</th><th>Out of tolerance</th>";
  b += "</tr></thead><tbody>\n";
  b.reserve(b.size() + rows.size() + 32);
  b += rows;
  b += "</tbody></table></div>\n";
  return b;
}

std::string fleet_page(const PageUser& u, const std::string& body) { return layout("Fleet", u, body); }
std::pair<std::string, std::string> fleet_page_frame(const PageUser& u) { return {layout_head("Fleet", u), layout_tail()}; }

std::string machine_page(const PageUser& u, const Json& m, const Json& trends) {
  const std::string name = m["machine"].get<std::string>();
  std::string b = "<p>Serial " + h(text_of(m["serial"])) + " · <a href=\"/machine/trend?name=" + h(url_encode(name)) +
                  "\" id=\"trend-link\">Timeline report (history trend)</a> · <a href=\"/api/machine?name=" +
                  h(url_encode(name)) + "\">JSON</a></p>\n";
  // Plots of the figures over time (Plotly, drawn by app.js from the data element).
  Json figs = Json::array();
  for (const auto& s : trends["series"])
    if (s["kind"] == "figure") figs.push_back(s);
  b += json_data("trend-data", {{"series", figs}, {"events", trends["events"]}});
  b += "<div id=\"plots\" class=\"plots\"></div>\n";
  b += "<h2>Calibrations</h2><div class=\"wide\"><table id=\"records\" class=\"data sortable\"><thead><tr><th>Measured</th>"
       "<th>Test</th><th>Figures</th><th>Recorded by</th><th>Record</th></tr></thead><tbody>\n";
  std::string options;
  for (const auto& r : m["records"]) {
    std::string f;
    for (const auto& [k, v] : r["figures"].items())
      f += (f.empty() ? "" : ", ") + h(k) + " " + h(text_of(v["value"])) + " " + h(text_of(v["unit"]));
    const std::string id = r["id"].get<std::string>();
    b += "<tr><td>" + h(text_of(r["measured_at"])) + "</td><td>" + h(text_of(r["command"])) + "</td><td>" + f +
         "</td><td>" + h(text_of(r["recorded_by"])) + "</td><td><a href=\"/record?id=" + h(url_encode(id)) + "\">" +
         h(id) + "</a></td></tr>\n";
    options += "<option value=\"" + h(id) + "\">" + h(text_of(r["measured_at"])) + " " + h(text_of(r["command"])) + " (" +
               h(id) + ")</option>";
  }
  b += "</tbody></table></div>\n";
  b += "<h2>Compare two calibrations</h2><form method=\"get\" action=\"/diff\" class=\"row\"><label>Before <select "
       "name=\"a\">" +
       options + "</select></label><label>After <select name=\"b\">" + options +
       "</select></label><button type=\"submit\">Diff</button></form>\n";
  b += "<h2>Events</h2><div class=\"wide\"><table id=\"events\" class=\"data\"><thead><tr><th>Date</th><th>Kind</th>"
       "<th>Note</th><th>Added by</th></tr></thead><tbody>\n";
  for (const auto& e : m["events"])
    b += "<tr><td>" + h(text_of(e["date"])) + "</td><td>" + h(text_of(e["kind"])) + "</td><td>" + h(text_of(e["note"])) +
         "</td><td>" + h(text_of(e["added_by"])) + "</td></tr>\n";
  b += "</tbody></table></div>\n";
  if (u.engineer) {
    b += "<h2>Add an event</h2><form method=\"post\" action=\"/events\" class=\"stack\" id=\"event-form\">" +
         csrf_field(u) + "<input type=\"hidden\" name=\"machine\" value=\"" + h(name) +
         "\"><label>Date <input name=\"date\" id=\"event-date\" placeholder=\"2026-11-27\" required></label>"
         "<label>Kind <select name=\"kind\" id=\"event-kind\"><option>compensation-loaded</option><option>crash</option>"
         "<option>repair</option><option>other</option></select></label><label>Note <input name=\"note\" "
         "id=\"event-note\"></label><button type=\"submit\" id=\"event-add\">Add event</button></form>\n";
    b += "<p><a href=\"/upload?machine=" + h(url_encode(name)) + "\">Upload a measurement of this machine</a></p>";
    // write compensation: what `mtcal compensate -m MACHINE --params P --format F --out DIR` writes, as DIR.zip.
    const std::string formats = format_options();
    b += "<h2>Write compensation</h2><p>The files <code>mtcal compensate -m MACHINE --params PARAMS --format F --out "
         "DIR</code> writes, downloaded as a zip of DIR (docs/compensation.md).</p><form method=\"post\" "
         "action=\"/machine/compensation\" enctype=\"multipart/form-data\" class=\"stack\" id=\"comp-form\">" +
         csrf_field(u) +
         "<label>Machine file (YAML) <input type=\"file\" name=\"machine_file\" id=\"comp-machine\" required></label>"
         "<label>Parameter file (identify --out; optional) <input type=\"file\" name=\"params\" id=\"comp-params\">"
         "</label><label>Controller <select name=\"format\" id=\"comp-format\">" +
         formats +
         "</select></label><label>Positions per table (optional) <input name=\"points\" id=\"comp-points\"></label>"
         "<button type=\"submit\" id=\"comp-write\">Write compensation (zip)</button></form>\n";
    // From a recorded result (identify, fit-motion ...): its machine and parameter files from the
    // store with its estimated parameters applied (the server says when the store lacks them).
    std::string recorded;
    for (const auto& r : m["records"])
      if (r["parameters"].is_number() && r["parameters"].get<long long>() > 0)
        recorded = "<option value=\"" + h(text_of(r["id"])) + "\">" + h(text_of(r["measured_at"])) + " " +
                   h(text_of(r["command"])) + " (" + h(text_of(r["id"])) + ")</option>" + recorded;  // newest first
    if (!recorded.empty())
      b += "<h3>From a recorded result</h3><p>The record's machine file and parameter files, held in the store, with "
           "its estimated parameters applied.</p><form method=\"post\" action=\"/machine/compensation\" "
           "enctype=\"multipart/form-data\" class=\"stack\" id=\"rec-comp-form\">" +
           csrf_field(u) + "<label>Record <select name=\"record\" id=\"rec-comp-record\">" + recorded +
           "</select></label><label>Controller <select name=\"format\" id=\"rec-comp-format\">" + formats +
           "</select></label><button type=\"submit\" id=\"rec-comp-write\">Write compensation (zip)</button></form>\n";
  }
  return layout("Machine " + name, u, b, true);
}

std::string record_page(const PageUser& u, const CalibrationRecord& r, const std::vector<AuditEntry>& audit,
                        const std::map<std::string, std::string>& model_kinds, const std::string& report_missing) {
  std::string b = "<table class=\"meta\"><tr><th>Machine</th><td><a href=\"/machine?name=" +
                  h(url_encode(r.machine_name)) + "\">" + h(r.machine_name) + "</a></td></tr><tr><th>Test</th><td>" +
                  h(r.command) + "</td></tr><tr><th>Measured</th><td>" + h(r.measured_at) +
                  "</td></tr><tr><th>Recorded</th><td>" + h(r.recorded_at) + "</td></tr>";
  for (const auto& a : audit) b += "<tr><th>Recorded by</th><td>" + h(a.user) + " (" + h(a.at) + ")</td></tr>";
  for (const auto& [k, v] : r.metadata)
    b += "<tr><th>" + h(metadata_label(k)) + "</th><td>" + h(v) + "</td></tr>";
  bool machine_held = false;
  for (const auto& i : r.inputs) {
    const auto kind = model_kinds.find(i.sha256);
    if (kind != model_kinds.end() && kind->second == "machine") machine_held = true;
    b += "<tr><th>Input</th><td>" + h(i.path) + " <code>" + h(i.sha256) + "</code>" +
         (kind == model_kinds.end() ? std::string() : " (" + h(kind->second) + " file, held in the store)") +
         "</td></tr>";
  }
  b += "</table>\n<h2>Figures</h2><div class=\"wide\"><table class=\"data\"><thead><tr><th>Name</th><th>Value</th>"
       "<th>Unit</th><th>u</th></tr></thead><tbody>";
  for (const auto& f : r.figures)
    b += "<tr><td>" + h(f.name) + "</td><td class=\"num\">" + h(fmt::format("{:.4g}", f.value)) + "</td><td>" + h(f.unit) +
         "</td><td>" + (f.uncertainty ? h(fmt::format("{:.3g}", *f.uncertainty)) : "-") + "</td></tr>";
  b += "</tbody></table></div><h2>Parameters</h2><div class=\"wide\"><table class=\"data\"><thead><tr><th>Name</th>"
       "<th>Value</th><th>Unit</th><th>u</th></tr></thead><tbody>";
  for (const auto& p : r.parameters)
    b += "<tr><td>" + h(p.name) + "</td><td class=\"num\">" + h(fmt::format("{:.4g}", p.value)) + "</td><td>" + h(p.unit) +
         "</td><td>" + (p.uncertainty ? h(fmt::format("{:.3g}", *p.uncertainty)) : "-") + "</td></tr>";
  b += "</tbody></table></div>";
  // The command's own --report, made from the measurement file the store holds (/record/report).
  b += "<h2>Report</h2>";
  if (report_missing.empty()) {
    b += "<p id=\"report-link\"><a href=\"/record/report?id=" + h(url_encode(r.id)) + "\">The report of <code>mtcal " +
         h(r.command) + " --report</code></a>, made from the measurement file held in the store with the command's "
         "options, as the command wrote it.";
  } else {
    b += "<p id=\"report-why\">The report of <code>mtcal " + h(r.command) + " --report</code> is not shown: " +
         h(report_missing) + ". Run the command with <code>--report</code> on its files; the <a "
         "href=\"/machine/trend?name=" + h(url_encode(r.machine_name)) +
         "\">timeline report</a> shows this record among the machine's.";
  }
  b += "</p>";
  if (u.engineer) {
    b += "<h2>Write compensation</h2>";
    if (machine_held) {
      b += "<p>The files <code>mtcal compensate -m MACHINE --params PARAMS... --format F --out DIR</code> writes for this "
           "record's model: its machine file and parameter files from the store"
           " with its estimated parameters applied, as a zip of DIR.</p><form method=\"post\" "
           "action=\"/machine/compensation\" enctype=\"multipart/form-data\" class=\"stack\" id=\"rec-comp-form\">" +
           csrf_field(u) + "<input type=\"hidden\" name=\"record\" value=\"" + h(r.id) +
           "\"><label>Controller <select name=\"format\" id=\"rec-comp-format\">" + format_options() +
           "</select></label><label>Positions per table (optional) <input name=\"points\"></label>"
           "<button type=\"submit\" id=\"rec-comp-write\">Write compensation (zip)</button></form>\n";
    } else {
      b += "<p id=\"rec-comp-why\">Not from this record: the store holds no machine file of it (none of its inputs is "
           "a stored model file; records made before schema version 5 or by a command without <code>-m</code> hold "
           "none). Write compensation from a machine file on the <a href=\"/machine?name=" +
           h(url_encode(r.machine_name)) + "\">machine page</a>.</p>";
    }
  }
  b += "<p><a href=\"/api/record?id=" + h(url_encode(r.id)) + "\">JSON of the record</a></p>";
  return layout("Record " + r.id, u, b);
}

std::string diff_page(const PageUser& u, const Json& d) {
  std::string b = "<p>" + h(text_of(d["machines"][0])) + " " + h(text_of(d["measured_at"][0])) + " → " +
                  h(text_of(d["machines"][1])) + " " + h(text_of(d["measured_at"][1])) +
                  ". Significant when |E<sub>n</sub>| &gt; 1, E<sub>n</sub> = change / sqrt(U1² + U2²), U = 2u.</p>";
  for (const char* part : {"parameters", "figures"}) {
    if (!d.contains(part) || !d[part].contains("changes")) continue;
    b += std::string("<h2>") + part + "</h2><div class=\"wide\"><table class=\"data\"><thead><tr>";
    std::vector<std::string> cols;
    for (const auto& c : d[part]["changes"]) {
      for (const auto& [k, v] : c.items())
        if (std::find(cols.begin(), cols.end(), k) == cols.end()) cols.push_back(k);
    }
    for (const auto& c : cols) b += "<th>" + h(c) + "</th>";
    b += "</tr></thead><tbody>";
    for (const auto& c : d[part]["changes"]) {
      b += "<tr>";
      for (const auto& k : cols) b += "<td>" + (c.contains(k) ? h(text_of(c[k])) : std::string()) + "</td>";
      b += "</tr>";
    }
    b += "</tbody></table></div>";
  }
  return layout("Diff", u, b);
}

std::string upload_page(const PageUser& u, const std::string& machine) {
  std::string b =
      "<p>An instrument file evaluated as its command does, with these fields as the record's metadata (the "
      "<code>--meta</code> keys); nothing is recorded before you confirm. ISO 230-2 runs (.dat, CSV in mm, Renishaw "
      ".rtl/.rta) as <code>mtcal history import FILE</code>; a ballbar trace as <code>mtcal ballbar TRACE --radius R "
      "--plane P</code>; probe contacts as <code>mtcal rotary-axis --axis A --contacts FILE --sphere-diameter D "
      "--stylus-diameter d</code>.</p>"
      "<form method=\"post\" action=\"/upload\" enctype=\"multipart/form-data\" class=\"stack\" id=\"upload-form\">" +
      csrf_field(u) +
      "<label>Kind <select name=\"kind\" id=\"upload-kind\"><option value=\"iso230-2\">ISO 230-2 positioning "
      "(.dat, .csv, .rtl, .rta)</option><option value=\"ballbar\">Ballbar trace, ISO 230-4 (.csv)</option><option "
      "value=\"rotary-axis\">Probe contacts on a sphere, rotary axis (.csv)</option></select></label>"
      "<label>File <input type=\"file\" name=\"file\" id=\"upload-file\" required></label>"
      "<fieldset><legend>Ballbar</legend><label>Radius, mm <input name=\"radius\" id=\"bb-radius\"></label>"
      "<label>Plane <select name=\"plane\"><option>XY</option><option>YZ</option><option>ZX</option></select></label>"
      "<label>Feed, mm/min (optional) <input name=\"feed\"></label></fieldset>"
      "<fieldset><legend>Probe contacts</legend><label>Rotary axis <select name=\"rotary_axis\"><option>C</option>"
      "<option>A</option><option>B</option></select></label><label>Sphere diameter, mm <input "
      "name=\"sphere_diameter\"></label><label>Stylus diameter, mm <input name=\"stylus_diameter\" "
      "value=\"0\"></label></fieldset>";
  for (const auto& f : metadata_fields()) {
    const std::string key(f.key);
    const std::string value = key == "machine" ? machine : "";
    b += "<label>" + h(f.label) + " <input name=\"" + h(key) + "\" id=\"meta-" + h(key) + "\" value=\"" + h(value) +
         "\"" + (key == "machine" ? " required" : "") + "></label>";
  }
  b += "<button type=\"submit\" id=\"upload-evaluate\">Evaluate</button></form>";
  return layout("Upload", u, b);
}

std::string upload_preview_page(const PageUser& u, const CalibrationRecord& r, const Json& result,
                                const std::string& token) {
  std::string b = "<p>Machine <strong>" + h(r.machine_name) + "</strong>, measured " + h(r.measured_at) +
                  ", file " + h(r.inputs.empty() ? "" : r.inputs.front().path) + ".</p>";
  b += "<div class=\"wide\"><table class=\"data\" id=\"preview\"><thead><tr><th>Figure</th><th>Value</th><th>Unit</th>"
       "</tr></thead><tbody>";
  for (const auto& f : r.figures)
    b += "<tr><td>" + h(f.name) + "</td><td class=\"num\">" + h(fmt::format("{:.4g}", f.value)) + "</td><td>" + h(f.unit) +
         "</td></tr>";
  b += "</tbody></table></div>";
  if (result.contains("warnings") && !result["warnings"].empty()) {
    b += "<ul class=\"warnings\">";
    for (const auto& w : result["warnings"]) b += "<li>" + h(text_of(w)) + "</li>";
    b += "</ul>";
  }
  b += "<form method=\"post\" action=\"/upload/confirm\">" + csrf_field(u) +
       "<input type=\"hidden\" name=\"token\" value=\"" + h(token) +
       "\"><button type=\"submit\" id=\"upload-confirm\">Record</button></form><p><a href=\"/upload\">Cancel</a></p>";
  return layout("Upload: check before recording", u, b);
}

std::string users_page(const PageUser& u, const std::vector<UserAccount>& users) {
  std::string b = "<div class=\"wide\"><table class=\"data\"><thead><tr><th>User</th><th>Role</th><th>Since</th></tr>"
                  "</thead><tbody>";
  for (const auto& x : users)
    b += "<tr><td>" + h(x.name) + "</td><td>" + h(x.role) + "</td><td>" + h(x.created_at) + "</td></tr>";
  b += "</tbody></table></div><h2>Add or change a user</h2><form method=\"post\" action=\"/admin/users\" "
       "class=\"stack\">" +
       csrf_field(u) +
       "<label>User <input name=\"user\" required></label><label>Role <select name=\"role\"><option>viewer</option>"
       "<option>engineer</option><option>admin</option></select></label><label>Password (10 characters or more) <input "
       "name=\"password\" type=\"password\" autocomplete=\"new-password\" required></label><button "
       "type=\"submit\">Save</button></form>";
  return layout("Users", u, b);
}

std::string machines_page(const PageUser& u, const std::vector<std::string>& machines,
                          const std::vector<MachineInterval>& intervals, int default_days) {
  std::string b = fmt::format(
      "<p>A machine's calibrations are overdue this many days after the latest of each kind; without an interval of "
      "its own, {} days (<code>mtcal serve --interval-days</code>).</p><div class=\"wide\"><table class=\"data\" "
      "id=\"intervals\"><thead><tr><th>Machine</th><th>Interval (days)</th><th>Set by</th><th>Set at</th></tr></thead>"
      "<tbody>",
      default_days);
  std::string options;
  for (const auto& m : machines) {
    const auto i = std::find_if(intervals.begin(), intervals.end(), [&](const MachineInterval& x) { return x.machine == m; });
    b += "<tr><td>" + h(m) + "</td><td class=\"num\">" +
         (i == intervals.end() ? fmt::format("{} (default)", default_days) : std::to_string(i->days)) + "</td><td>" +
         (i == intervals.end() ? "" : h(i->set_by)) + "</td><td>" + (i == intervals.end() ? "" : h(i->set_at)) +
         "</td></tr>";
    options += "<option value=\"" + h(m) + "\">" + h(m) + "</option>";
  }
  b += "</tbody></table></div><h2>Set an interval</h2><form method=\"post\" action=\"/admin/machines\" "
       "class=\"stack\" id=\"interval-form\">" +
       csrf_field(u) + "<label>Machine <select name=\"machine\" id=\"interval-machine\">" + options +
       "</select></label><label>Days (0: the default) <input name=\"days\" id=\"interval-days\" required></label>"
       "<button type=\"submit\" id=\"interval-save\">Save</button></form>";
  return layout("Calibration intervals", u, b);
}

const std::string& style_css() {
  static const std::string css = R"(*{box-sizing:border-box}
body{font:15px/1.4 system-ui,sans-serif;margin:0;color:#1b1f24;background:#fafafa}
header{background:#1f3b57;color:#fff;padding:.5rem 1rem}
header a{color:#fff;margin-right:.8rem}
nav{display:flex;flex-wrap:wrap;align-items:center;gap:.4rem}
nav strong{margin-right:1rem}
.who{margin-left:auto;display:flex;gap:.5rem;align-items:center;flex-wrap:wrap}
main{padding:1rem;max-width:1240px;margin:0 auto}
footer{color:#777;font-size:12px;padding:1rem;text-align:center}
h1{font-size:1.4rem;overflow-wrap:anywhere}
.wide{overflow-x:auto;max-width:100%}
table.data{border-collapse:collapse;width:100%}
table.data th,table.data td{border-bottom:1px solid #ddd;padding:.3rem .5rem;text-align:left;vertical-align:top;overflow-wrap:anywhere}
table.data th{background:#eef2f6;cursor:pointer}
td.num{text-align:right;font-variant-numeric:tabular-nums}
tr.overdue td{background:#fdecea}
.note{color:#6b4e00}
fieldset{border:1px solid #ccd;display:flex;flex-direction:column;gap:.4rem}
table.meta th{text-align:left;padding-right:1rem}
table.meta td{overflow-wrap:anywhere}
.error{color:#a40000;font-weight:bold}
form.stack{display:flex;flex-direction:column;gap:.5rem;max-width:32rem}
form.stack label{display:flex;flex-direction:column}
form.row{display:flex;flex-wrap:wrap;gap:.5rem;align-items:end}
form.row select{max-width:100%}
form.inline{display:inline}
input,select,button{font:inherit;max-width:100%}
.plots{display:grid;grid-template-columns:repeat(auto-fill,minmax(min(100%,560px),1fr));gap:.5rem}
.plots{overflow:hidden;max-width:100%}
.plot{height:300px;min-width:0;max-width:100%;overflow:hidden}
form.row label{min-width:0;max-width:100%}
form.row select{width:100%}
code{overflow-wrap:anywhere}
)";
  return css;
}

const std::string& app_js() {
  static const std::string js = R"((function () {
  'use strict';
  // Sortable tables: a click on a header sorts by that column (numbers as numbers).
  document.querySelectorAll('table.sortable').forEach(function (table) {
    table.querySelectorAll('th').forEach(function (th, col) {
      var asc = true;
      th.addEventListener('click', function () {
        var body = table.tBodies[0];
        var rows = Array.prototype.slice.call(body.rows);
        rows.sort(function (a, b) {
          var x = a.cells[col].textContent, y = b.cells[col].textContent;
          var nx = parseFloat(x), ny = parseFloat(y);
          var c = (!isNaN(nx) && !isNaN(ny)) ? nx - ny : x.localeCompare(y);
          return asc ? c : -c;
        });
        asc = !asc;
        rows.forEach(function (r) { body.appendChild(r); });
      });
    });
  });
  // Filter: rows whose text contains what is typed.
  var filter = document.getElementById('filter');
  if (filter) {
    filter.addEventListener('input', function () {
      var table = document.getElementById(filter.dataset.table);
      var q = filter.value.toLowerCase();
      Array.prototype.forEach.call(table.tBodies[0].rows, function (r) {
        r.style.display = r.textContent.toLowerCase().indexOf(q) >= 0 ? '' : 'none';
      });
    });
  }
  // Plots of a machine's figures over time, events as vertical lines.
  var data = document.getElementById('trend-data');
  var box = document.getElementById('plots');
  if (data && box && window.Plotly) {
    var d = JSON.parse(data.textContent);
    d.series.forEach(function (s, i) {
      var div = document.createElement('div');
      div.className = 'plot';
      div.id = 'plot-' + i;
      box.appendChild(div);
      var x = s.samples.map(function (p) { return p.measured_at; });
      var y = s.samples.map(function (p) { return p.value; });
      var err = s.samples.map(function (p) { return p.u === null ? 0 : 2 * p.u; });
      var shapes = d.events.map(function (e) {
        return {type: 'line', xref: 'x', yref: 'paper', x0: e.date, x1: e.date, y0: 0, y1: 1,
                line: {color: '#a40000', width: 1, dash: 'dot'}};
      });
      Plotly.newPlot(div, [{x: x, y: y, mode: 'lines+markers', name: s.quantity,
                            error_y: {type: 'data', array: err, visible: true}}],
                     {title: {text: s.quantity + ' (' + s.unit + ')'}, margin: {l: 50, r: 10, t: 40, b: 40},
                      shapes: shapes, autosize: true},
                     {responsive: true, displaylogo: false});
    });
  }
})();
)";
  return js;
}

}  // namespace mtcal::server
