// Rotary-axis location test from sphere probing: contacts grouped by indexation into centres, both estimators.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "mtcal/model/machine.hpp"
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
// sphere per indexation (sphere_centre). An angle met again later is a second indexation of the
// same position, fitted on its own (locate_rotary_axis averages the centres). Throws InputError
// naming the source and line where an indexation's contacts do not give a sphere.
IndexedCentres centres_from_contacts(const ContactSet& contacts, const SphereProbing& probing);

// One contact of a controller's probe log (LinuxCNC's PROBEOPEN log, the ISO #5061 CSV): the axis
// values at the trip, chain order, internal units (mm, rad; NaN for an axis the log does not carry),
// and its 1-based line.
struct LoggedAxisValues {
  std::vector<double> q;
  int line = 0;
};

// A probe log as the contacts of a rotary-axis test on machine m turning `axis`: each contact's
// angle is the logged value of that axis; its point what simulate_probing records, the nominal tool
// point at the logged linear axes with the rotary axes at zero (machine coordinates: workpiece frame
// plus the workpiece origin); its approach, which a log does not hold, the direction from the
// contact to the centre of a free sphere fitted to its indexation's contacts (>= 4 not on one
// plane; else -z): a touch moves towards the centre. Throws InputError (source, line) for a log
// without contacts, without that axis's value, without X, Y or Z, or where another rotary axis
// does not stay at its first line's value; ModelError when the axis is
// not a rotary axis of m.
ContactSet contacts_from_log(const Machine& m, char axis, const std::vector<LoggedAxisValues>& log,
                             const std::string& source);

// The most centres the triples estimator takes: its counters hold C(n, 3) (1.7e17 for 1e6) and
// its sums take 6 kB per centre. Time is the bound in practice (C(n, 3) triples at about 9e6 per
// second and thread: 1000 centres take 20 s on one thread): callers estimate it first with
// triples_cost (mtcal rotary-axis refuses beyond --max-time).
inline constexpr std::size_t kMaxTriplesCentres = 1'000'000;

struct RotaryAxisOptions {
  bool triples = true;        // the all-triples estimator
  bool least_squares = true;  // the global least-squares circle
  TriplesOptions triples_options;
  // Beyond this angle (rad) between the measured and the nominal axis direction the ISO 230-7
  // location errors (small angles about the nominal line) are not estimated: the result gives
  // the measured line only.
  double max_tilt = 0.1;
};

// Where the instrument's coordinates sit in the machine's: machine = rotation * instrument +
// translation (a probe or tracker whose axes are not the machine's).
struct InstrumentFrame {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Point3 translation = Point3::Zero();
};
// Rotation of the angles (rad) rx about x, then ry about y, then rz about z: Rz Ry Rx.
InstrumentFrame frame_from_angles(double rx, double ry, double rz, const Point3& translation);
void apply_frame(IndexedCentres& centres, const InstrumentFrame& frame);

// Indexations that are one position of the axis (angles a whole number of turns apart: -360,
// 0, 360 deg) merged into one centre, the mean of their centres, at the angle nearest zero, in
// the order of first appearance. Returns one line per merge for the user.
std::vector<std::string> merge_wrapped_centres(IndexedCentres& centres);

// The measured axis line with no assumption on its direction: the least-squares circle of the
// centres, its unit normal (sign: towards the nominal direction, or +x/+y/+z by the largest
// component when perpendicular), the line's point nearest the nominal point, the angle to the
// nominal direction (rad, 0..pi/2).
struct MeasuredAxisLine {
  Point3 point = Point3::Zero();
  Point3 direction = Point3::UnitZ();
  double radius = 0.0;
  double tilt = 0.0;
  double rms = 0.0;  // the centres' in-plane residual rms, mm
};
MeasuredAxisLine measure_axis_line(const NominalRotaryAxis& axis, const std::vector<MeasuredCentre>& centres);

// Location errors of a rotary axis from its centres: either or both estimators.
struct RotaryAxisResult {
  NominalRotaryAxis axis;
  IndexedCentres centres;
  MeasuredAxisLine line;           // always
  bool located = true;             // false: tilt beyond options.max_tilt, no ISO 230-7 estimates
  std::vector<std::string> notes;  // merged indexations, why the location errors are not given
  double reject_sigma = 2.0;       // the triples' rejection rule used
  std::optional<TriplesEstimate> triples;
  std::optional<LeastSquaresEstimate> least_squares;

  // With 3 centres the circle passes exactly through them: no redundancy, no uncertainty.
  bool uncertainty_known() const { return centres.centres.size() >= 4; }
  // The least-squares estimate when there is one, else the triples'.
  const RotaryEstimate& best() const;
  // Angle between the measured and the nominal axis direction (rad) of best().
  double tilt() const { return best().value[5]; }
};

// Merges wrapped indexations (merge_wrapped_centres), measures the line, then runs the estimators
// options asks for (at least one) when the line is within options.max_tilt of the nominal
// direction. Throws InputError with more than kMaxTriplesCentres centres for the triples, or where an estimate is not
// finite (centres that are not of this axis).
RotaryAxisResult locate_rotary_axis(const NominalRotaryAxis& axis, IndexedCentres centres,
                                    const RotaryAxisOptions& options);

}  // namespace mtcal
