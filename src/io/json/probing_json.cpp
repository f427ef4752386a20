// JSON of the rotary-axis location test (io/json/probing_json.hpp); keys documented in docs/rotary-axis.md.
#include "mtcal/io/json/probing_json.hpp"
#include "mtcal/util/units.hpp"

#include <numbers>

namespace mtcal {
namespace {


}  // namespace

// With 3 centres there is no redundancy: the uncertainty is unknown (null), not zero.
Json to_json(const RotaryEstimate& e, const std::array<std::string, kRotaryQuantities>& names, bool u_known) {
  Json j;
  for (std::size_t q = 0; q < kRotaryQuantities; ++q) {
    j[names[q]] = e.value[q];
    j[names[q] + "_u"] = u_known ? Json(e.uncertainty[q]) : Json(nullptr);
    j[names[q] + "_spread"] = e.spread[q];
  }
  j["axis_point"] = {e.axis_point.x(), e.axis_point.y(), e.axis_point.z()};
  j["axis_direction"] = {e.axis_direction.x(), e.axis_direction.y(), e.axis_direction.z()};
  return j;
}

Json to_json(const RotaryAxisResult& r) {
  const auto names = rotary_quantity_names(r.axis.letter);
  const bool u_known = r.uncertainty_known();
  const auto& centres = r.centres.centres;
  const auto& details = r.centres.fits;
  Json j;
  j["axis"] = std::string(1, r.axis.letter);
  j["indexations"] = centres.size();
  j["centre_method"] = r.centres.method;
  j["units"] = "positions and radius in mm, angles in rad";
  if (r.triples) {
    const auto& tri = *r.triples;
    Json t = to_json(static_cast<const RotaryEstimate&>(tri), names, u_known);
    t["triples"] = tri.triples;
    t["degenerate"] = tri.degenerate;
    t["reject_sigma"] = r.reject_sigma;
    Json kept, mean_all, hist;
    for (std::size_t q = 0; q < kRotaryQuantities; ++q) {
      kept[names[q]] = tri.kept[q];
      mean_all[names[q]] = tri.mean_all[q];
      hist[names[q]] = {{"low", tri.histograms[q].low},
                        {"high", tri.histograms[q].high},
                        {"counts", tri.histograms[q].counts}};
    }
    t["kept"] = kept;
    t["mean_before_rejection"] = mean_all;
    t["histograms"] = hist;
    j["triples"] = t;
  }
  if (r.least_squares) {
    Json l = to_json(static_cast<const RotaryEstimate&>(*r.least_squares), names, u_known);
    l["rms"] = r.least_squares->circle.quality.rms;
    j["least_squares"] = l;
  }
  Json cs = Json::array();
  for (std::size_t i = 0; i < centres.size(); ++i) {
    const auto& c = centres[i];
    Json cj = {{"angle", c.angle / kRadPerDeg}, {"x", c.centre.x()}, {"y", c.centre.y()}, {"z", c.centre.z()}};
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
  j["measured_line"] = {{"point", {r.line.point.x(), r.line.point.y(), r.line.point.z()}},
                        {"direction", {r.line.direction.x(), r.line.direction.y(), r.line.direction.z()}},
                        {"radius", r.line.radius},
                        {"tilt", r.line.tilt},
                        {"rms", r.line.rms}};
  j["notes"] = r.notes;
  return j;
}

}  // namespace mtcal
