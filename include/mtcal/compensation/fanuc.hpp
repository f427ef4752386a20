// FANUC pitch error compensation from a machine model: parameters 3620-3625 and incremental compensation values per
// axis.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "mtcal/compensation/compensation.hpp"
#include "mtcal/model/machine.hpp"

namespace mtcal {

// One axis's pitch error compensation. Point numbers n from min_number to max_number; the value
// of point n is the compensation increment over the section ending at compensation position n,
// ((n - reference_number - 1)·interval, (n - reference_number)·interval], measured from the
// reference position (FANUC Series 0i-PB Parameter Manual B-63980EN/01, parameters 3620-3625 and
// the examples on p. 100). Values are counts of detection_unit × magnification (parameter 3623).
// The values are written as CORRECTIONS (c = -e, the amount the control adds): the sign is not
// confirmed by a public FANUC source and must be checked on the control.
struct FanucPitchAxis {
  char axis = 'X';
  int axis_number = 1;  // controlled axis number: X Y Z then A B C, as present
  bool rotary = false;
  int reference_number = 0;   // 3620: point of the reference position
  int min_number = 0;         // 3621: farthest point on the - side
  int max_number = 0;         // 3622: farthest point on the + side
  int magnification = 1;      // 3623
  double interval = 0.0;      // 3624: mm or deg (a whole number of detection units)
  double travel_per_rev = 0;  // 3625: deg, rotary axes only
  double detection_unit = 0.001;
  std::vector<int> values;  // values[n - min_number], n = min_number ... max_number
  // Compensation positions of the section ends, from min_number - 1 to max_number (mm or deg), and
  // the absolute correction the values add up to there (mm or deg; zero at the reference position).
  std::vector<double> node, absolute;
};

struct FanucCompensation {
  std::vector<FanucPitchAxis> axes;
  CompensationSummary summary;
};

// Points per axis at most (sections from the farthest - to the farthest + point; "a maximum of 128
// compensation points between the extremes" is assumed), value range per point (assumed -128 ... 127),
// magnification range (parameter 3623: 0 ... 100).
constexpr std::size_t kFanucMaxPoints = 128;
constexpr int kFanucMaxValue = 127;
constexpr int kFanucMaxMagnification = 100;

// Per linear axis: the tool point's error along the axis when it alone moves (others at the
// reference), mean of both directions, relative to the reference position (axis position 0, where
// mtcal's joint is zero); per rotary axis: its positioning error (EAA, EBB, ECC) over one turn,
// 0 ... 360 deg, the values summing to zero (the non-periodic part is listed as not held). The
// interval is the travel / (points - 1) rounded up to a detection unit, the grid anchored at the
// reference position; the magnification is the smallest that keeps every value in range.
// `detection_unit` (mm and deg per count) from CompensationOptions::detection_unit.
// Residual: the control adds the absolute correction, linearly interpolated between the compensation
// positions (ends held; rotary axes modulo 360 deg).
FanucCompensation compensate_fanuc(const Machine& m, const CompensationOptions& o);

}  // namespace mtcal
