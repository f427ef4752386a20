// mtcal fit-motion: laser and positioning files -> motion errors (EXX, EYX, EBX, ECC ...) in one parameter file.
#include <iostream>
#include <memory>

#include <fmt/format.h>

#include "common.hpp"
#include "history.hpp"
#include "mtcal/io/model/estimated_parameters_file.hpp"
#include "mtcal/io/instruments/motion_fit_files.hpp"
#include "mtcal/io/system/files.hpp"
#include "mtcal/io/json/motion_fit_json.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal::cli {
namespace {

struct FitMotionOptions {
  std::vector<std::string> files;
  std::string out, form = "auto", unit = "mm", target_unit, format = "auto";
  int degree = 3;
  double coverage = 2.0, wrap = 0;
  bool json_out = false;
};

int run_fit_motion(const FitMotionOptions& o) {
  std::vector<std::string> inputs;
  for (const auto& s : o.files) inputs.push_back(split_motion_file_spec(s).second);
  check_outputs(inputs, {o.out});
  if (!o.out.empty()) AtomicFile check(o.out);  // refuse a bad path before the work
  MotionFileOptions fo;
  fo.fit.form = o.form;
  fo.fit.max_degree = o.degree;
  fo.fit.coverage = o.coverage;
  fo.format = o.format;
  fo.unit = o.unit;
  fo.target_unit = o.target_unit;
  fo.wrap = o.wrap;
  const MotionFileFits fits = fit_motion_files(o.files, fo);
  for (const auto& w : fits.warnings) std::cerr << "mtcal: warning: " << w << "\n";
  if (!o.out.empty())
    write_estimated_parameters(o.out, fits.errors,
                               "Motion errors fitted by mtcal fit-motion (internal units mm, rad)\n" + command_line());
  if (o.json_out || recording()) {
    const Json j = motion_fits_json(fits.errors, fits.fits, fits.warnings, o.out);
    if (o.json_out) std::cout << json_text(j, 2) << "\n";
    emit_json(j, false);  // noted for --record (printed above as it always was)
    return 0;
  }
  for (std::size_t i = 0; i < fits.errors.size(); ++i) {
    const auto& f = fits.fits[i];
    std::cout << fmt::format("{} from {}: {}\n", fits.errors[i].name.str(), fits.errors[i].source, f.reason);
    for (const auto& n : f.notes) std::cout << "  note: " << n << "\n";
  }
  if (!o.out.empty()) std::cout << "wrote " << o.out << "\n";
  return 0;
}

}  // namespace

std::vector<Command> add_fit_motion_commands(CLI::App& app) {
  auto o = std::make_shared<FitMotionOptions>();
  auto* c = app.add_subcommand("fit-motion",
                               "Motion errors (EXX, EYX, EZX, EAX, EBX, ECX, ECC ...) from laser or positioning "
                               "files, as a table or a polynomial / Fourier series with reversal and uncertainties, "
                               "merged into one parameter file for --params");
  c->add_option("files", o->files,
                "Measurement files, each [ERROR=]FILE: a Renishaw .rtl/.rta export (its Axis:/Error: name the "
                "error), an ISO 230-2 .dat or a table (name the error: EXX=x.dat, EYX=straightness.csv)")
      ->required();
  c->add_option("--out", o->out, "Parameter file to write (mtcal eval/volumetric/compensate --params)");
  c->add_option("--form", o->form,
                "auto (smoothest form within --coverage x the repeatability, else a table), table, polynomial "
                "(linear axes) or fourier (rotary axes)")
      ->check(CLI::IsMember({"auto", "table", "polynomial", "fourier"}))
      ->capture_default_str();
  c->add_option("--degree", o->degree, "Highest polynomial degree / Fourier harmonic")
      ->check(CLI::Range(1, 3))
      ->capture_default_str();
  c->add_option("--coverage", o->coverage, "Criterion of --form auto: residual rms <= this x u of the means")
      ->check(CLI::PositiveNumber & kFinite)
      ->capture_default_str();
  c->add_option("--unit", o->unit, "Unit of a table's values unless its header says")
      ->check(kUnitName)
      ->capture_default_str();
  c->add_option("--target-unit", o->target_unit, "Unit of a table's targets (default: the values' unit)")
      ->check(kUnitName);
  c->add_option("--format", o->format, "Input format: auto, csv, dat or laser")
      ->check(CLI::IsMember({"auto", "csv", "dat", "laser"}))
      ->capture_default_str();
  c->add_option("--wrap", o->wrap, "Rotary tests: targets this far apart (e.g. 360) are one position")
      ->check(CLI::PositiveNumber & kFinite);
  c->add_flag(
      "--json", o->json_out,
      "Machine-readable output: errors[] with error, file, form, degree, targets, bidirectional, "
      "residual_rms, u_mean, reason, notes, parameters {NAME.suffix: {value, u}} (mm, rad); units, warnings, out");
  c->footer(
      "Examples:\n  mtcal fit-motion examples/instruments/x-axis.rtl --out x-axis.yaml\n"
      "  mtcal fit-motion EXX=examples/instruments/x-axis.rtl --form table --out x-table.yaml --json\n"
      "  mtcal compensate -m examples/instruments/mill.yaml --params x-axis.yaml --format linuxcnc \\\n"
      "      --linuxcnc-type 1 --points 11 --out comp-x\n"
      "Several files: mtcal fit-motion x.rtl EYX=x-straightness.rtl EBX=x-pitch.rtl --out x.yaml");
  return {{c, [o] { return run_fit_motion(*o); }}};
}

}  // namespace mtcal::cli
