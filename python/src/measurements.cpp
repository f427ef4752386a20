// Python bindings from measurements to parameter files: laser files, fit-motion, ballbar parameters, Etalon files.
#include "common.hpp"
#include "results.hpp"
#include "mtcal/identification/machine_params.hpp"
#include "mtcal/io/compensation/output.hpp"
#include "mtcal/io/instruments/laser_files.hpp"
#include "mtcal/io/instruments/motion_fit_files.hpp"
#include "mtcal/io/json/identification_json.hpp"
#include "mtcal/io/json/motion_fit_json.hpp"
#include "mtcal/io/model/estimated_parameters_file.hpp"
#include "mtcal/io/model/etalon_file.hpp"
#include "mtcal/io/system/files.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal::python {

using namespace pybind11::literals;

namespace {

// name.suffix -> value of every coefficient of a motion error, or name -> value of a location error.
py::dict estimated_values(const EstimatedError& e) {
  py::dict d;
  if (e.motion) {
    for (std::size_t k = 0; k < e.motion->parameter_count(); ++k)
      d[py::str(e.name.str() + "." + e.motion->parameter_suffix(k))] = e.motion->parameter(k);
  } else {
    d[py::str(e.name.str())] = e.value;
  }
  return d;
}

const char* kParamsDoc =
    "A parameter file (docs/machine-file.md, 'Parameter files') that Machine.load(params=[...]), "
    "Machine.with_parameter_file and every command's --params read: each error in internal units (mm, rad) at "
    "full precision with its provenance and standard uncertainties as comments; description is the first "
    "comment.";

}  // namespace

