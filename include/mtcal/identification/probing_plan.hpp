// Probing plans and measurements for indirect calibration: balls and facets probed at indexations (SAMBA/TANGO).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "mtcal/model/machine.hpp"

namespace mtcal {

// An artefact feature on the workpiece side, nominal geometry in the workpiece frame (mm). Ball
// centres are where the probe centre (the tool point) goes; a facet is the plane n . p = n . point
// that the probe centre touches (stylus radius and pre-travel are part of its unknown offset).
// Two further instruments read the tool point in other ways (docs/identification.md):
// - Ballbar (ISO 230-4): a telescoping bar between a pivot on the table (position: its centre)
//   and a ball at the tool point, `radius` long; the machine moves the tool point on a circle of
//   that radius about the pivot in a principal plane (normal: +z XY, +x YZ, +y ZX) and the bar
//   reads its length. Unknowns of the setup: the pivot's centre in the plane and the bar's length
//   offset.
// - Laser (ISO 230-2): an interferometer's beam along `normal` (unit) through `position`; a
//   reflector at the tool point, its reading the displacement along the beam. Unknown of the
//   line: the reading's offset (the laser is zeroed wherever the run starts).
struct ProbeFeature {
  enum class Kind { Ball, Facet, Ballbar, Laser };
  std::string id;
  Kind kind = Kind::Ball;
  Vec3 position = Vec3::Zero();  // ball centre, a point of the facet's plane, the ballbar's pivot, a point of the beam
  Vec3 normal = Vec3::Zero();    // facet: unit outward normal; ballbar: its plane's normal; laser: the beam; ball: zero
  double radius = 0.0;           // ballbar: the bar's nominal length (mm)
};

// The feature kind's name in files and messages: ball, facet, ballbar, laser.
const char* feature_kind_name(ProbeFeature::Kind kind);
// Readings of a record of this kind: 3 (ball centre) or 1.
inline std::size_t readings_of(ProbeFeature::Kind kind) { return kind == ProbeFeature::Kind::Ball ? 3 : 1; }
// Unknowns of a feature of this kind: ball centre 3, facet offset 1, laser offset 1, ballbar 3: the
// pivot's centre in the circle's plane and the bar's length offset (the pivot's offset along the
// plane's normal changes the bar's length only at second order, ISO 230-4's cosine error: it stays
// nominal).
inline std::size_t unknowns_of(ProbeFeature::Kind kind) { return kind == ProbeFeature::Kind::Laser ? 1 : kind == ProbeFeature::Kind::Facet ? 1 : 3; }
// The principal plane of a ballbar (the index of its normal's axis: 2 XY, 0 YZ, 1 ZX); throws
// InputError for another normal.
int ballbar_plane(const ProbeFeature& f);
// The nominal tool point of a ballbar or laser record: on the circle at `at` (rad, from the plane's
// first axis: XY from +x, YZ from +y, ZX from +z, counter-clockwise about the normal) or on the beam
// `at` mm from its point. Throws InputError for a ballbar plane that is not a principal one.
Vec3 instrument_target(const ProbeFeature& f, double at);

// One probing: the rotary axes' indexation, the feature, the directions of motion of the linear
// axes at the contact (the facet's pre-moves, Mohammed 2019 Table 4.1; 0 for ball centres, which
// average touches from every side), and - in a measurement - the linear axes' readings when the
// probe centre is at the ball centre or touches the facet.
struct ProbingRecord {
  int indexation = 0;
  std::vector<double> q;         // joint values, chain order, internal units (mm, rad); the
                                 // linear ones are the readings (nominal targets in a plan)
  std::vector<std::int8_t> dir;  // per axis, chain order: -1, 0, +1
  std::size_t feature = 0;       // index into ProbingPlan::features
  int line = 0;                  // source line, for messages
  // Ballbar and laser records: where on the circle (angle, rad) or the beam (mm) the tool point is
  // commanded, and in a measurement the instrument's reading (the bar's length, the displacement
  // along the beam; mm). Their q are the commanded axis values (nominal targets in a plan).
  double at = 0.0;
  double reading = 0.0;
};

struct ProbingPlan {
  std::vector<ProbeFeature> features;
  std::vector<ProbingRecord> records;
  bool measured = false;  // the records hold readings (a measurement file), not only targets
  std::string source;

  std::optional<std::size_t> feature_index(const std::string& id) const;
  std::size_t residual_count() const;  // 3 per ball record, 1 per facet, ballbar or laser record
};

// The CSV files of plans and measurements are read and written by the formats layer (probing_plan_file.hpp).

}  // namespace mtcal
