// Python bindings of prediction (Yaqoob 2017 regressions, prediction models, separation, process error) and of the
// compensation targets' registry and the simulated LinuxCNC probe; their files.
#include <map>
#include <optional>

#include "common.hpp"
#include "mtcal/compensation/compensation.hpp"
#include "mtcal/compensation/tables.hpp"
#include "mtcal/io/compensation/linuxcnc_probe.hpp"
#include "mtcal/io/compensation/output.hpp"
#include "mtcal/io/compensation/output_json.hpp"
#include "mtcal/io/text/csv.hpp"
#include "mtcal/io/gcode/reader.hpp"
#include "mtcal/io/json/prediction_json.hpp"
#include "mtcal/io/model/prediction_model_file.hpp"
#include "mtcal/io/points/prediction_points.hpp"
#include "mtcal/io/instruments/separation_file.hpp"
#include "mtcal/prediction/prediction_model.hpp"
#include "mtcal/prediction/process_error.hpp"
#include "mtcal/prediction/regression.hpp"
#include "mtcal/prediction/separation.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/report/prediction.hpp"
#include "mtcal/report/report.hpp"

namespace mtcal::python {

using namespace pybind11::literals;

namespace {

ModelSpec one_spec(const std::string& label, const char* name) {
  const auto specs = parse_model_specs(label, name);
  if (specs.size() != 1) throw py::value_error(std::string(name) + ": expected one model form, found '" + label + "'");
  return specs[0];
}

PredictionPoints make_points(py::dict columns, const std::string& source) {
  PredictionPoints p;
  p.source = source;
  std::vector<std::vector<double>> cols;
  for (auto item : columns) {
    const auto name = item.first.cast<std::string>();
    const std::string what = "columns['" + name + "']";
    cols.push_back(as_std_vector(item.second, what.c_str()));
    if (cols.back().size() != cols.front().size())
      throw py::value_error(what + ": expected " + std::to_string(cols.front().size()) +
                            " values like the first column");
    p.columns.push_back(name);
  }
  const std::size_t n = cols.empty() ? 0 : cols[0].size();
  for (std::size_t i = 0; i < n; ++i) {
    std::vector<double> row;
    for (const auto& c : cols) row.push_back(c[i]);
    p.rows.push_back(std::move(row));
    p.lines.push_back(static_cast<int>(i) + 1);
  }
  return p;
}

struct Prediction {
  PredictionModel model;
  PredictionRun run;
};

Prediction predict(const PredictionModel& m, py::handle points_obj, const std::map<std::string, double>& constants,
                   bool strict, bool compensation) {
  const PredictionPoints t = py::isinstance<PredictionPoints>(points_obj)
                                 ? points_obj.cast<PredictionPoints>()
                                 : make_points(points_obj.cast<py::dict>(), "points");
  // As mtcal predict: every variable the model reads must be a column or a constant, before any work.
  for (const auto& v : missing_variables(m, t, constants)) {
    std::string users;
    for (const auto& u : components_reading(m, v)) users += (users.empty() ? "" : ", ") + u;
    throw InputError({t.source, 0, v},
                     "missing column '" + v + "' needed by " + users + " (give it as a column or in constants)");
  }
  if (compensation && t.column("step") < 0)
    throw InputError({t.source, 0, "step"}, "compensation needs a 'step' column in the points");
  return {m, predict_points(m, t, constants, strict, compensation)};
}

py::array_t<double> rows_array(const std::vector<std::vector<double>>& rows, std::size_t cols) {
  std::vector<double> flat;
  for (const auto& r : rows) flat.insert(flat.end(), r.begin(), r.end());
  if (cols == 0 || rows.empty())
    return new_array({static_cast<py::ssize_t>(rows.size()), static_cast<py::ssize_t>(cols)});
  return to_array(flat, cols);
}

struct Regression {
  ModelComparison comparison;
  std::size_t n = 0;
  std::vector<double> x, y;  // the data, for the report
  std::string file, x_name = "x", y_name = "y";
};

struct Compensated {
  TargetOutput output;
};

// mtcal linuxcnc-probe: the simulated probe's files with what its summary names.
struct ProbeComponent {
  Machine machine;  // the truth
  LinuxcncProbeOptions options;
  TargetOutput output;
};

}  // namespace

void bind_prediction_compensation(py::module_& m) {
  // ---------------------------------------------------------------- regression
  py::class_<FitResult>(m, "FitResult", "A least-squares fit of one model form (Yaqoob 2017 ch. 5).")
      .def_property_readonly("label", [](const FitResult& f) { return f.model.spec.label(); })
      .def_property_readonly("parameter_names", [](const FitResult& f) { return parameter_names(f.model.spec); })
      .def_property_readonly("parameters", [](const FitResult& f) { return to_array(f.model.p); })
      .def_property_readonly("stddev", [](const FitResult& f) { return to_array(f.stddev); })
      .def_property_readonly(
          "covariance", [](const FitResult& f) { return to_array(f.covariance, f.model.p.size()); },
          "(p, p) sigma^2 (J^T J)^-1; NaN where singular or at a bound")
      .def_readonly("converged", &FitResult::converged)
      .def_readonly("rss", &FitResult::rss)
      .def_readonly("sigma", &FitResult::sigma)
      .def_readonly("r_squared", &FitResult::r_squared)
      .def_readonly("aicc", &FitResult::aicc)
      .def_readonly("loocv_rmse", &FitResult::loocv_rmse)
      .def(
          "__call__",
          [](const FitResult& f, py::handle x) {
            const Rows r = as_rows(x, "x", std::nullopt, true, false);
            std::vector<double> v(r.rows * r.cols);
            for (std::size_t i = 0; i < v.size(); ++i) v[i] = f.model(r.data[i]);
            return r.single ? to_array(v) : to_array(v, r.cols);
          },
          "x"_a, "The fitted model's value at x (an array).")
      .def("to_dict", [](const FitResult& f) { return to_py(to_json(f)); });
  m.def(
      "fit_model",
      [](py::handle x, py::handle y, const std::string& model, bool loocv) {
        const auto xs = as_std_vector(x, "x");
        const auto ys = as_std_vector(y, "y", xs.size());
        return fit_model(one_spec(model, "model"), xs, ys, FitOptions{loocv});
      },
      "x"_a, "y"_a, py::kw_only(), "model"_a = "polynomial(1)", "loocv"_a = true,
      R"doc(Least squares of one model form to (x, y): model is a label as mtcal regress --models takes it,
"polynomial(2)", "polynomial(1, c0=0)", "exp_approach", "stretched_exp", "logistic_ln",
"gompertz", "saturation", "power". Returns FitResult with parameters, stddev, covariance.)doc");
  py::class_<Regression>(m, "ModelComparison", "Every model form fitted and ranked (mtcal regress).")
      .def_property_readonly("fits", [](const Regression& r) { return r.comparison.fits; })
      .def_property_readonly("best_backward",
                             [](const Regression& r) { return r.comparison.fits.at(r.comparison.by_backward.at(0)); })
      .def_property_readonly("best_loocv",
                             [](const Regression& r) { return r.comparison.fits.at(r.comparison.by_loocv.at(0)); })
      .def(
          "to_dict",
          [](const Regression& r, const std::optional<std::string>& file, const std::optional<std::string>& x,
             const std::optional<std::string>& y) {
            return to_py(to_json(r.comparison, file.value_or(r.file), x.value_or(r.x_name), y.value_or(r.y_name), r.n));
          },
          "file"_a = py::none(), "x"_a = py::none(), "y"_a = py::none(),
          "As `mtcal regress --json` (file, x, y name the data; default: as given to compare_models).")
      .def(
          "_write_report",
          [](const Regression& r, const std::string& path, const std::string& command) {
            regression_report(r.comparison, r.x, r.y, r.file, r.x_name, r.y_name, command).write(path);
          },
          "path"_a, "command"_a);
  m.def(
      "compare_models",
      [](py::handle x, py::handle y, const std::string& models, const std::string& file, const std::string& x_name,
         const std::string& y_name) {
        const auto specs = parse_model_specs(models, "models");
        auto xs = as_std_vector(x, "x");
        auto ys = as_std_vector(y, "y", xs.size());
        Regression r{compare_models(specs, xs, ys), xs.size(), std::move(xs), std::move(ys), file, x_name, y_name};
        if (r.comparison.fits.empty())
          throw Error("no model could be fitted: " +
                      (r.comparison.skipped.empty() ? std::string() : r.comparison.skipped[0].reason));
        return r;
      },
      "x"_a, "y"_a, py::kw_only(), "models"_a = "all", "file"_a = "", "x_name"_a = "x", "y_name"_a = "y",
      "Fits every form of models ('all' or a comma list of labels) and ranks them by backward prediction and "
      "leave-one-out error. As `mtcal regress`. file, x_name, y_name: what to_dict() and write_report name as the "
      "data (the data file, hashed into the report, and its columns).");

  // ---------------------------------------------------------------- prediction models
  py::class_<PredictionModel>(m, "PredictionModel", "A workpiece error prediction model (YAML, docs/prediction.md).")
      .def_readonly("name", &PredictionModel::name)
      .def_readonly("file", &PredictionModel::file)
      .def_property_readonly("components",
                             [](const PredictionModel& pm) {
                               std::vector<std::string> v;
                               for (const auto& c : pm.components) v.push_back(c.name);
                               return v;
                             })
      .def_property_readonly("variables", &PredictionModel::variables, "Every variable the components read");
  m.def("read_prediction_model", &read_prediction_model, "path"_a);
  m.def("parse_prediction_model", &parse_prediction_model, "text"_a, "source"_a = "<string>");
  py::class_<PredictionPoints>(m, "PredictionPoints", "Points to predict at: a value per variable (column) per row.")
      .def(py::init(&make_points), "columns"_a, py::kw_only(), "source"_a = "points",
           "columns: dict variable -> array (t, S, F, dx, dy, dz, step ...), all of one length.")
      .def_readonly("columns", &PredictionPoints::columns)
      .def_property_readonly("values", [](const PredictionPoints& p) { return rows_array(p.rows, p.columns.size()); })
      .def_readonly("lines", &PredictionPoints::lines)
      .def_readonly("source", &PredictionPoints::source);
  m.def("read_prediction_points", &read_prediction_points, "path"_a);
  m.def("points_from_gcode", &points_from_gcode, "program"_a, "source"_a, py::kw_only(), "start_time"_a = 0.0,
        "speed"_a, "rapid_feed"_a = 10000.0,
        "One point per cutting move's end of a GcodeProgram (read it with axes='XYZ'): columns line X Y Z t S F dx "
        "dy dz; start_time in minutes, speed in rpm.");
  py::class_<Prediction>(m, "PredictionRun", "Predicted errors at every point (mtcal predict).")
      .def(
          "_write_report",
          [](const Prediction& p, const std::string& path, const std::string& command) {
            prediction_report(p.run, p.model, p.model.file, "points", command).write(path);
          },
          "path"_a, "command"_a)
      .def_property_readonly("component_names",
                             [](const Prediction& p) {
                               std::vector<std::string> v;
                               for (const auto& c : p.model.components) v.push_back(c.name);
                               return v;
                             })
      .def_property_readonly(
          "errors",
          [](const Prediction& p) {
            std::vector<double> v;
            for (const auto& x : p.run.predictions) v.insert(v.end(), x.e, x.e + 3);
            return p.run.predictions.empty() ? new_array({0, 3}) : to_array(v, 3);
          },
          "(N, 3) predicted X, Y, Z errors (mm)")
      .def_property_readonly(
          "values",
          [](const Prediction& p) {
            std::vector<std::vector<double>> rows;
            for (const auto& x : p.run.predictions) rows.push_back(x.values);
            return rows_array(rows, p.model.components.size());
          },
          "(N, C) every component's value per point")
      .def_property_readonly("warnings", [](const Prediction& p) { return p.run.warnings; })
      .def_property_readonly(
          "compensation",
          [](const Prediction& p) {
            py::list l;
            for (const auto& c : p.run.compensation)
              l.append(py::make_tuple(c.step, c.offset[0], c.offset[1], c.offset[2]));
            return l;
          },
          "(step, offset_x, offset_y, offset_z) per step (mm), with compensation=True")
      .def(
          "to_dict", [](const Prediction& p) { return to_py(to_json(p.run, p.model)); }, "As `mtcal predict --json`.")
      .def(
          "csv", [](const Prediction& p) { return prediction_csv(p.run, p.model); }, "As `mtcal predict --out`.")
      .def("compensation_csv", [](const Prediction& p) { return compensation_csv(p.run); });
  m.def("predict", &predict, "model"_a, "points"_a, py::kw_only(), "constants"_a = std::map<std::string, double>{},
        "strict"_a = false, "compensation"_a = false,
        "Predicted workpiece errors at points (PredictionPoints or a dict of columns); constants give variables "
        "that are not columns; strict refuses extrapolation. As `mtcal predict`.");

  // ---------------------------------------------------------------- separation and process error
  py::class_<PositionSeparation>(m, "PositionSeparation")
      .def(
          "to_dict", [](const PositionSeparation& s, const std::string& file) { return to_py(to_json(s, file)); },
          "file"_a = "")
      .def("csv", [](const PositionSeparation& s) { return separation_csv(s); });
  py::class_<ControlSeparation>(m, "ControlSeparation")
      .def_readonly("quantity", &ControlSeparation::quantity)
      .def(
          "to_dict", [](const ControlSeparation& s, const std::string& file) { return to_py(to_json(s, file)); },
          "file"_a = "")
      .def("csv", [](const ControlSeparation& s) { return separation_csv(s); });
  py::class_<PositionObservation>(m, "PositionObservation", "One CMM/probe pair of a feature at a step (mm).")
      .def_readonly("step", &PositionObservation::step)
      .def_property_readonly("axis", [](const PositionObservation& o) { return std::string(1, o.axis); })
      .def_readonly("feature", &PositionObservation::feature)
      .def_readonly("distance", &PositionObservation::distance)
      .def_readonly("cmm", &PositionObservation::cmm)
      .def_readonly("probe", &PositionObservation::probe)
      .def_readonly("line", &PositionObservation::line);
  py::class_<DimensionRecord>(m, "DimensionRecord", "One dimension of one workpiece at one step (mm).")
      .def_readonly("workpiece", &DimensionRecord::workpiece)
      .def_readonly("step", &DimensionRecord::step)
      .def_property_readonly("axis", [](const DimensionRecord& r) { return std::string(1, r.axis); })
      .def_readonly("nominal", &DimensionRecord::nominal)
      .def_readonly("measured", &DimensionRecord::measured)
      .def_readonly("e_pf", &DimensionRecord::e_pf)
      .def_readonly("e_pt", &DimensionRecord::e_pt)
      .def_readonly("e_pos", &DimensionRecord::e_pos)
      .def_readonly("line", &DimensionRecord::line);
  m.def(
      "read_position_observations", [](const std::string& path) { return read_position_observations(path); }, "path"_a,
      "The CMM/probe position table (Yaqoob 2017 Table 5.3 form): one PositionObservation per filled pair.");
  m.def(
      "read_dimension_table", [](const std::string& path) { return read_dimension_table(path); }, "path"_a,
      "The long dimension table (workpiece, step, axis, nominal, measured, e_pf, e_pt, e_pos).");
  m.def(
      "separate_position",
      [](py::handle data) {
        if (py::isinstance<py::str>(data)) {
          const auto path = data.cast<std::string>();
          return separate_position_with_fits(read_position_observations(read_text_csv(path), path));
        }
        return separate_position_with_fits(data.cast<std::vector<PositionObservation>>());
      },
      "data"_a,
      "Mechanical position errors per step from a CMM/probe position table (a path, or the records of "
      "read_position_observations). As `mtcal separate position`.");
  m.def(
      "separate_control",
      [](py::handle data, const std::string& a, const std::string& b, const PredictionModel* model) {
        if (py::isinstance<py::str>(data)) {
          const auto path = data.cast<std::string>();
          return separate_control(read_dimension_table(read_text_csv(path), path), a, b, path, model);
        }
        return separate_control(data.cast<std::vector<DimensionRecord>>(), a, b, "records", model);
      },
      "data"_a, "a"_a, "b"_a, py::kw_only(), "model"_a = nullptr,
      "Control errors between workpieces a and b from the dimension table (a path, or the records of "
      "read_dimension_table), minus the model's e_ctrl with a model. As `mtcal separate control`.");
  py::class_<ProcessErrorStudy>(m, "ProcessErrorStudy")
      .def_property_readonly(
          "e_prog",
          [](const ProcessErrorStudy& s) {
            std::vector<double> v;
            for (const auto& p : s.points) v.push_back(p.e_prog);
            return to_array(v);
          },
          "Program-generated error per feed (mm)")
      .def(
          "to_dict", [](const ProcessErrorStudy& s) { return to_py(to_json(s)); }, "As `mtcal process-error --json`.");
  m.def(
      "process_error",
      [](py::handle feeds, py::handle measured, const std::string& form, py::dict tool_d, py::dict k_d,
         py::dict cut_d) {
        EndMill tool;
        CuttingCoefficients k;
        CutConditions cut;
        auto get = [](py::dict d, const char* key, auto& field) {
          if (d.contains(key)) field = d[key].cast<std::remove_reference_t<decltype(field)>>();
        };
        get(tool_d, "diameter", tool.diameter);
        get(tool_d, "teeth", tool.teeth);
        get(tool_d, "helix_deg", tool.helix_deg);
        get(tool_d, "overhang", tool.overhang);
        get(tool_d, "flute_length", tool.flute_length);
        get(tool_d, "flute_diameter_ratio", tool.flute_diameter_ratio);
        get(tool_d, "young_modulus", tool.young_modulus);
        get(k_d, "ktc", k.ktc);
        get(k_d, "krc", k.krc);
        get(k_d, "kte", k.kte);
        get(k_d, "kre", k.kre);
        get(cut_d, "radial_depth", cut.radial_depth);
        get(cut_d, "axial_depth", cut.axial_depth);
        get(cut_d, "spindle_speed", cut.spindle_speed);
        get(cut_d, "down_milling", cut.down_milling);
        const auto f = as_std_vector(feeds, "feeds");
        std::vector<double> meas;
        std::optional<ModelSpec> spec;
        if (!measured.is_none()) {
          meas = as_std_vector(measured, "measured", f.size());
          spec = one_spec(form, "form");
        }
        return process_error_study(tool, k, cut, f, meas, spec);
      },
      "feeds"_a, "measured"_a = py::none(), py::kw_only(), "form"_a = "logistic_ln", "tool"_a = py::dict(),
      "coefficients"_a = py::dict(), "cut"_a = py::dict(),
      "Program-generated process error e_prog per feed (mm/min) from a mechanistic milling force model and "
      "tool deflection; with measured process errors, their calibration on e_prog. As `mtcal process-error`.");

  // ---------------------------------------------------------------- compensation
  py::class_<AxisSampling>(m, "AxisSampling", "Where one axis is sampled: points from start to end (mm or deg).")
      .def(py::init([](const std::string& axis, double start, double end, std::size_t points) {
             if (axis.size() != 1) throw py::value_error("axis: expected one axis letter, found '" + axis + "'");
             return AxisSampling{axis[0], start, end, points};
           }),
           "axis"_a, "start"_a, "end"_a, "points"_a)
      .def_property_readonly("axis", [](const AxisSampling& s) { return std::string(1, s.axis); })
      .def_readonly("start", &AxisSampling::start)
      .def_readonly("end", &AxisSampling::end)
      .def_readonly("points", &AxisSampling::points);
  py::class_<TargetOutput>(m, "TargetOutput", "A compensation target's files and summary.")
      .def_property_readonly(
          "files",
          [](const TargetOutput& o) {
            py::dict d;
            for (const auto& f : o.files) d[py::str(f.name)] = f.text;
            return d;
          },
          "file name -> text")
      .def_property_readonly("target", [](const TargetOutput& o) { return o.summary.target; })
      .def_property_readonly(
          "quantity", [](const TargetOutput& o) { return std::string(to_string(o.summary.quantity)); },
          "What the numbers are: error, correction or actual position")
      .def_property_readonly("warnings", [](const TargetOutput& o) { return o.summary.warnings; })
      .def_property_readonly(
          "commanded_range", [](const TargetOutput& o) { return to_py(to_json(o)["commanded_range"]); },
          "linuxcnc-kins: per axis the commanded travel its pre-check holds (axis lo hi unit given margin "
          "largest_correction why), as `compensate --json`'s commanded_range; [] for the other targets")
      .def(
          "write", [](const TargetOutput& o, const std::string& dir) { write_target_output(dir, o); }, "dir"_a,
          "Writes the files into dir (new or empty): all of them or none.")
      .def(
          "to_dict", [](const TargetOutput& o) { return to_py(to_json(o)); },
          "The summary as `mtcal compensate --json`.");
  py::class_<ProbeComponent>(m, "LinuxcncProbe", "The simulated touch probe for LinuxCNC (mtcal linuxcnc-probe).")
      .def_property_readonly(
          "files",
          [](const ProbeComponent& p) {
            py::dict d;
            for (const auto& f : p.output.files) d[py::str(f.name)] = f.text;
            return d;
          },
          "file name -> text (mtcal_probe.c, build.sh, linuxcnc-probe.hal, README.txt)")
      .def_property_readonly("component", [](const ProbeComponent& p) { return p.options.component_name; })
      .def(
          "write", [](const ProbeComponent& p, const std::string& dir) { write_target_output(dir, p.output); }, "dir"_a,
          "Writes the files into dir (new or empty): all of them or none, as --out.")
      .def(
          "to_dict",
          [](const ProbeComponent& p, const std::string& out) {
            return to_py(linuxcnc_probe_json(p.machine, p.options, p.output, out));
          },
          "out"_a = "", "As `mtcal linuxcnc-probe --json` (out: the directory written, as --out).");
  m.def(
      "linuxcnc_probe",
      [](const Machine& mm, py::handle spheres, double sphere_diameter, double stylus_diameter) {
        const Rows c = as_rows(spheres, "spheres", 3, true);
        ProbeComponent p{mm, {}, {}};
        p.options.stylus_diameter = stylus_diameter;
        for (std::size_t i = 0; i < c.rows; ++i) {
          SimulatedSphere sp;
          sp.centre = Vec3(c.data[3 * i], c.data[3 * i + 1], c.data[3 * i + 2]);
          sp.diameter = sphere_diameter;
          p.options.spheres.push_back(sp);
        }
        p.output = linuxcnc_probe_output(mm, p.options);
        return p;
      },
      "machine"_a, "spheres"_a, py::kw_only(), "sphere_diameter"_a = 25.4, "stylus_diameter"_a = 3.0,
      R"(A simulated touch probe for LinuxCNC, as `mtcal linuxcnc-probe`: the HAL component (C,
halcompile) that sets motion.probe-input while the stylus tip of machine (its errors are the
truth the probe sees) touches a sphere. spheres: centres (S, 3) or one (3,), mm in the machine's
workpiece frame (1 to 16); diameters in mm. Returns LinuxcncProbe: files, write(dir), to_dict().
docs/planning.md.)");
  m.def(
      "compensation_targets",
      []() {
        py::dict d;
        for (const auto& t : compensation_targets()) d[py::str(t.name)] = t.description;
        return d;
      },
      "Every compensation target mtcal writes: name -> description, in the library's order.");
  m.def(
      "compensate",
      [](const Machine& mm, const std::string& target, const std::vector<AxisSampling>& sampling, std::size_t points,
         py::handle reference, std::size_t residual_points, int threads, double skew_reference_length,
         int linuxcnc_type, double fanuc_unit) {
        const CompensationTarget& t = compensation_target(target);
        if (linuxcnc_type != 0 && linuxcnc_type != 1)
          throw py::value_error("linuxcnc_type: expected 0 or 1 (LinuxCNC's COMP_FILE_TYPE), found " +
                                std::to_string(linuxcnc_type));
        if (!(fanuc_unit >= 1e-6 && fanuc_unit <= 1.0))
          throw py::value_error("fanuc_unit: expected a detection unit in [1e-06, 1] (mm, deg per count), found " +
                                std::to_string(fanuc_unit));
        CompensationOptions o;
        o.skew_reference_length = skew_reference_length;
        o.comp_file_type = linuxcnc_type;
        o.detection_unit = fanuc_unit;
        o.sampling = sampling;
        o.points = points;
        if (!reference.is_none()) o.reference = configuration(mm, reference, "reference");
        o.residual_points = residual_points;
        o.threads = threads;
        LongCall release;  // without the GIL, stoppable with Ctrl-C
        return t.run(mm, o);
      },
      "machine"_a, "target"_a, py::kw_only(), "sampling"_a = std::vector<AxisSampling>{}, "points"_a = std::size_t{0},
      "reference"_a = py::none(), "residual_points"_a = std::size_t{11}, "threads"_a = 0,
      "skew_reference_length"_a = 100.0, "linuxcnc_type"_a = 1, "fanuc_unit"_a = 0.001,
      R"(Compensation for a controller: `target` names an entry of compensation_targets(). sampling: per
axis AxisSampling (default: each axis over its travel at `points` positions, or the target's
default; --range). reference: the other axes' configuration (internal units). skew_reference_length: mm,
RepRapFirmware M556 S / FluidNC distance_mm (as --skew-reference-length). linuxcnc_type: LinuxCNC's
COMP_FILE_TYPE, 0 = columns are the positions reached, 1 = corrections (--linuxcnc-type); fanuc_unit:
FANUC detection unit, mm and deg per count of a pitch error value (--fanuc-unit). Returns TargetOutput
(files, summary with the residual before/after; write(dir) writes them all or none).)");
}

}  // namespace mtcal::python
