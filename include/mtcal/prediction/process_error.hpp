// Program-generated process error e_prog (Yaqoob 2017 sec. 3.7): mechanistic milling force and two-section tool
// deflection.
#pragma once

#include <optional>
#include <span>
#include <vector>

#include "mtcal/prediction/regression.hpp"

namespace mtcal {

// An end mill as a cantilever out of the holder: the fluted part (length flute_length from the
// tip, second moment of area of an equivalent diameter) and the solid shank above it. Units: mm,
// N, N/mm^2 (MPa).
struct EndMill {
  double diameter = 10.0;             // D (mm)
  int teeth = 3;                      // N
  double helix_deg = 0.0;             // 0: straight flutes
  double overhang = 40.0;             // L: length out of the holder (mm)
  double flute_length = 22.0;         // L1, from the tip (mm), <= overhang
  double flute_diameter_ratio = 0.8;  // equivalent diameter of the fluted section / D (a common choice for 2-4 flutes)
  double young_modulus = 600000.0;    // E (N/mm^2): cemented carbide
};

// Linear-edge mechanistic force model (Budak, ref. [43] of the thesis; Altintas 2000 ch. 2):
// on an axial slice dz of a tooth at immersion phi (measured from +Y, clockwise, feed along +X)
// with chip thickness h = fz sin(phi):
//   dFt = (Ktc h + Kte) dz,  dFr = (Krc h + Kre) dz,
//   dFx = -dFt cos(phi) - dFr sin(phi),  dFy = dFt sin(phi) - dFr cos(phi).
// Coefficients in N/mm^2 (cutting) and N/mm (edge); the defaults are typical of aluminium 7075.
struct CuttingCoefficients {
  double ktc = 796.0, krc = 168.0, kte = 27.7, kre = 30.8;
};

struct CutConditions {
  double radial_depth = 1.0;    // ae (mm)
  double axial_depth = 5.0;     // ap (mm)
  double feed = 200.0;          // F (mm/min)
  double spindle_speed = 3500;  // S (rpm)
  bool down_milling = true;     // climb: the tooth leaves the wall at phi = pi
};

struct MillingForces {
  double mean_x = 0, mean_y = 0;      // mean over a tooth period (N)
  double peak_y = 0;                  // largest |Fy| over a tooth period: Fy is normal to a wall along X
  std::vector<double> angle, fx, fy;  // sampled tool rotation (rad) and forces (N)
};

// Forces over one tooth period, sampled at `samples` rotation angles with `slices` axial slices
// (helix lag phi - z tan(helix) / R). InputError for non-physical inputs (ae > D, zero teeth ...).
MillingForces milling_forces(const EndMill& tool, const CuttingCoefficients& k, const CutConditions& cut,
                             int samples = 360, int slices = 50);

// Deflection at height z (from the tip) of the two-section cantilever under a force F at height
// zf (from the tip), by the unit-load method: delta = F / E * integral over the beam of
// (s_F - s)(s_z - s) / I(s), s from the clamp. With equal sections it is DeVor's eq. 2.6. The
// thesis' eq. 3.16 is not used: as printed it divides by E I^2 (not a length) and, even with I,
// does not reduce to F L^3 / 3EI for a uniform tool (docs/prediction.md).
double cantilever_deflection(const EndMill& tool, double force, double zf, double z);

// e_prog: the deflection at the tip (z = 0) under the peak wall-normal force applied at the
// middle of the axial depth (zf = ap / 2), in mm.
double program_generated_error(const EndMill& tool, const CuttingCoefficients& k, const CutConditions& cut);

// Calibration (sec. 3.7, eq. 5.49-5.51): the measured process errors regressed on e_prog at the
// feeds they were measured at; spec is the thesis' choice of form (logistic_ln for e_pf_x,
// e_pf_y, saturation for e_splf_z).
struct Calibration {
  std::vector<double> e_prog;  // per feed
  FitResult fit;               // measured = f(e_prog)
};
Calibration calibrate_process_error(const EndMill& tool, const CuttingCoefficients& k, CutConditions cut,
                                    std::span<const double> feeds, std::span<const double> measured,
                                    const ModelSpec& spec);

// ---- What mtcal process-error reports ----

// e_prog and the forces behind it at one feed.
struct ProcessErrorPoint {
  double feed = 0;  // F (mm/min)
  double fz = 0;    // feed per tooth F / (N S) (mm)
  MillingForces forces;
  double e_prog = 0;  // mm
};
struct ProcessErrorStudy {
  EndMill tool;
  CuttingCoefficients k;
  CutConditions cut;                       // feed: that of the last point
  std::vector<ProcessErrorPoint> points;   // per feed, in the given order
  std::vector<double> measured;            // measured process errors per feed, or empty
  std::optional<Calibration> calibration;  // with measured: measured = f(e_prog)
};
// e_prog per feed, and with measured values (one per feed) the calibration of spec on it.
// InputError for a count mismatch; Error if the calibration does not converge.
ProcessErrorStudy process_error_study(const EndMill& tool, const CuttingCoefficients& k, const CutConditions& cut,
                                      std::span<const double> feeds, std::span<const double> measured,
                                      const std::optional<ModelSpec>& spec);

}  // namespace mtcal