void bind_measurements(py::module_& m) {
  // ---------------------------------------------------------------- laser files
  py::class_<LaserFile>(m, "LaserFile", "A Renishaw laser test (.rtl linear, .rta rotary) as its file gives it.")
      .def_readonly("runs", &LaserFile::runs, "PositioningRuns: deviations per target and run, in the file's units")
      .def_readonly("kind", &LaserFile::kind, "'linear', 'rotary', 'straightness' or 'angular'")
      .def_readonly("axis", &LaserFile::axis, "The USER-TEXT Axis (upper case), '' if not given")
      .def_readonly("component", &LaserFile::component, "The ISO 230-1 error the file names (Error: EYX), or ''")
      .def_readonly("bidirectional", &LaserFile::bidirectional)
      .def_property_readonly(
          "error_name", [](const LaserFile& f) { return laser_error_name(f); },
          "The motion error the file measured (its Error:, else EXX for a linear test of X, ECC for a rotary test "
          "of C), '' when it does not say")
      .def_property_readonly(
          "report_metadata", [](const LaserFile& f) { return metadata_dict(laser_report_metadata(f.runs)); },
          "The acceptance-report fields the header states (machine, serial, date, temperatures, instrument ...)");
  m.def("read_laser_file", &read_laser_file, "path"_a,
        "A Renishaw LaserXL / CARTO ASCII export (.rtl linear, .rta rotary; a HEADER Type: line overrides the "
        "extension): the runs as deviations, the test's kind, axis and error, its metadata "
        "(docs/instrument-files.md). read_positioning reads the same runs for iso230_2.");
  m.def(
      "parse_laser_file",
      [](const std::string& text, const std::string& source, bool rotary) {
        return parse_laser_file(text, source, rotary);
      },
      "text"_a, "source"_a = "<string>", py::kw_only(), "rotary"_a = false,
      "The same from text; rotary: the .rta defaults (deg, arcsec).");

  // ---------------------------------------------------------------- estimated errors
  py::class_<EstimatedError>(m, "EstimatedError",
                             "One error estimated from a measurement, internal units (mm, rad), with uncertainties.")
      .def_property_readonly("name", [](const EstimatedError& e) { return e.name.str(); })
      .def_property_readonly("is_motion", [](const EstimatedError& e) { return e.motion.has_value(); },
                             "A motion error (a function of its axis); else a location error (value)")
      .def_readonly("value", &EstimatedError::value, "A location error's value (0 for a motion error)")
      .def_property_readonly("parameters", &estimated_values,
                             "NAME.SUFFIX -> value of every coefficient of a motion error (suffixes as in the "
                             "parameter file: 0..3 and b, or the table's), or NAME -> value")
      .def_property_readonly(
          "uncertainty", [](const EstimatedError& e) { return to_array(e.uncertainty); },
          "Standard uncertainties, one per entry of parameters")
      .def_readonly("rotary_argument", &EstimatedError::rotary_argument)
      .def_readonly("source", &EstimatedError::source, "The measurement file")
      .def_readonly("method", &EstimatedError::method, "How: the form and its criterion, the diagnostic term ...")
      .def(
          "to_dict", [](const EstimatedError& e) { return to_py(estimated_parameters_json({e})); },
          "{NAME[.SUFFIX]: {value, u}} of the non-zero coefficients, as `mtcal ballbar --to-params --json`'s "
          "parameters");
  py::class_<MotionFit>(m, "MotionFit", "How one motion error was fitted.")
      .def_readonly("form", &MotionFit::form, "'table', 'polynomial' or 'fourier'")
      .def_readonly("degree", &MotionFit::degree, "Polynomial degree or number of harmonics (0: a table)")
      .def_readonly("residual_rms", &MotionFit::residual_rms, "Of the form against the target means (mm or rad)")
      .def_readonly("u_mean", &MotionFit::u_mean, "rms standard uncertainty of the target means (0: unknown)")
      .def_readonly("targets", &MotionFit::targets)
      .def_readonly("bidirectional", &MotionFit::bidirectional)
      .def_readonly("reason", &MotionFit::reason)
      .def_readonly("notes", &MotionFit::notes);
  py::class_<MotionFileFits>(m, "MotionFitResult", "fit_motion's result: one EstimatedError and MotionFit per file.")
      .def_readonly("errors", &MotionFileFits::errors)
      .def_readonly("fits", &MotionFileFits::fits)
      .def_readonly("warnings", &MotionFileFits::warnings, "What the readers kept but did not use")
      .def(
          "to_dict", [](const MotionFileFits& f, const std::string& out) {
            return to_py(motion_fits_json(f.errors, f.fits, f.warnings, out));
          },
          "out"_a = "", "As `mtcal fit-motion --json` (out: the parameter file named, as --out).")
      .def(
          "parameters_yaml",
          [](const MotionFileFits& f, const std::string& description) {
            return estimated_parameters_yaml(f.errors, description);
          },
          "description"_a = "Motion errors fitted by mtcal fit-motion (internal units mm, rad)",
          "The parameter file's text (what write_parameters writes).")
      .def(
          "write_parameters",
          [](const MotionFileFits& f, const std::string& path, const std::string& description) {
            write_estimated_parameters(path, f.errors, description);
          },
          "path"_a, "description"_a = "Motion errors fitted by mtcal fit-motion (internal units mm, rad)",
          "Writes the parameter file (complete or not at all), as `mtcal fit-motion --out`.");
  m.def(
      "fit_motion",
      [](const std::vector<std::string>& files, const std::string& form, int degree, double coverage,
         const std::string& unit, const std::string& target_unit, const std::string& format, double wrap) {
        if (degree < 1 || degree > 3) throw py::value_error("degree: expected 1, 2 or 3, found " + std::to_string(degree));
        if (!(coverage > 0)) throw py::value_error("coverage: expected a number > 0");
        if (!(wrap >= 0)) throw py::value_error("wrap: expected a number >= 0");
        MotionFileOptions o;
        o.fit.form = form;
        o.fit.max_degree = degree;
        o.fit.coverage = coverage;
        o.unit = unit;
        o.target_unit = target_unit;
        o.format = format;
        o.wrap = wrap;
        return fit_motion_files(files, o);
      },
      "files"_a, py::kw_only(), "form"_a = "auto", "degree"_a = 3, "coverage"_a = 2.0, "unit"_a = "mm",
      "target_unit"_a = "", "format"_a = "auto", "wrap"_a = 0.0,
      R"(Motion errors (EXX, EYX, EBX, ECC ...) from laser or positioning files, as `mtcal fit-motion`.

files: each "[ERROR=]FILE": a Renishaw .rtl/.rta export names its error; an ISO 230-2 .dat or a
table must be named ("EYX=straightness.csv"). form: 'auto' (the smoothest form within coverage x
the repeatability, else a table), 'table', 'polynomial' (linear axes) or 'fourier' (rotary axes);
degree: highest polynomial degree / harmonic (1..3); unit, target_unit: a table's units; format:
'auto', 'csv', 'dat' or 'laser'; wrap: targets this far apart are one position (e.g. 360).
Returns MotionFitResult (errors, fits, warnings, to_dict(), write_parameters(path)).)");

  m.def(
      "ballbar_parameters",
      [](const BallbarResult& r, bool squareness, bool scale, bool backlash) {
        if (!r.diagnosis)
          throw py::value_error("result: expected a ballbar result of both directions with its diagnosis "
                                "(ballbar(..., diagnose=True) without direction)");
        return ballbar_parameters(*r.diagnosis, r.plane, {squareness, scale, backlash}, r.trace.source);
      },
      "result"_a, py::kw_only(), "squareness"_a = true, "scale"_a = true, "backlash"_a = true,
      "The ISO 230-4 diagnosis of a BallbarResult as model parameters (docs/fit-motion.md): squareness -> EC0Y "
      "(XY), EA0Z (YZ), EB0Z (ZX); scaling mismatch -> the linear terms of both axes' positioning errors; "
      "backlash -> their reversal terms. As `mtcal ballbar --to-params --terms ...`. A list of EstimatedError.");
  m.def(
      "estimated_parameters_dict",
      [](const std::vector<EstimatedError>& errors) { return to_py(estimated_parameters_json(errors)); },
      "errors"_a, "{NAME[.SUFFIX]: {value, u}} of the errors, as `mtcal ballbar --to-params --json`'s parameters.");
  m.def("parameters_yaml", &estimated_parameters_yaml, "errors"_a, "description"_a, kParamsDoc);
  m.def("write_parameters", &write_estimated_parameters, "path"_a, "errors"_a, "description"_a,
        (std::string(kParamsDoc) + " Written complete or not at all (ballbar --to-params, fit-motion --out).").c_str());

  // ---------------------------------------------------------------- Etalon exchange files
  py::class_<EtalonBlock>(m, "EtalonBlock", "One block of an Etalon exchange file.")
      .def_readonly("name", &EtalonBlock::name, "'C0B' (a position error) or 'EXY' (a component error)")
      .def_readonly("line", &EtalonBlock::line)
      .def_readonly("table", &EtalonBlock::table, "A component error's Gridpoints, else VALUE")
      .def_readonly("value", &EtalonBlock::value, "A position error: mm or rad")
      .def_property_readonly(
          "argument", [](const EtalonBlock& b) { return to_array(b.argument); }, "mm or deg")
      .def_property_readonly(
          "error", [](const EtalonBlock& b) { return to_array(b.error); }, "mm or rad");
  m.def(
      "read_etalon",
      [](const std::string& path) { return parse_etalon(read_text_file(path, "Etalon file"), path); }, "path"_a,
      "The blocks of an Etalon exchange file (TF5280 'Etalon Exchange Format'). Machine.with_parameter_file "
      "and --params apply one to a machine.");
  m.def("parse_etalon", &parse_etalon, "text"_a, "source"_a = "<string>", "The same from text.");
  m.def(
      "write_etalon",
      [](const Machine& mm, const std::string& dir, std::size_t points) {
        CompensationOptions o;
        o.points = points;
        TargetOutput out;
        {
          LongCall release;
          out = compensation_target("etalon").run(mm, o);
        }
        write_target_output(dir, out);
        return out;
      },
      "machine"_a, "dir"_a, py::kw_only(), "points"_a = std::size_t{0},
      "The machine's errors as an Etalon exchange file: dir/volcomp.etalon and README.txt, all or none; as "
      "`mtcal compensate --format etalon --out DIR` (compensate(machine, 'etalon') gives the same without "
      "writing). Returns the TargetOutput.");
}

}  // namespace mtcal::python
