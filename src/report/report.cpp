#include "mtcal/report/report.hpp"

#include <array>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <optional>

#include <fmt/format.h>

#include "mtcal/io/system/files.hpp"
#include "mtcal/io/system/headless_browser.hpp"
#include "mtcal/io/json/json.hpp"
#include "mtcal/model/machine.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/version.hpp"

extern "C" const char mtcal_plotly_js_begin[];
extern "C" const char mtcal_plotly_js_end[];

namespace mtcal {

nlohmann::json machine_scene_layout() {
  return {{"scene",
           {{"xaxis", {{"title", {{"text", "x (mm)"}}}}},
            {"yaxis", {{"title", {{"text", "y (mm)"}}}}},
            {"zaxis", {{"title", {{"text", "z (mm)"}}}}},
            {"aspectmode", "data"},
            // Plotly's default eye (1.25, 1.25, 1.25) crops the corners of a long workspace at
            // a 1280x800 window; from further out the whole scene and its tick labels show.
            {"camera", {{"eye", {{"x", 1.7}, {"y", 1.7}, {"z", 1.2}}}}}}},
          {"showlegend", false}};
}

std::string_view plotly_js() {
  return {mtcal_plotly_js_begin, static_cast<std::size_t>(mtcal_plotly_js_end - mtcal_plotly_js_begin)};
}

std::string html_escape(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string script_safe_json(const nlohmann::json& j) {
  // json_text escapes control characters and replaces bytes that are not UTF-8; "<" is escaped
  // too so that no "</script" or "<!--" in a user string can end the script element (JSON allows
  // \u003c anywhere in a string).
  const std::string text = json_text(j);
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    if (c == '<')
      out += "\\u003c";
    else
      out += c;
  }
  return out;
}

Report::Report(std::string title, std::string command)
    : title_(std::move(title)), command_(std::move(command)), metadata_(session_metadata()) {}

void Report::set_machine(const Machine& m) {
  machine_ = m.name + " (" + m.topology.chain + ")";
  if (!m.source.empty()) add_input("machine file", m.source);
}

void Report::add_input(const std::string& label, const std::string& path) {
  add_input(label, path, sha256_hex(read_text_file(path, label)));
}

void Report::add_input(const std::string& label, const std::string& path, const std::string& sha256) {
  inputs_.emplace_back(label, path + "  (SHA-256 " + sha256 + ")");
}

void Report::add_figure(const std::string& label, const std::string& value, const std::string& unit) {
  figures_.push_back({label, value, unit});
}

void Report::add_warning(const std::string& text) { warnings_.push_back(text); }

void Report::add_section(const std::string& title) { body_ += "<h2>" + html_escape(title) + "</h2>\n"; }

void Report::add_paragraph(const std::string& text) { body_ += "<p>" + html_escape(text) + "</p>\n"; }

void Report::add_table(const std::string& caption, const std::vector<std::string>& columns,
                       const std::vector<std::vector<std::string>>& rows) {
  std::string t =
      "<div class=\"wide\"><table class=\"data\">\n<caption>" + html_escape(caption) + "</caption>\n<thead><tr>";
  for (const auto& c : columns) t += "<th>" + html_escape(c) + "</th>";
  t += "</tr></thead>\n<tbody>\n";
  for (const auto& r : rows) {
    t += "<tr>";
    for (const auto& c : r) t += "<td>" + html_escape(c) + "</td>";
    t += "</tr>\n";
  }
  body_ += t + "</tbody>\n</table></div>\n";
}

void Report::add_plot(const std::string& caption, nlohmann::json figure) {
  const std::string id = fmt::format("plot-{}", ++plots_);
  auto& layout = figure["layout"];
  if (!layout.contains("margin")) layout["margin"] = {{"l", 60}, {"r", 20}, {"t", 40}, {"b", 50}};
  // 3D scenes get a taller box so that the scene is not squeezed into a strip.
  const bool scene = layout.contains("scene");
  body_ += fmt::format("<figure><div class=\"plot{}\" id=\"{}\"></div><figcaption>{}</figcaption></figure>\n",
                       scene ? " scene" : "", id, html_escape(caption));
  body_ += fmt::format(
      "<script>(function(){{var "
      "f={};Plotly.newPlot('{}',f.data,f.layout,{{responsive:true,displaylogo:false}}).then(mtcalSeparateLabels)"
      ".then(mtcalPrintImage);}})();"
      "</script>\n",
      script_safe_json(figure), id);
}

std::string Report::html(const std::string& date) const {
  std::string h;
  h += "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  h += "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n";
  h += "<title>" + html_escape(title_) + " - mtcal</title>\n";
  h += R"(<style>
body { font-family: system-ui, -apple-system, "Segoe UI", Roboto, sans-serif; margin: 2em auto; max-width: 1100px; color: #222; padding: 0 1em; }
h1 { font-size: 1.6em; margin-bottom: 0.2em; } h2 { font-size: 1.25em; margin-top: 2em; border-bottom: 1px solid #ccc; }
table { border-collapse: collapse; margin: 0.8em 0; } td, th { border: 1px solid #ccc; padding: 0.25em 0.6em; text-align: left; }
table.data td { font-variant-numeric: tabular-nums; } caption { text-align: left; font-weight: 600; padding: 0.3em 0; }
th { background: #f3f3f3; } .summary th { width: 12em; } .figures td.value { text-align: right; font-weight: 600; }
.warnings { background: #fff4e5; border-left: 4px solid #f0a020; padding: 0.5em 1em; }
.plot { width: 100%; height: clamp(320px, 62vh, 560px); } .plot.scene { height: clamp(420px, 80vh, 720px); }
figure { margin: 1em 0; } figcaption { color: #555; font-size: 0.9em; }
.plot-print { display: none; } .wide { overflow-x: auto; }
.verdict { font-size: 1.6em; font-weight: 700; padding: 0.35em 0.8em; margin: 0.5em 0 1em; border-radius: 4px; color: #fff; }
.verdict span { font-size: 0.55em; font-weight: 400; margin-left: 1em; }
.verdict.pass { background: #1a7f37; } .verdict.fail { background: #c62828; } tr.fail td { color: #c62828; font-weight: 600; }
footer { margin-top: 3em; color: #777; font-size: 0.85em; }
@media print {
  @page { size: A4; margin: 12mm; }
  body { max-width: none; margin: 0; padding: 0; font-size: 10pt; }
  * { -webkit-print-color-adjust: exact; print-color-adjust: exact; }
  figure.has-print .plot { display: none; }
  .plot-print { display: block; width: 100%; height: auto; max-height: 240mm; object-fit: contain; }
  figure, .verdict, .warnings, tr { break-inside: avoid; } h2 { break-after: avoid; }
  table { font-size: 8.5pt; } .wide { overflow: visible; }
}
</style>
)";
  // Where scripts do not run (an e-mail reader) the plots cannot be drawn: their empty boxes are
  // hidden and a note says where the numbers are and how to get a static copy.
  if (plots_ > 0) h += "<noscript><style>.plot { display: none; }</style></noscript>\n";
  h += "<script>";
  h += plotly_js();
  h += "</script>\n";
  // A static PNG of every plot, made once it has rendered, shown instead of the interactive plot
  // when printing: a 3D (WebGL) scene prints blank and an SVG sized for the screen is cropped on
  // paper. mtcalPending counts the images still being made (the browser test waits for 0).
  h += R"(<script>
// Labels (annotations) that overlap once drawn are moved up, each past the labels before it,
// in one relayout: the plots place their labels apart, and this holds for any size of text.
function mtcalSeparateLabels(gd) {
  var nodes = gd.querySelectorAll('g.annotation');
  if (nodes.length < 2) return Promise.resolve(gd);
  var placed = [], shifts = {};
  Array.prototype.forEach.call(nodes, function (node) {
    var i = Number(node.getAttribute('data-index')), r = node.getBoundingClientRect();
    var box = {left: r.left, right: r.right, top: r.top, bottom: r.bottom}, dy = 0, moved = true;
    while (moved) {
      moved = false;
      placed.forEach(function (p) {
        if (box.left < p.right && p.left < box.right && box.top < p.bottom && p.top < box.bottom) {
          var up = box.bottom - p.top + 2;
          box.top -= up; box.bottom -= up; dy += up; moved = true;
        }
      });
    }
    placed.push(box);
    if (dy > 0) shifts['annotations[' + i + '].yshift'] = ((gd.layout.annotations[i] || {}).yshift || 0) + dy;
  });
  return Object.keys(shifts).length ? Plotly.relayout(gd, shifts) : Promise.resolve(gd);
}
window.mtcalPending = 0;
function mtcalPrintImage(gd) {
  window.mtcalPending++;
  var w = 1100, h = Math.round(w * gd.clientHeight / Math.max(gd.clientWidth, 1));
  return Plotly.toImage(gd, {format: 'png', width: w, height: Math.min(Math.max(h, 400), 1300), scale: 2})
    .then(function (url) {
      var img = document.createElement('img');
      img.className = 'plot-print';
      img.alt = 'static image of the plot above, for printing';
      img.src = url;
      gd.parentNode.insertBefore(img, gd.nextSibling);
      gd.parentNode.classList.add('has-print');
    })
    .catch(function (e) { console.warn('mtcal: no static image of ' + gd.id + ': ' + e); })
    .finally(function () { window.mtcalPending--; });
}
</script>
</head>
<body>
)";
  h += "<h1>" + html_escape(title_) + "</h1>\n";
  if (plots_ > 0)
    h += fmt::format(
        "<noscript><div class=\"warnings noscript\"><strong>JavaScript is off here</strong>: the {} plot{} of this "
        "report cannot be drawn; every number is in the tables. {}</div></noscript>\n",
        plots_, plots_ == 1 ? "" : "s", static_copy_note());
  if (!verdict_.empty()) {
    std::size_t failed = 0;
    for (const auto& c : verdict_.checks) failed += c.pass ? 0 : 1;
    h += verdict_.pass()
             ? fmt::format(
                   "<div class=\"verdict pass\">PASS <span>every one of the {} quantities checked is within "
                   "its tolerance</span></div>\n",
                   verdict_.checks.size())
             : fmt::format(
                   "<div class=\"verdict fail\">FAIL <span>{} of the {} quantities checked exceed their "
                   "tolerance</span></div>\n",
                   failed, verdict_.checks.size());
  }
  if (!metadata_.empty()) {
    h += "<table class=\"summary metadata\"><caption>Test</caption>\n";
    for (const auto& [k, v] : metadata_.entries())
      h += "<tr><th>" + html_escape(metadata_label(k)) + "</th><td>" + html_escape(v) + "</td></tr>\n";
    h += "</table>\n";
  }
  h += "<table class=\"summary\">\n";
  if (!machine_.empty()) h += "<tr><th>Machine</th><td>" + html_escape(machine_) + "</td></tr>\n";
  for (const auto& [label, text] : inputs_)
    h += "<tr><th>" + html_escape(label) + "</th><td>" + html_escape(text) + "</td></tr>\n";
  h += "<tr><th>Command</th><td><code>" + html_escape(command_) + "</code></td></tr>\n";
  h += "<tr><th>Date</th><td class=\"date\">" + html_escape(date) + "</td></tr>\n";
  h += "<tr><th>mtcal</th><td>" + html_escape(version()) + "</td></tr>\n";
  h += "</table>\n";
  if (!figures_.empty()) {
    h += "<table class=\"figures\"><caption>Headline figures</caption>\n";
    for (const auto& f : figures_)
      h += "<tr><th>" + html_escape(f[0]) + "</th><td class=\"value\">" + html_escape(f[1]) + "</td><td>" +
           html_escape(f[2]) + "</td></tr>\n";
    h += "</table>\n";
  }
  if (!verdict_.empty()) {
    h += "<table class=\"data tolerances\"><caption>Tolerances (a quantity passes when its value is at most its "
         "permitted value)</caption>\n<thead><tr><th>quantity</th><th>value (µm)</th><th>permitted (µm)</th>"
         "<th>result</th></tr></thead>\n<tbody>\n";
    for (const auto& c : verdict_.checks)
      h += fmt::format("<tr class=\"{}\"><td>{}</td><td>{:.2f}</td><td>{:.2f}</td><td>{}</td></tr>\n",
                       c.pass ? "pass" : "fail", html_escape(c.quantity), c.value, c.limit, c.pass ? "pass" : "FAIL");
    h += "</tbody>\n</table>\n";
  }
  if (!warnings_.empty()) {
    h += "<div class=\"warnings\"><strong>Warnings</strong><ul>\n";
    for (const auto& w : warnings_) h += "<li>" + html_escape(w) + "</li>\n";
    h += "</ul></div>\n";
  }
  h += body_;
  h += "<footer>Made by mtcal " + html_escape(version()) +
       ", an open toolkit for the geometric accuracy of machine tools. Conventions: docs/conventions.md.</footer>\n";
  h += "</body>\n</html>\n";
  return h;
}

namespace {
StaticCopies& copies_setting() {
  static StaticCopies c;
  return c;
}

// RFC 4648 section 4 base64, padding optional; nullopt for a character outside the alphabet.
std::optional<std::string> base64_decode(std::string_view in) {
  std::string out;
  out.reserve(in.size() / 4 * 3);
  std::uint32_t acc = 0;
  int bits = 0;
  for (char c : in) {
    int v;
    if (c >= 'A' && c <= 'Z')
      v = c - 'A';
    else if (c >= 'a' && c <= 'z')
      v = c - 'a' + 26;
    else if (c >= '0' && c <= '9')
      v = c - '0' + 52;
    else if (c == '+')
      v = 62;
    else if (c == '/')
      v = 63;
    else if (c == '=')
      break;
    else
      return std::nullopt;
    acc = (acc << 6) | static_cast<std::uint32_t>(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out += static_cast<char>((acc >> bits) & 0xff);
    }
  }
  return out;
}
}  // namespace

void set_static_copies(StaticCopies copies) { copies_setting() = std::move(copies); }

namespace {
std::string& static_copy_note_setting() {
  static std::string note =
      "A static copy for e-mail: the report printed to PDF, or each plot as a PNG image, made by the program "
      "that wrote this report with a headless browser (docs/reports.md).";
  return note;
}
}  // namespace
void set_static_copy_note(std::string html) { static_copy_note_setting() = std::move(html); }
const std::string& static_copy_note() { return static_copy_note_setting(); }
const StaticCopies& static_copies() { return copies_setting(); }

std::vector<std::string> plot_images_from_dom(std::string_view dom) {
  std::vector<std::string> images;
  constexpr std::string_view kClass = "class=\"plot-print\"", kPrefix = "data:image/png;base64,";
  for (std::size_t at = dom.find(kClass); at != std::string_view::npos; at = dom.find(kClass, at + 1)) {
    const std::size_t open = dom.rfind('<', at), close = dom.find('>', at);
    if (open == std::string_view::npos || close == std::string_view::npos) break;
    const std::string_view tag = dom.substr(open, close - open);
    const std::size_t src = tag.find("src=\"");
    if (tag.rfind("<img", 0) != 0 || src == std::string_view::npos) continue;
    const std::size_t end = tag.find('"', src + 5);
    const std::string_view url =
        tag.substr(src + 5, end == std::string_view::npos ? std::string_view::npos : end - src - 5);
    if (url.rfind(kPrefix, 0) != 0)
      throw Error("the rendered report's plot image " + std::to_string(images.size() + 1) + " is not a PNG data URL");
    auto png = base64_decode(url.substr(kPrefix.size()));
    if (!png || png->rfind("\x89PNG\r\n\x1a\n", 0) != 0)
      throw Error("the rendered report's plot image " + std::to_string(images.size() + 1) + " is not a valid PNG");
    images.push_back(std::move(*png));
  }
  return images;
}

std::vector<std::string> plot_image_paths(const std::string& report_path, const std::string& png_dir, std::size_t n) {
  const std::string stem = std::filesystem::path(report_path).stem().string();
  std::vector<std::string> paths;
  for (std::size_t k = 1; k <= n; ++k)
    paths.push_back((std::filesystem::path(png_dir) / fmt::format("{}-plot-{}.png", stem, k)).string());
  return paths;
}

std::string Report::date_now() {
  std::time_t t = std::time(nullptr);
  if (const char* e = std::getenv("SOURCE_DATE_EPOCH")) t = static_cast<std::time_t>(std::strtoll(e, nullptr, 10));
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[64];
  std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M:%S UTC", &tm);
  return buf;
}

void Report::write(const std::string& path) const {
  const std::string text = html(date_now());
  write_file_atomically(path, text);
  const StaticCopies& copies = static_copies();
  if (copies.empty()) return;
  HeadlessBrowser browser{copies.browser, copies.timeout_s};
  if (browser.program.empty()) browser = find_headless_browser(copies.timeout_s);
  if (!copies.pdf.empty()) write_file_atomically(copies.pdf, print_to_pdf(browser, text));
  if (!copies.png_dir.empty()) {
    const std::vector<std::string> images = plot_images_from_dom(rendered_dom(browser, text));
    if (images.size() != plots_)
      throw Error(fmt::format("the browser made {} of the report's {} plot images ({})", images.size(), plots_,
                              browser.program));
    // A folder that is not there yet is made, as one of the command's outputs (all or none).
    if (std::error_code ec; !std::filesystem::exists(copies.png_dir, ec)) create_output_directory(copies.png_dir);
    const auto paths = plot_image_paths(path, copies.png_dir, images.size());
    for (std::size_t k = 0; k < images.size(); ++k) write_file_atomically(paths[k], images[k]);
  }
}

}  // namespace mtcal
