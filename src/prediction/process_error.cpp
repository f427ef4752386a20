#include "mtcal/prediction/process_error.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "mtcal/util/errors.hpp"

namespace mtcal {
namespace {

void require(bool ok, const char* field, const std::string& what) {
  if (!ok) throw InputError({"", 0, field}, what);
}

void check_tool(const EndMill& t) {
  require(t.diameter > 0 && std::isfinite(t.diameter), "diameter",
          fmt::format("expected a tool diameter > 0 mm, found {:g}", t.diameter));
  require(t.teeth >= 1 && t.teeth <= 32, "teeth", fmt::format("expected 1 to 32 teeth, found {}", t.teeth));
  require(t.helix_deg >= 0 && t.helix_deg < 80, "helix",
          fmt::format("expected a helix angle in [0, 80) deg, found {:g}", t.helix_deg));
  require(t.overhang > 0 && std::isfinite(t.overhang), "overhang",
          fmt::format("expected an overhang > 0 mm, found {:g}", t.overhang));
  require(t.flute_length > 0 && t.flute_length <= t.overhang, "flute_length",
          fmt::format("expected a flute length in (0, overhang = {:g}] mm, found {:g}", t.overhang, t.flute_length));
  require(t.flute_diameter_ratio > 0 && t.flute_diameter_ratio <= 1, "flute_diameter_ratio",
          fmt::format("expected a ratio in (0, 1], found {:g}", t.flute_diameter_ratio));
  require(t.young_modulus > 0 && std::isfinite(t.young_modulus), "young_modulus",
          fmt::format("expected E > 0 N/mm^2, found {:g}", t.young_modulus));
}

}  // namespace

MillingForces milling_forces(const EndMill& tool, const CuttingCoefficients& k, const CutConditions& cut, int samples,
                             int slices) {
  check_tool(tool);
  require(cut.radial_depth > 0 && cut.radial_depth <= tool.diameter, "radial_depth",
          fmt::format("expected a radial depth in (0, D = {:g}] mm, found {:g}", tool.diameter, cut.radial_depth));
  require(cut.axial_depth > 0 && cut.axial_depth <= tool.flute_length, "axial_depth",
          fmt::format("expected an axial depth in (0, flute length = {:g}] mm, found {:g}", tool.flute_length,
                      cut.axial_depth));
  require(cut.feed > 0 && std::isfinite(cut.feed), "feed",
          fmt::format("expected a feed > 0 mm/min, found {:g}", cut.feed));
  require(cut.spindle_speed > 0 && std::isfinite(cut.spindle_speed), "spindle_speed",
          fmt::format("expected a spindle speed > 0 rpm, found {:g}", cut.spindle_speed));
  require(samples >= 8 && slices >= 1, "samples", "expected at least 8 samples and 1 slice");
  const double pi = std::numbers::pi;
  const double fz = cut.feed / (tool.teeth * cut.spindle_speed);  // mm per tooth
  // Immersion: up milling enters at 0 and leaves at arccos(1 - 2 ae / D); down milling enters
  // at arccos(2 ae / D - 1) and leaves at pi (phi from +Y, clockwise).
  const double sweep = std::acos(1.0 - 2.0 * cut.radial_depth / tool.diameter);
  const double phi_st = cut.down_milling ? pi - sweep : 0.0;
  const double phi_ex = cut.down_milling ? pi : sweep;
  const double pitch = 2.0 * pi / tool.teeth;
  const double dz = cut.axial_depth / slices;
  const double lag = 2.0 * std::tan(tool.helix_deg * pi / 180.0) / tool.diameter;  // rad per mm of height
  MillingForces f;
  for (int i = 0; i < samples; ++i) {
    const double theta = pitch * i / samples;
    double fx = 0, fy = 0;
    for (int j = 0; j < tool.teeth; ++j)
      for (int s = 0; s < slices; ++s) {
        const double z = (s + 0.5) * dz;
        double phi = std::fmod(theta + j * pitch - lag * z, 2.0 * pi);
        if (phi < 0) phi += 2.0 * pi;
        if (phi < phi_st || phi > phi_ex) continue;
        const double h = fz * std::sin(phi);
        const double ft = (k.ktc * h + k.kte) * dz, fr = (k.krc * h + k.kre) * dz;
        fx += -ft * std::cos(phi) - fr * std::sin(phi);
        fy += ft * std::sin(phi) - fr * std::cos(phi);
      }
    f.angle.push_back(theta);
    f.fx.push_back(fx);
    f.fy.push_back(fy);
    f.mean_x += fx / samples;
    f.mean_y += fy / samples;
    f.peak_y = std::max(f.peak_y, std::abs(fy));
  }
  return f;
}

double cantilever_deflection(const EndMill& tool, double force, double zf, double z) {
  check_tool(tool);
  const double L = tool.overhang;
  require(zf >= 0 && zf <= L, "zf", fmt::format("expected the force height in [0, {:g}] mm, found {:g}", L, zf));
  require(z >= 0 && z <= L, "z", fmt::format("expected the height in [0, {:g}] mm, found {:g}", L, z));
  const double pi = std::numbers::pi;
  const double i_shank = pi * std::pow(tool.diameter, 4) / 64.0;
  const double i_flute = pi * std::pow(tool.flute_diameter_ratio * tool.diameter, 4) / 64.0;
  // s from the clamp; the shank is [0, sc], the flutes [sc, L].
  const double sf = L - zf, sz = L - z, sc = L - tool.flute_length;
  const auto G = [&](double s) { return sf * sz * s - (sf + sz) * s * s / 2.0 + s * s * s / 3.0; };
  const double top = std::min(sf, sz);
  const double shank_end = std::min(top, sc);
  double integral = (G(shank_end) - G(0.0)) / i_shank;
  if (top > sc) integral += (G(top) - G(sc)) / i_flute;
  return force / tool.young_modulus * integral;
}

double program_generated_error(const EndMill& tool, const CuttingCoefficients& k, const CutConditions& cut) {
  const MillingForces f = milling_forces(tool, k, cut);
  return cantilever_deflection(tool, f.peak_y, cut.axial_depth / 2.0, 0.0);
}

Calibration calibrate_process_error(const EndMill& tool, const CuttingCoefficients& k, CutConditions cut,
                                    std::span<const double> feeds, std::span<const double> measured,
                                    const ModelSpec& spec) {
  Calibration c;
  for (double F : feeds) {
    cut.feed = F;
    c.e_prog.push_back(program_generated_error(tool, k, cut));
  }
  c.fit = fit_model(spec, c.e_prog, measured);
  return c;
}

}  // namespace mtcal

namespace mtcal {

ProcessErrorStudy process_error_study(const EndMill& tool, const CuttingCoefficients& k, const CutConditions& cut,
                                      std::span<const double> feeds, std::span<const double> measured,
                                      const std::optional<ModelSpec>& spec) {
  ProcessErrorStudy out;
  out.tool = tool;
  out.k = k;
  out.cut = cut;
  if (spec && measured.size() != feeds.size())
    throw InputError({"measured process errors", 0, ""},
                     fmt::format("expected one measured process error per feed ({}), found {}", feeds.size(),
                                 measured.size()));
  for (double F : feeds) {
    CutConditions c = cut;
    c.feed = F;
    ProcessErrorPoint p{F, F / (tool.teeth * c.spindle_speed), milling_forces(tool, k, c), 0.0};
    p.e_prog = program_generated_error(tool, k, c);
    out.points.push_back(std::move(p));
  }
  if (spec) {
    out.measured.assign(measured.begin(), measured.end());
    out.calibration = calibrate_process_error(tool, k, cut, feeds, measured, *spec);
    if (!out.calibration->fit.converged)
      throw Error("the calibration " + spec->label() + " did not converge: " + out.calibration->fit.message);
  }
  return out;
}

}  // namespace mtcal
