// HTML report of the rotary-axis location test (report/probing.hpp).
#include "mtcal/report/probing.hpp"
#include "mtcal/util/units.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <utility>

#include <Eigen/Geometry>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "mtcal/io/system/files.hpp"
#include "mtcal/report/report.hpp"

namespace mtcal {
namespace {


// Display scale: positions and radius in um/mm, angles in urad.
std::pair<double, const char*> display(std::size_t q) {
  if (q == 4) return {1.0, "mm"};
  if (q < 2) return {1e3, "um"};
  return {1e6, "urad"};
}

}  // namespace

Report rotary_report(const std::string& command, const Machine* machine, const RotaryAxisResult& result,
                     double max_rms, const std::string& input_sha256, const ReportMetadata& metadata) {
  const NominalRotaryAxis& axis = result.axis;
  const std::vector<MeasuredCentre>& centres = result.centres.centres;
  const std::vector<SphereCentre>& details = result.centres.fits;
  const std::string& centre_method = result.centres.method;
  const TriplesEstimate* tri = result.triples ? &*result.triples : nullptr;
  const LeastSquaresEstimate* lsq = result.least_squares ? &*result.least_squares : nullptr;
  const bool u_known = result.uncertainty_known();
  const auto names = rotary_quantity_names(axis.letter);
  Report r(std::string("Location errors of rotary axis ") + axis.letter, command);
  r.set_metadata(metadata);
  if (machine) r.set_machine(*machine);
  const bool given = centre_method == "given";
  r.add_input(given ? "sphere centres" : "probe contacts", result.centres.source, input_sha256);
  r.add_figure("indexations", fmt::format("{}", centres.size()), centre_method + " sphere centres");
  const RotaryEstimate* best = lsq ? static_cast<const RotaryEstimate*>(lsq) : tri;
  for (std::size_t q = 0; q < 4; ++q) {
    const auto [f, unit] = display(q);
    r.add_figure(names[q], fmt::format("{:.3f} ± {:.3f}", best->value[q] * f, best->uncertainty[q] * f),
                 std::string(unit) +
                     (lsq ? " (least squares, standard uncertainty)" : " (triples, standard uncertainty)"));
  }
  for (const auto& note : result.notes) r.add_warning(note);
  if (tri) {
    const double kept = static_cast<double>(tri->kept[0]) /
                        static_cast<double>(std::max<std::size_t>(1, tri->triples - tri->degenerate));
    if (kept < 0.8)
      r.add_warning(
          fmt::format("The {:g}-sigma rule rejected {:.0f} % of the triples for {}: look for outlying "
                      "centres (dirt on the sphere, a missed trigger).",
                      result.reject_sigma, 100 * (1 - kept), names[0]));
    if (tri->degenerate > 0)
      r.add_warning(fmt::format("{} triples of centres were collinear and skipped.", tri->degenerate));
    // Centres whose triples are rejected far more often than the others' are likely outliers.
    std::vector<double> share = tri->rejected_share;
    std::vector<double> sorted = share;
    std::sort(sorted.begin(), sorted.end());
    const double median = sorted.empty() ? 0.0 : sorted[sorted.size() / 2];
    for (std::size_t i = 0; i < share.size(); ++i)
      if (share[i] > 0.2 && share[i] > 3 * median)
        r.add_warning(
            fmt::format("The triples through the centre at {}={:g} deg were rejected {:.0f} % of the time "
                        "(median {:.0f} %): an outlying measurement?",
                        axis.letter, centres[i].angle / kRadPerDeg, 100 * share[i], 100 * median));
  }
  for (std::size_t i = 0; i < details.size(); ++i)
    if (details[i].rms > 0.5 * max_rms)
      r.add_warning(fmt::format("The contacts at {}={:g} deg lie {:.4f} mm rms from their sphere (limit {} mm).",
                                axis.letter, centres[i].angle / kRadPerDeg, details[i].rms, max_rms));
  if (best->value[5] > 1e-3) r.add_warning("The axis is tilted by more than 1 mrad from its nominal direction.");
  if (!u_known)
    r.add_warning(
        "Only 3 indexations: the circle passes exactly through them; there is no redundancy and no uncertainty.");

  r.add_section("Location errors");
  std::vector<std::vector<std::string>> rows;
  for (std::size_t q = 0; q < kRotaryQuantities; ++q) {
    const auto [f, unit] = display(q);
    auto cells = [&, f = f](const RotaryEstimate* e) -> std::vector<std::string> {
      if (!e) return {"", "", ""};
      return {fmt::format("{:.4f}", e->value[q] * f), fmt::format("{:.4f}", e->uncertainty[q] * f),
              fmt::format("{:.4f}", e->spread[q] * f)};
    };
    std::vector<std::string> row{names[q], unit};
    for (const auto& c : cells(tri)) row.push_back(c);
    for (const auto& c : cells(lsq)) row.push_back(c);
    rows.push_back(row);
  }
  r.add_table(
      "Both estimators (ISO 230-7 names; uncertainty = standard uncertainty; spread = scatter of the "
      "samples used)",
      {"quantity", "unit", "triples value", "triples u", "triples spread", "least-squares value", "least-squares u",
       "least-squares spread"},
      rows);

  r.add_section("Sphere centres");
  nlohmann::json cx = nlohmann::json::array(), cy = cx, cz = cx, ct = cx;
  for (const auto& c : centres) {
    cx.push_back(c.centre.x());
    cy.push_back(c.centre.y());
    cz.push_back(c.centre.z());
    ct.push_back(fmt::format("{}={:g} deg", axis.letter, c.angle / kRadPerDeg));
  }
  nlohmann::json data = nlohmann::json::array();
  data.push_back({{"type", "scatter3d"},
                  {"mode", "markers"},
                  {"x", cx},
                  {"y", cy},
                  {"z", cz},
                  {"text", ct},
                  {"name", "sphere centres"},
                  {"marker", {{"size", 4}}}});
  std::optional<CircleFit> circle;
  if (lsq) {
    circle = lsq->circle;
  } else {
    std::vector<Point3> pts;
    for (const auto& c : centres) pts.push_back(c.centre);
    circle = fit_circle(pts);
  }
  if (circle) {
    // The fitted circle and the measured axis line through its centre.
    const Point3 u = circle->normal.unitOrthogonal(), v = circle->normal.cross(u);
    nlohmann::json lx = nlohmann::json::array(), ly = lx, lz = lx;
    for (int k = 0; k <= 120; ++k) {
      const double a = 2 * std::numbers::pi * k / 120;
      const Point3 p = circle->centre + circle->radius * (std::cos(a) * u + std::sin(a) * v);
      lx.push_back(p.x());
      ly.push_back(p.y());
      lz.push_back(p.z());
    }
    data.push_back(
        {{"type", "scatter3d"}, {"mode", "lines"}, {"x", lx}, {"y", ly}, {"z", lz}, {"name", "fitted circle"}});
    const Point3 a0 = circle->centre - 0.5 * circle->radius * circle->normal;
    const Point3 a1 = circle->centre + 0.5 * circle->radius * circle->normal;
    data.push_back({{"type", "scatter3d"},
                    {"mode", "lines"},
                    {"x", {a0.x(), a1.x()}},
                    {"y", {a0.y(), a1.y()}},
                    {"z", {a0.z(), a1.z()}},
                    {"name", "measured axis"},
                    {"line", {{"width", 6}}}});
  }
  r.add_plot("Sphere centres at each indexation (mm, machine coordinates), the least-squares circle and the axis",
             {{"data", data}, {"layout", {{"scene", {{"aspectmode", "data"}}}}}});
  if (lsq) {
    nlohmann::json ang = nlohmann::json::array(), rad = ang;
    for (std::size_t i = 0; i < centres.size(); ++i) {
      ang.push_back(centres[i].angle / kRadPerDeg);
      rad.push_back(lsq->circle.quality.residuals[i] * 1e3);
    }
    r.add_plot("Radial deviation of each centre from the least-squares circle (µm)",
               {{"data", {{{"type", "bar"}, {"x", ang}, {"y", rad}, {"name", "radial deviation"}}}},
                {"layout",
                 {{"xaxis", {{"title", {{"text", std::string(1, axis.letter) + " (deg)"}}}}},
                  {"yaxis", {{"title", {{"text", "µm"}}}}}}}});
  }
  if (tri) {
    r.add_section("Triples' distributions");
    r.add_paragraph(
        fmt::format("Every one of the {} triples of centres gives a circle and so a value of each "
                    "quantity (Cubas & Yeh 2022); values beyond {:g} standard deviations are rejected "
                    "before averaging. {} triples were collinear.",
                    tri->triples, result.reject_sigma, tri->degenerate));
    for (std::size_t q = 0; q < 4; ++q) {
      const auto [f, unit] = display(q);
      const auto& h = tri->histograms[q];
      nlohmann::json xs = nlohmann::json::array();
      const double w = (h.high - h.low) / static_cast<double>(h.counts.size());
      for (std::size_t b = 0; b < h.counts.size(); ++b) xs.push_back((h.low + (static_cast<double>(b) + 0.5) * w) * f);
      r.add_plot(fmt::format("{}: distribution over the triples ({}); kept {} of {}", names[q], unit, tri->kept[q],
                             tri->triples - tri->degenerate),
                 {{"data", {{{"type", "bar"}, {"x", xs}, {"y", h.counts}, {"name", names[q]}}}},
                  {"layout",
                   {{"xaxis", {{"title", {{"text", names[q] + " (" + unit + ")"}}}}},
                    {"yaxis", {{"title", {{"text", "triples"}}}}},
                    {"bargap", 0.02},
                    {"shapes",
                     {{{"type", "line"},
                       {"x0", tri->value[q] * f},
                       {"x1", tri->value[q] * f},
                       {"y0", 0},
                       {"y1", 1},
                       {"yref", "paper"},
                       {"line", {{"color", "red"}}}}}}}}});
    }
  }
  return r;
}

void write_rotary_report(const std::string& path, const std::string& command, const Machine* machine,
                         const RotaryAxisResult& result, double max_rms) {
  const bool given = result.centres.method == "given";
  rotary_report(command, machine, result, max_rms,
                sha256_hex(read_text_file(result.centres.source, given ? "sphere centres" : "probe contacts")),
                session_metadata())
      .write(path);
}

}  // namespace mtcal
