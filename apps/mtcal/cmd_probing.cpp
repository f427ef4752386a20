// mtcal rotary-axis and probe-sim: rotary-axis location errors from touch-probe sphere probing.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>
#include <memory>
#include <numbers>
#include <optional>

#include <Eigen/Geometry>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "common.hpp"
#include "mtcal/io/csv.hpp"
#include "mtcal/io/files.hpp"
#include "mtcal/io/joints.hpp"
#include "mtcal/io/machine_file.hpp"
#include "mtcal/probing/rotary_axis.hpp"
#include "mtcal/probing/sphere_probing.hpp"
#include "mtcal/report/report.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/util/parse.hpp"

namespace mtcal::cli {
namespace {

using json = nlohmann::ordered_json;
constexpr double kDeg = std::numbers::pi / 180.0;

struct RotaryOptions {
  std::string axis = "C";
  std::string contacts, centres, machine, method = "both", out, report;
  double sphere_diameter = 0, stylus_diameter = 0, reject_sigma = 2.0, max_rms = 0.01;
  int bins = 40, threads = 0;
  bool json_out = false;
};

// The column index of name, or -1; refuses columns outside allowed.
int column(const CsvTable& t, const std::string& name) { return t.column(name); }

void refuse_unknown_columns(const CsvTable& t, const std::string& file, const std::vector<std::string>& allowed) {
  for (const auto& c : t.columns)
    if (std::find(allowed.begin(), allowed.end(), c) == allowed.end()) {
      std::string list;
      for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
      throw InputError({file, 1, c}, "unknown column '" + c + "' (expected " + list + ")");
    }
}

int require(const CsvTable& t, const std::string& file, const std::string& name) {
  const int c = column(t, name);
  if (c < 0) throw InputError({file, 1, ""}, "missing column '" + name + "'");
  return c;
}

std::vector<std::string> axis_columns() { return {"X", "Y", "Z", "A", "B", "C"}; }

// Sphere centres per indexation from a contacts file, in order of first appearance; details
// receives each indexation's fit (both centres, rms, effective radius).
std::vector<MeasuredCentre> centres_from_contacts(const RotaryOptions& o, std::string& method,
                                                  std::vector<SphereCentre>& details) {
  const CsvTable t = read_csv(o.contacts);
  auto allowed = axis_columns();
  for (const char* c : {"x", "y", "z", "approach_x", "approach_y", "approach_z"}) allowed.push_back(c);
  refuse_unknown_columns(t, o.contacts, allowed);
  const int ca = require(t, o.contacts, o.axis);
  const int cx = require(t, o.contacts, "x"), cy = require(t, o.contacts, "y"), cz = require(t, o.contacts, "z");
  const int ax = column(t, "approach_x"), ay = column(t, "approach_y"), az = column(t, "approach_z");
  const bool approach = ax >= 0 && ay >= 0 && az >= 0;
  if (!approach && (ax >= 0 || ay >= 0 || az >= 0))
    throw InputError({o.contacts, 1, ""}, "give all three approach_x, approach_y, approach_z columns or none");
  // Consecutive rows with the same angle form one indexation; an angle met again later is an
  // error (a sphere probed twice would silently merge into one bad fit).
  struct Group {
    double angle;
    int line;
    std::vector<ProbeContact> contacts;
  };
  std::vector<Group> groups;
  std::map<double, int> seen;
  for (std::size_t r = 0; r < t.rows.size(); ++r) {
    const auto& row = t.rows[r];
    const double angle = row[static_cast<std::size_t>(ca)];
    ProbeContact c;
    c.point = Point3(row[static_cast<std::size_t>(cx)], row[static_cast<std::size_t>(cy)], row[static_cast<std::size_t>(cz)]);
    if (approach) {
      c.approach = Point3(row[static_cast<std::size_t>(ax)], row[static_cast<std::size_t>(ay)], row[static_cast<std::size_t>(az)]);
      if (!(c.approach.norm() > 0))
        throw InputError({o.contacts, t.lines[r], "approach_x"}, "the approach direction is a zero vector");
      c.approach.normalize();
    }
    if (groups.empty() || groups.back().angle != angle) {
      if (seen.count(angle))
        throw InputError({o.contacts, t.lines[r], o.axis},
                         fmt::format("{}={:g} was probed already (from line {}); keep each indexation's contacts together",
                                     o.axis, angle, seen[angle]));
      seen[angle] = t.lines[r];
      groups.push_back({angle, t.lines[r], {}});
    }
    groups.back().contacts.push_back(c);
  }
  const SphereProbing probing{o.sphere_diameter, o.stylus_diameter, o.max_rms};
  std::vector<MeasuredCentre> out;
  method.clear();
  for (const auto& g : groups) {
    const double a = g.angle;
    const auto sc = sphere_centre(g.contacts, probing, fmt::format("{}:{} ({}={:g})", o.contacts, g.line, o.axis, a));
    if (method.empty()) method = sc.method;
    if (method != sc.method) method = "mixed";
    out.push_back({a * kDeg, sc.centre()});
    details.push_back(sc);
  }
  return out;
}

std::vector<MeasuredCentre> centres_from_file(const RotaryOptions& o) {
  const CsvTable t = read_csv(o.centres);
  auto allowed = axis_columns();
  for (const char* c : {"x", "y", "z"}) allowed.push_back(c);
  refuse_unknown_columns(t, o.centres, allowed);
  const int ca = require(t, o.centres, o.axis);
  const int cx = require(t, o.centres, "x"), cy = require(t, o.centres, "y"), cz = require(t, o.centres, "z");
  std::vector<MeasuredCentre> out;
  std::map<double, int> seen;
  for (std::size_t r = 0; r < t.rows.size(); ++r) {
    const auto& row = t.rows[r];
    const double angle = row[static_cast<std::size_t>(ca)];
    if (seen.count(angle))
      throw InputError({o.centres, t.lines[r], o.axis},
                       fmt::format("{}={:g} is given twice (lines {} and {})", o.axis, angle, seen[angle], t.lines[r]));
    seen[angle] = t.lines[r];
    out.push_back({row[static_cast<std::size_t>(ca)] * kDeg,
                   Point3(row[static_cast<std::size_t>(cx)], row[static_cast<std::size_t>(cy)], row[static_cast<std::size_t>(cz)])});
  }
  return out;
}

// With 3 centres there is no redundancy: the uncertainty is unknown (null), not zero.
json estimate_json(const RotaryEstimate& e, const std::array<std::string, kRotaryQuantities>& names, bool u_known) {
  json j;
  for (std::size_t q = 0; q < kRotaryQuantities; ++q) {
    j[names[q]] = e.value[q];
    j[names[q] + "_u"] = u_known ? json(e.uncertainty[q]) : json(nullptr);
    j[names[q] + "_spread"] = e.spread[q];
  }
  j["axis_point"] = {e.axis_point.x(), e.axis_point.y(), e.axis_point.z()};
  j["axis_direction"] = {e.axis_direction.x(), e.axis_direction.y(), e.axis_direction.z()};
  return j;
}

// Display scale: positions and radius in um/mm, angles in urad.
std::pair<double, const char*> display(std::size_t q) {
  if (q == 4) return {1.0, "mm"};
  if (q < 2) return {1e3, "um"};
  return {1e6, "urad"};
}

// The HTML report: estimates of both estimators, centres and their circle, residuals, and the
// triples' distributions.
void write_rotary_report(const RotaryOptions& o, const Machine* machine, const NominalRotaryAxis& axis,
                         const std::vector<MeasuredCentre>& centres,
                         const std::vector<SphereCentre>& details, const std::string& centre_method,
                         const TriplesEstimate* tri, const LeastSquaresEstimate* lsq, bool u_known) {
  const auto names = rotary_quantity_names(axis.letter);
  Report r(std::string("Location errors of rotary axis ") + axis.letter, command_line());
  if (machine) r.set_machine(*machine);
  r.add_input(o.contacts.empty() ? "sphere centres" : "probe contacts", o.contacts.empty() ? o.centres : o.contacts);
  r.add_figure("indexations", fmt::format("{}", centres.size()), centre_method + " sphere centres");
  const RotaryEstimate* best = lsq ? static_cast<const RotaryEstimate*>(lsq) : tri;
  for (std::size_t q = 0; q < 4; ++q) {
    const auto [f, unit] = display(q);
    r.add_figure(names[q], fmt::format("{:.3f} ± {:.3f}", best->value[q] * f, best->uncertainty[q] * f),
                 std::string(unit) + (lsq ? " (least squares, standard uncertainty)" : " (triples, standard uncertainty)"));
  }
  if (tri) {
    const double kept = static_cast<double>(tri->kept[0]) / static_cast<double>(std::max<std::size_t>(1, tri->triples - tri->degenerate));
    if (kept < 0.8)
      r.add_warning(fmt::format("The {:g}-sigma rule rejected {:.0f} % of the triples for {}: look for outlying "
                                "centres (dirt on the sphere, a missed trigger).", o.reject_sigma, 100 * (1 - kept), names[0]));
    if (tri->degenerate > 0)
      r.add_warning(fmt::format("{} triples of centres were collinear and skipped.", tri->degenerate));
    // Centres whose triples are rejected far more often than the others' are likely outliers.
    std::vector<double> share = tri->rejected_share;
    std::vector<double> sorted = share;
    std::sort(sorted.begin(), sorted.end());
    const double median = sorted.empty() ? 0.0 : sorted[sorted.size() / 2];
    for (std::size_t i = 0; i < share.size(); ++i)
      if (share[i] > 0.2 && share[i] > 3 * median)
        r.add_warning(fmt::format("The triples through the centre at {}={:g} deg were rejected {:.0f} % of the time "
                                  "(median {:.0f} %): an outlying measurement?",
                                  axis.letter, centres[i].angle / kDeg, 100 * share[i], 100 * median));
  }
  for (std::size_t i = 0; i < details.size(); ++i)
    if (details[i].rms > 0.5 * o.max_rms)
      r.add_warning(fmt::format("The contacts at {}={:g} deg lie {:.4f} mm rms from their sphere (limit {} mm).",
                                axis.letter, centres[i].angle / kDeg, details[i].rms, o.max_rms));
  if (best->value[5] > 1e-3) r.add_warning("The axis is tilted by more than 1 mrad from its nominal direction.");
  if (!u_known) r.add_warning("Only 3 indexations: the circle passes exactly through them; there is no redundancy and no uncertainty.");

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
  r.add_table("Both estimators (ISO 230-7 names; uncertainty = standard uncertainty; spread = scatter of the "
              "samples used)",
              {"quantity", "unit", "triples value", "triples u", "triples spread", "least-squares value",
               "least-squares u", "least-squares spread"},
              rows);

  r.add_section("Sphere centres");
  nlohmann::json cx = nlohmann::json::array(), cy = cx, cz = cx, ct = cx;
  for (const auto& c : centres) {
    cx.push_back(c.centre.x());
    cy.push_back(c.centre.y());
    cz.push_back(c.centre.z());
    ct.push_back(fmt::format("{}={:g} deg", axis.letter, c.angle / kDeg));
  }
  nlohmann::json data = nlohmann::json::array();
  data.push_back({{"type", "scatter3d"}, {"mode", "markers"}, {"x", cx}, {"y", cy}, {"z", cz}, {"text", ct},
                  {"name", "sphere centres"}, {"marker", {{"size", 4}}}});
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
    data.push_back({{"type", "scatter3d"}, {"mode", "lines"}, {"x", lx}, {"y", ly}, {"z", lz}, {"name", "fitted circle"}});
    const Point3 a0 = circle->centre - 0.5 * circle->radius * circle->normal;
    const Point3 a1 = circle->centre + 0.5 * circle->radius * circle->normal;
    data.push_back({{"type", "scatter3d"}, {"mode", "lines"}, {"x", {a0.x(), a1.x()}}, {"y", {a0.y(), a1.y()}},
                    {"z", {a0.z(), a1.z()}}, {"name", "measured axis"}, {"line", {{"width", 6}}}});
  }
  r.add_plot("Sphere centres at each indexation (mm, machine coordinates), the least-squares circle and the axis",
             {{"data", data}, {"layout", {{"scene", {{"aspectmode", "data"}}}}}});
  if (lsq) {
    nlohmann::json ang = nlohmann::json::array(), rad = ang;
    for (std::size_t i = 0; i < centres.size(); ++i) {
      ang.push_back(centres[i].angle / kDeg);
      rad.push_back(lsq->circle.quality.residuals[i] * 1e3);
    }
    r.add_plot("Radial deviation of each centre from the least-squares circle (µm)",
               {{"data", {{{"type", "bar"}, {"x", ang}, {"y", rad}, {"name", "radial deviation"}}}},
                {"layout", {{"xaxis", {{"title", {{"text", std::string(1, axis.letter) + " (deg)"}}}}},
                            {"yaxis", {{"title", {{"text", "µm"}}}}}}}});
  }
  if (tri) {
    r.add_section("Triples' distributions");
    r.add_paragraph(fmt::format("Every one of the {} triples of centres gives a circle and so a value of each "
                                "quantity (Cubas & Yeh 2022); values beyond {:g} standard deviations are rejected "
                                "before averaging. {} triples were collinear.",
                                tri->triples, o.reject_sigma, tri->degenerate));
    for (std::size_t q = 0; q < 4; ++q) {
      const auto [f, unit] = display(q);
      const auto& h = tri->histograms[q];
      nlohmann::json xs = nlohmann::json::array();
      const double w = (h.high - h.low) / static_cast<double>(h.counts.size());
      for (std::size_t b = 0; b < h.counts.size(); ++b) xs.push_back((h.low + (static_cast<double>(b) + 0.5) * w) * f);
      r.add_plot(fmt::format("{}: distribution over the triples ({}); kept {} of {}", names[q], unit, tri->kept[q],
                             tri->triples - tri->degenerate),
                 {{"data", {{{"type", "bar"}, {"x", xs}, {"y", h.counts}, {"name", names[q]}}}},
                  {"layout", {{"xaxis", {{"title", {{"text", names[q] + " (" + unit + ")"}}}}},
                              {"yaxis", {{"title", {{"text", "triples"}}}}},
                              {"bargap", 0.02},
                              {"shapes", {{{"type", "line"}, {"x0", tri->value[q] * f}, {"x1", tri->value[q] * f},
                                           {"y0", 0}, {"y1", 1}, {"yref", "paper"},
                                           {"line", {{"color", "red"}}}}}}}}});
    }
  }
  r.write(o.report);
}

int run_rotary(const RotaryOptions& o) {
  if (o.axis.size() != 1 || o.axis[0] < 'A' || o.axis[0] > 'C')
    throw InputError({"--axis", 0, ""}, "expected A, B or C, found '" + o.axis + "'");
  if (o.contacts.empty() == o.centres.empty())
    throw InputError({"rotary-axis", 0, ""}, "expected exactly one of --contacts and --centres");
  if (!o.contacts.empty() && !(o.sphere_diameter > 0))
    throw InputError({"--sphere-diameter", 0, ""}, "expected the sphere diameter (mm) with --contacts");
  check_outputs({o.contacts, o.centres, o.machine}, {o.out, o.report});
  if (!o.out.empty() && o.machine.empty())
    throw InputError({"--out", 0, ""}, "--out needs --machine: the position errors are relative to the axis's nominal "
                                       "point, which the machine file gives");
  if (o.reject_sigma != 0 && o.reject_sigma < 1)
    throw InputError({"--reject-sigma", 0, ""}, fmt::format("expected 0 (no rejection) or at least 1, found {:g}", o.reject_sigma));
  NominalRotaryAxis axis = NominalRotaryAxis::by_letter(o.axis[0]);
  std::optional<Machine> machine;
  if (!o.machine.empty()) {
    machine = load_machine(o.machine);
    axis = NominalRotaryAxis::from(machine->axis(o.axis[0]));
  }

  std::string centre_method = "given";
  std::vector<SphereCentre> details;
  const auto centres = o.contacts.empty() ? centres_from_file(o) : centres_from_contacts(o, centre_method, details);
  const auto names = rotary_quantity_names(axis.letter);
  const bool do_triples = o.method != "lsq", do_lsq = o.method != "triples";
  const bool u_known = centres.size() >= 4;

  std::unique_ptr<AtomicFile> file;
  if (!o.out.empty()) file = std::make_unique<AtomicFile>(o.out);  // refuse a bad path before the work
  if (!o.report.empty()) AtomicFile check(o.report);

  constexpr std::size_t kMaxTriplesCentres = 1000;  // C(1000, 3) = 1.7e8 triples, about 20 s
  if (do_triples && centres.size() > kMaxTriplesCentres)
    throw InputError({o.contacts.empty() ? o.centres : o.contacts, 0, ""},
                     fmt::format("{} indexations make too many triples for --method triples/both (at most {}); use "
                                 "--method lsq",
                                 centres.size(), kMaxTriplesCentres));
  std::optional<TriplesEstimate> tri;
  std::optional<LeastSquaresEstimate> lsq;
  if (do_lsq) lsq = estimate_by_least_squares(axis, centres);
  if (do_triples) tri = estimate_by_triples(axis, centres, TriplesOptions{o.reject_sigma, o.bins, o.threads});
  // A circle of centres far from perpendicular to the axis means the wrong axis or wrong data.
  const RotaryEstimate& first = lsq ? static_cast<const RotaryEstimate&>(*lsq) : *tri;
  for (const RotaryEstimate* e : {lsq ? static_cast<const RotaryEstimate*>(&*lsq) : nullptr,
                                  tri ? static_cast<const RotaryEstimate*>(&*tri) : nullptr}) {
    if (!e) continue;
    for (std::size_t q = 0; q < kRotaryQuantities; ++q)
      if (!std::isfinite(e->value[q]))
        throw InputError({"centres", 0, names[q]}, "the estimate is not finite: are the centres of axis " + o.axis + "?");
  }
  if (first.value[5] > 0.1)
    throw InputError({"--axis", 0, o.axis},
                     fmt::format("the centres turn about a line {:.1f} deg from the nominal direction of {}: wrong --axis?",
                                 first.value[5] / kDeg, o.axis));

  if (file) {
    const RotaryEstimate& use = lsq ? static_cast<const RotaryEstimate&>(*lsq) : *tri;
    std::string y = fmt::format("# Location errors of axis {} from mtcal rotary-axis ({}), {} indexations of {}\n",
                                axis.letter, lsq ? "least squares" : "triples", centres.size(),
                                o.contacts.empty() ? o.centres : o.contacts);
    y += "mtcal_parameters: 1\nerrors:\n";
    for (std::size_t q = 0; q < 4; ++q)
      y += fmt::format("  {}: {{value: {:.17g}, unit: {}}}  # +- {:.3g} (standard uncertainty)\n", names[q],
                       use.value[q], q < 2 ? "mm" : "rad", use.uncertainty[q]);
    file->stream() << y;
    file->commit();
  }

  if (!o.report.empty())
    write_rotary_report(o, machine ? &*machine : nullptr, axis, centres, details, centre_method, tri ? &*tri : nullptr,
                        lsq ? &*lsq : nullptr, u_known);

  if (o.json_out) {
    json j;
    j["axis"] = std::string(1, axis.letter);
    j["indexations"] = centres.size();
    j["centre_method"] = centre_method;
    j["units"] = "positions and radius in mm, angles in rad";
    if (tri) {
      json t = estimate_json(*tri, names, u_known);
      t["triples"] = tri->triples;
      t["degenerate"] = tri->degenerate;
      t["reject_sigma"] = o.reject_sigma;
      json kept, mean_all, hist;
      for (std::size_t q = 0; q < kRotaryQuantities; ++q) {
        kept[names[q]] = tri->kept[q];
        mean_all[names[q]] = tri->mean_all[q];
        hist[names[q]] = {{"low", tri->histograms[q].low}, {"high", tri->histograms[q].high},
                          {"counts", tri->histograms[q].counts}};
      }
      t["kept"] = kept;
      t["mean_before_rejection"] = mean_all;
      t["histograms"] = hist;
      j["triples"] = t;
    }
    if (lsq) {
      json l = estimate_json(*lsq, names, u_known);
      l["rms"] = lsq->circle.quality.rms;
      j["least_squares"] = l;
    }
    json cs = json::array();
    for (std::size_t i = 0; i < centres.size(); ++i) {
      const auto& c = centres[i];
      json cj = {{"angle", c.angle / kDeg}, {"x", c.centre.x()}, {"y", c.centre.y()}, {"z", c.centre.z()}};
      if (i < details.size()) {
        // Beside the centre used (the 5-point protocol's when it applies), the least-squares fit
        // of all contacts, its rms, and the free-radius fit's tip-centre distance.
        const auto& d = details[i];
        cj["least_squares"] = {d.least_squares.x(), d.least_squares.y(), d.least_squares.z()};
        cj["rms"] = d.rms;
        if (d.effective_radius) cj["effective_radius"] = *d.effective_radius;
      }
      cs.push_back(cj);
    }
    j["centres"] = cs;
    if (!o.out.empty()) j["out"] = o.out;
    if (!o.report.empty()) j["report"] = o.report;
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::cout << fmt::format("rotary axis {}: {} indexations, sphere centres: {}\n", axis.letter, centres.size(),
                           centre_method);
  std::cout << fmt::format("{:<8} {:<5} {:>30} {:>30}\n", "", "", tri ? "triples (Cubas & Yeh)" : "",
                           lsq ? "least squares" : "");
  for (std::size_t q = 0; q < kRotaryQuantities; ++q) {
    const auto [f, unit] = display(q);
    auto cell = [&](const RotaryEstimate* e) {
      if (!e) return std::string();
      return u_known ? fmt::format("{:.4f} +- {:.4f}", e->value[q] * f, e->uncertainty[q] * f)
                     : fmt::format("{:.4f} +- n/a", e->value[q] * f);
    };
    std::cout << fmt::format("{:<8} {:<5} {:>30} {:>30}\n", names[q], unit, cell(tri ? &*tri : nullptr),
                             cell(lsq ? &*lsq : nullptr));
  }
  if (!u_known) std::cout << "3 indexations: a circle exactly, no redundancy, so no uncertainty\n";
  if (tri)
    std::cout << fmt::format("triples: {} ({} degenerate); kept after the {:g}-sigma rule: {} of {}\n", tri->triples,
                             tri->degenerate, o.reject_sigma, tri->kept[0], tri->triples - tri->degenerate);
  if (!o.out.empty()) std::cout << "wrote " << o.out << "\n";
  if (!o.report.empty()) std::cout << "report " << o.report << "\n";
  return 0;
}

struct SimOptions {
  ModelOptions model;
  std::string axis = "C", angles = "0:350:36", hold, sphere = "150,0,50", out;
  double sphere_diameter = 30, stylus_diameter = 6, noise = 0, bias = 0;
  std::uint64_t seed = 1;
};

int run_sim(const SimOptions& o) {
  check_outputs(model_inputs(o.model), {o.out});
  const Machine m = load(o.model);
  if (o.axis.size() != 1) throw InputError({"--axis", 0, ""}, "expected one axis letter, found '" + o.axis + "'");
  const auto k = m.axis_index(o.axis[0]);
  if (!k) throw InputError({"--axis", 0, ""}, "axis '" + o.axis + "' is not in topology " + m.topology.chain);
  ProbingSimulation sim;
  sim.axis = o.axis[0];
  // --angles lo:hi:count in deg, as a grid of that one axis.
  const auto grid = parse_grid(m, o.axis + "=" + o.angles, "--angles");
  sim.angles = grid[*k];
  sim.held = o.hold.empty() ? std::vector<double>(m.axes.size(), 0.0) : parse_joint_values(m, o.hold, "--hold");
  const auto parts = split_list(o.sphere);
  if (parts.size() != 3) throw InputError({"--sphere", 0, ""}, "expected x,y,z in mm, found '" + o.sphere + "'");
  for (int c = 0; c < 3; ++c) {
    const auto v = parse_number(parts[static_cast<std::size_t>(c)]);
    if (!v) throw InputError({"--sphere", 0, ""}, "expected a number, found '" + parts[static_cast<std::size_t>(c)] + "'");
    sim.sphere[c] = *v;
  }
  if (!(o.sphere_diameter > 0) || !(o.stylus_diameter >= 0) || !(o.noise >= 0) || !std::isfinite(o.bias))
    throw InputError({"probe-sim", 0, ""}, "expected a sphere diameter > 0, a stylus diameter >= 0 and a noise >= 0");
  sim.probing = {o.sphere_diameter, o.stylus_diameter, 0.01};
  sim.noise = o.noise;
  sim.trigger_bias = o.bias;
  sim.seed = o.seed;
  AtomicFile file(o.out);
  const auto probed = simulate_probing(m, sim);
  file.stream() << o.axis << ",x,y,z,approach_x,approach_y,approach_z\n";
  for (const auto& ix : probed)
    for (const auto& c : ix.contacts)
      file.stream() << fmt::format("{:.12g},{:.9f},{:.9f},{:.9f},{:g},{:g},{:g}\n", to_user_units(m.axes[*k], ix.angle),
                                   c.point.x(), c.point.y(), c.point.z(), c.approach.x(), c.approach.y(), c.approach.z());
  file.commit();
  std::cout << fmt::format("simulated {} indexations of {} x 5 contacts on {} (noise {} mm, trigger bias {} mm): wrote {}\n",
                           probed.size(), o.axis, m.name, o.noise, o.bias, o.out);
  return 0;
}

}  // namespace

std::vector<Command> add_probing_commands(CLI::App& app) {
  auto ro = std::make_shared<RotaryOptions>();
  auto* r = app.add_subcommand(
      "rotary-axis",
      "Location errors of a rotary axis (ISO 230-7: EX0C EY0C EA0C EB0C for C ...) from a sphere probed at many "
      "indexations: all-triples estimator (Cubas & Yeh 2022) and global least-squares circle, with uncertainties");
  r->add_option("--axis", ro->axis, "The rotary axis turned between indexations: A, B or C")->required();
  r->add_option("--contacts", ro->contacts,
                "CSV of probe contacts: the axis's angle (deg, column named by its letter), recorded stylus-tip "
                "centre x,y,z (mm), approach_x,approach_y,approach_z (direction of probe motion)");
  r->add_option("--centres", ro->centres, "CSV of sphere centres already known: the axis's angle (deg), x,y,z (mm)");
  r->add_option("--sphere-diameter", ro->sphere_diameter, "Calibration sphere diameter, mm (with --contacts)")->check(kFinite);
  r->add_option("--stylus-diameter", ro->stylus_diameter, "Stylus tip diameter, mm (with --contacts)")->check(kFinite);
  r->add_option("--machine", ro->machine, "Machine file giving the axis's nominal point and direction (default: "
                                          "through the origin along its letter's axis)");
  r->add_option("--method", ro->method, "Estimator: triples, lsq or both")
      ->check(CLI::IsMember({"triples", "lsq", "both"}))
      ->capture_default_str();
  r->add_option("--reject-sigma", ro->reject_sigma, "Triples farther than this many standard deviations are "
                                                    "rejected (0: none)")
      ->check(CLI::Range(0.0, 100.0) & kFinite)
      ->capture_default_str();
  r->add_option("--max-rms", ro->max_rms, "Largest rms distance (mm) of contacts from their sphere")
      ->check(CLI::PositiveNumber & kFinite)
      ->capture_default_str();
  r->add_option("--bins", ro->bins, "Histogram bins of the triples' distributions")->check(CLI::Range(1, 10000));
  r->add_option("--threads", ro->threads, "Threads for the triples (0: all cores)")->check(CLI::Range(0, 4096));
  r->add_flag("--json", ro->json_out, "Machine-readable output: ISO names in mm and rad, '_u' uncertainty, "
                                      "'_spread' spread, triples' histograms");
  r->add_option("--out", ro->out, "Write the location errors as a parameter file (mtcal eval --params ...); with "
                                  "--method both the least-squares values");
  r->add_option("--report", ro->report, "Write an HTML report: both estimators, centres and circle, residuals, "
                                        "the triples' distributions");

  auto so = std::make_shared<SimOptions>();
  auto* s = app.add_subcommand("probe-sim", "Simulated touch-probe contacts on a sphere at indexations of a rotary "
                                            "axis of a machine model (5-point protocol), with noise and trigger bias");
  add_model_options(s, so->model);  // the machine's errors (with --params, --only, --set) are what the probing sees
  s->add_option("--axis", so->axis, "Rotary axis that carries the workpiece, turned between indexations")->capture_default_str();
  s->add_option("--angles", so->angles, "Indexations lo:hi:count in deg")->capture_default_str();
  s->add_option("--hold", so->hold, "Other joints, e.g. \"A=0\" (mm, deg; not named: 0)");
  s->add_option("--sphere", so->sphere, "Sphere centre at zero indexation, machine coordinates x,y,z in mm")
      ->capture_default_str();
  s->add_option("--sphere-diameter", so->sphere_diameter, "mm")->check(kFinite)->capture_default_str();
  s->add_option("--stylus-diameter", so->stylus_diameter, "mm")->check(kFinite)->capture_default_str();
  s->add_option("--noise", so->noise, "Standard deviation of each recorded coordinate, mm")->check(kFinite)->capture_default_str();
  s->add_option("--trigger-bias", so->bias, "Probe pre-travel along the approach, mm")->check(kFinite)->capture_default_str();
  s->add_option("--seed", so->seed, "Random seed of the noise")->capture_default_str();
  s->add_option("--out", so->out, "Contacts CSV to write (input of mtcal rotary-axis --contacts)")->required();
  return {{r, [ro] { return run_rotary(*ro); }}, {s, [so] { return run_sim(*so); }}};
}

}  // namespace mtcal::cli
