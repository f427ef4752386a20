// Rotary-axis location test from sphere probing: contacts grouped by indexation into centres, both estimators.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "mtcal/probing/rotary_axis.hpp"
#include "mtcal/probing/sphere_probing.hpp"

namespace mtcal {

// One recorded trigger at an indexation of the rotary axis: the axis's angle as recorded (deg),
// the contact, and the 1-based line of its source it came from.
struct IndexedContact {
  double angle_deg = 0.0;
  ProbeContact contact;
  int line = 0;
};

// The contacts of one probing session in recorded order: the rotary axis turned between
// indexations (its letter) and where they came from (a file name, for messages).
struct ContactSet {
  std::string source = "contacts";
  char axis = 'C';
  std::vector<IndexedContact> contacts;
};

// Sphere centres per indexation, in order of first appearance, and how they were obtained.
struct IndexedCentres {
  std::string source = "centres";  // where the contacts or centres came from
  std::vector<MeasuredCentre> centres;
  std::vector<SphereCentre> fits;  // each centre's sphere fit; empty when the centres were given
  std::string method = "given";    // "five-point", "least-squares", "mixed" (both) or "given"
};

// Groups the contacts into indexations (consecutive contacts at the same angle) and fits one
// sphere per indexation (sphere_centre). Throws InputError naming the source and line where an
// angle met before comes again (a sphere probed twice would silently merge into one bad fit),
// or where an indexation's contacts do not give a sphere.
IndexedCentres centres_from_contacts(const ContactSet& contacts, const SphereProbing& probing);

// Above this many centres the triples (C(n, 3): 1.7e8 for 1000, about 20 s) take too long.
inline constexpr std::size_t kMaxTriplesCentres = 1000;

struct RotaryAxisOptions {
  bool triples = true;        // the all-triples estimator
  bool least_squares = true;  // the global least-squares circle
  TriplesOptions triples_options;
};

// Location errors of a rotary axis from its centres: either or both estimators.
struct RotaryAxisResult {
  NominalRotaryAxis axis;
  IndexedCentres centres;
  double reject_sigma = 2.0;  // the triples' rejection rule used
  std::optional<TriplesEstimate> triples;
  std::optional<LeastSquaresEstimate> least_squares;

  // With 3 centres the circle passes exactly through them: no redundancy, no uncertainty.
  bool uncertainty_known() const { return centres.centres.size() >= 4; }
  // The least-squares estimate when there is one, else the triples'.
  const RotaryEstimate& best() const;
  // Angle between the measured and the nominal axis direction (rad) of best().
  double tilt() const { return best().value[5]; }
};

// Runs the estimators options asks for (at least one). Throws InputError with more than
// kMaxTriplesCentres centres for the triples, or where an estimate is not finite (centres that
// are not of this axis).
RotaryAxisResult locate_rotary_axis(const NominalRotaryAxis& axis, IndexedCentres centres,
                                    const RotaryAxisOptions& options);

}  // namespace mtcal
