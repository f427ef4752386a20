// Rotary-axis location test from sphere probing (probing/rotary_probing.hpp).
#include "mtcal/probing/rotary_probing.hpp"

#include <cmath>
#include <map>
#include <numbers>
#include <utility>

#include <fmt/format.h>

#include "mtcal/util/errors.hpp"

namespace mtcal {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

}  // namespace

IndexedCentres centres_from_contacts(const ContactSet& set, const SphereProbing& probing) {
  // Consecutive contacts with the same angle form one indexation; an angle met again later is an
  // error.
  struct Group {
    double angle;
    int line;
    std::vector<ProbeContact> contacts;
  };
  std::vector<Group> groups;
  std::map<double, int> seen;
  const std::string axis(1, set.axis);
  for (const auto& c : set.contacts) {
    if (groups.empty() || groups.back().angle != c.angle_deg) {
      if (seen.count(c.angle_deg))
        throw InputError(
            {set.source, c.line, axis},
            fmt::format("{}={:g} was probed already (from line {}); keep each indexation's contacts together", axis,
                        c.angle_deg, seen[c.angle_deg]));
      seen[c.angle_deg] = c.line;
      groups.push_back({c.angle_deg, c.line, {}});
    }
    groups.back().contacts.push_back(c.contact);
  }
  IndexedCentres out;
  out.source = set.source;
  out.method.clear();
  for (const auto& g : groups) {
    const double a = g.angle;
    const auto sc = sphere_centre(g.contacts, probing, fmt::format("{}:{} ({}={:g})", set.source, g.line, axis, a));
    if (out.method.empty()) out.method = sc.method;
    if (out.method != sc.method) out.method = "mixed";
    out.centres.push_back({a * kDeg, sc.centre()});
    out.fits.push_back(sc);
  }
  return out;
}

const RotaryEstimate& RotaryAxisResult::best() const {
  if (least_squares) return *least_squares;
  if (triples) return *triples;
  throw Error("no estimate of the rotary axis");
}

RotaryAxisResult locate_rotary_axis(const NominalRotaryAxis& axis, IndexedCentres centres,
                                    const RotaryAxisOptions& options) {
  if (!options.triples && !options.least_squares) throw Error("expected at least one estimator of the rotary axis");
  if (options.triples && centres.centres.size() > kMaxTriplesCentres)
    throw InputError({centres.source, 0, ""},
                     fmt::format("{} indexations make too many triples for the triples estimator (at most {})",
                                 centres.centres.size(), kMaxTriplesCentres));
  RotaryAxisResult r;
  r.axis = axis;
  r.centres = std::move(centres);
  r.reject_sigma = options.triples_options.reject_sigma;
  if (options.least_squares) r.least_squares = estimate_by_least_squares(axis, r.centres.centres);
  if (options.triples) r.triples = estimate_by_triples(axis, r.centres.centres, options.triples_options);
  const auto names = rotary_quantity_names(axis.letter);
  for (const RotaryEstimate* e : {r.least_squares ? static_cast<const RotaryEstimate*>(&*r.least_squares) : nullptr,
                                  r.triples ? static_cast<const RotaryEstimate*>(&*r.triples) : nullptr}) {
    if (!e) continue;
    for (std::size_t q = 0; q < kRotaryQuantities; ++q)
      if (!std::isfinite(e->value[q]))
        throw InputError({"centres", 0, names[q]},
                         std::string("the estimate is not finite: are the centres of axis ") + axis.letter + "?");
  }
  return r;
}

}  // namespace mtcal
