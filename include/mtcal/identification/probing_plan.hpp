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
struct ProbeFeature {
  enum class Kind { Ball, Facet };
  std::string id;
  Kind kind = Kind::Ball;
  Vec3 position = Vec3::Zero();  // ball centre, or a point of the facet's plane
  Vec3 normal = Vec3::Zero();    // facet: unit outward normal; ball: zero
};

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
};

struct ProbingPlan {
  std::vector<ProbeFeature> features;
  std::vector<ProbingRecord> records;
  bool measured = false;  // the records hold readings (a measurement file), not only targets
  std::string source;

  std::optional<std::size_t> feature_index(const std::string& id) const;
  std::size_t residual_count() const;  // 3 per ball record, 1 per facet record
};

// The CSV files of plans and measurements are read and written by the formats layer (probing_plan_file.hpp).

}  // namespace mtcal
