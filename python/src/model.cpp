// Python bindings of the model and the kinematics: Machine, MachineBuilder, ErrorModel, evaluate, eval's run,
// jacobian, effects, machine and parameter files, joint values and configuration files.
#include <algorithm>
#include <chrono>
#include <numbers>

#include <Eigen/Core>

#include "common.hpp"
#include "mtcal/evaluation/contributions.hpp"
#include "mtcal/evaluation/error_stream.hpp"
#include "mtcal/io/text/csv.hpp"
#include "mtcal/io/points/error_csv.hpp"
#include "mtcal/io/json/error_map_json.hpp"
#include "mtcal/io/system/files.hpp"
#include "mtcal/io/text/joints.hpp"
#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/model/joints.hpp"
#include "mtcal/model/machine_builder.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/util/parallel.hpp"
#include "mtcal/report/error_map.hpp"

namespace mtcal::python {

using namespace pybind11::literals;

namespace {

// ---------------------------------------------------------------- evaluate and jacobian

const char* kEvaluateDoc = R"(Volumetric error of the tool relative to the workpiece at N configurations.

Parameters
----------
model : Machine or ErrorModel
    The machine (compiled on each call) or an ErrorModel compiled once for repeated calls.
configs : array_like, shape (N, k) or (k,)
    Joint values in internal units: mm for linear axes, rad for rotary axes, one column per
    axis in the machine's chain order (Machine.axis_letters; Machine.to_internal converts
    from mm and deg). A C-contiguous float64 array is read in place, without a copy.
directions : array_like of int8, shape like configs, optional
    Direction of motion of each axis, -1, 0 or +1 (reversal terms of the motion errors);
    None: 0 everywhere (the mean of both approaches).
threads : int, keyword-only
    Worker threads, 0 (default): all cores. The GIL is released during the computation.
travel_check : bool, keyword-only
    Refuse (InputError) a configuration outside its axes' travels; default False.
out : numpy.ndarray, keyword-only, optional
    A writeable C-contiguous float64 array of the result's shape to fill (no allocation); returned.

Returns
-------
numpy.ndarray, shape (N, 6) or (6,)
    dx, dy, dz in mm and rx, ry, rz in rad (rotation vector of R_actual R_nominal^T), in the
    workpiece frame: the error e = actual - nominal. The same numbers as `mtcal eval`.

Raises
------
ValueError
    A wrong shape or dtype, a non-finite value, or a direction other than -1, 0, +1, naming
    the argument.
)";

const char* kJacobianDoc = R"(Sensitivity Jacobian of the volumetric error to every parameter of the model.

Parameters
----------
model : Machine or ErrorModel
configs : array_like, shape (N, k) or (k,)
    Joint values in internal units (mm, rad), chain order; read in place when C-contiguous float64.
directions : array_like of int8, shape like configs, optional
    Directions of motion -1, 0, +1; None: 0.
threads : int, keyword-only
    Worker threads, 0: all cores (GIL released).

Returns
-------
numpy.ndarray, shape (N, 6, P) or (6, P)
    d(dx dy dz rx ry rz) / d(parameter), columns in the order of Machine.parameter_names
    (P = Machine.parameter_count); per unit of each parameter's internal unit
    (ErrorParameter.unit). Exact: analytic through the exact transforms.
)";

// The ErrorModel of a Machine or ErrorModel argument: the latter by reference, the former compiled here.
struct ModelRef {
  std::optional<ErrorModel> own;
  const ErrorModel* model = nullptr;
};
ModelRef model_of(py::handle obj) {
  ModelRef r;
  if (py::isinstance<ErrorModel>(obj)) {
    r.model = &obj.cast<const ErrorModel&>();
  } else if (py::isinstance<Machine>(obj)) {
    r.own.emplace(obj.cast<const Machine&>());
    r.model = &*r.own;
  } else {
    throw py::type_error("model: expected a Machine or an ErrorModel, found " +
                         std::string(py::str(py::type::of(obj).attr("__name__"))));
  }
  return r;
}

void check_travel(const Machine& m, const Rows& q) {
  std::vector<double> row(q.cols);
  for (std::size_t i = 0; i < q.rows; ++i) {
    std::copy_n(q.data + i * q.cols, q.cols, row.begin());
    check_joints(m, row, "configs[" + std::to_string(i) + "]", true);
  }
}

// The caller's output array, when given: C-contiguous, writeable float64 of the result's shape.
py::array_t<double> output_array(py::handle out, const Rows& q) {
  const std::vector<py::ssize_t> shape =
      q.single ? std::vector<py::ssize_t>{6} : std::vector<py::ssize_t>{static_cast<py::ssize_t>(q.rows), 6};
  if (out.is_none()) return new_array(shape);
  const std::string want = q.single ? "(6,)" : "(" + std::to_string(q.rows) + ", 6)";
  if (!py::isinstance<py::array>(out))
    throw py::value_error("out: expected a float64 array of shape " + want + ", found " +
                          std::string(py::str(py::type::of(out).attr("__name__"))));
  auto a = py::reinterpret_borrow<py::array>(out);
  const bool shape_ok =
      a.ndim() == static_cast<py::ssize_t>(shape.size()) && std::equal(shape.begin(), shape.end(), a.shape());
  if (!a.dtype().is(py::dtype::of<double>()) || !shape_ok || !(a.flags() & py::array::c_style) || !a.writeable())
    throw py::value_error("out: expected a writeable C-contiguous float64 array of shape " + want);
  return py::reinterpret_borrow<py::array_t<double>>(out);
}

py::array_t<double> evaluate(py::handle model_obj, py::handle configs, py::handle directions, int threads,
                             bool travel_check, py::handle out_arg) {
  const ModelRef ref = model_of(model_obj);
  const ErrorModel& model = *ref.model;
  const std::size_t k = model.axis_count();
  const Rows q = as_rows(configs, "configs", k, true);
  Directions d;
  if (!directions.is_none()) d = as_directions(directions, "directions", q.rows, k, q.single);
  if (travel_check) check_travel(model.machine(), q);
  py::array_t<double> out = output_array(out_arg, q);
  double* o = out.mutable_data();
  {
    LongCall release;  // without the GIL, stoppable with Ctrl-C
    model.evaluate_batch(q.span(), d.span(), std::span<double>(o, q.rows * 6), BatchOptions{threads});
  }
  return out;
}

// mtcal eval --points / --grid: every configuration's error, the summary the command prints and what
// its report shows.
struct EvaluationRun {
  Machine machine;
  StreamSummary summary;
  std::vector<double> q, error;   // N x k (internal units), N x 6
  std::vector<std::int8_t> dir;   // N x k, or empty
  std::string points_file, grid;  // what the report names as the configurations' source
};

EvaluationRun evaluate_configurations(const Machine& m, py::handle configs, py::handle directions, py::handle grid,
                                      const std::string& points, bool travel_check, int threads) {
  const int given = (configs.is_none() ? 0 : 1) + (grid.is_none() ? 0 : 1) + (points.empty() ? 0 : 1);
  if (given != 1) throw py::value_error("expected exactly one of configs, grid, points");
  if (!directions.is_none() && configs.is_none())
    throw py::value_error("directions: expected configs beside them (a points file has its own)");
  const std::size_t k = m.axes.size();
  EvaluationRun r{m, {}, {}, {}, {}, points, ""};
  ConfigurationList list;
  GridValues values;
  if (!points.empty()) {
    list = read_configurations(m, points, travel_check);
  } else if (!grid.is_none()) {
    values = grid_values(m, grid, "grid");
    check_grid(m, values, "grid", travel_check, 200'000'000);
    if (py::isinstance<py::str>(grid)) r.grid = grid.cast<std::string>();
  } else {
    const Rows q = as_rows(configs, "configs", k, false);
    Directions d;
    if (!directions.is_none()) d = as_directions(directions, "directions", q.rows, k, false);
    if (travel_check) check_travel(m, q);
    list.axes = k;
    list.q.assign(q.data, q.data + q.rows * k);
    list.dir.assign(d.data, d.data + d.size);
    list.lines.assign(q.rows, 0);
  }
  const auto source = grid.is_none() ? ConfigurationSource::list(list) : ConfigurationSource::grid(values);
  const ErrorModel model(m);
  r.q.reserve(source.size() * k);
  r.error.reserve(source.size() * 6);
  if (source.has_directions()) r.dir.reserve(source.size() * k);
  StreamOptions so;  // the command's chunks and grid kernel: the same numbers as `mtcal eval`
  so.threads = threads;
  LongCall release;  // without the GIL, stoppable with Ctrl-C
  r.summary = evaluate_stream(
      model, source,
      [&](const ErrorChunk& c) {
        r.q.insert(r.q.end(), c.q.begin(), c.q.end());
        r.dir.insert(r.dir.end(), c.dir.begin(), c.dir.end());
        r.error.insert(r.error.end(), c.error.begin(), c.error.end());
      },
      so);
  return r;
}

py::array_t<double> jacobian(py::handle model_obj, py::handle configs, py::handle directions, int threads) {
  const ModelRef ref = model_of(model_obj);
  const ErrorModel& model = *ref.model;
  const std::size_t k = model.axis_count();
  const std::size_t P = model.machine().parameter_count();
  const Rows q = as_rows(configs, "configs", k, true);
  Directions d;
  if (!directions.is_none()) d = as_directions(directions, "directions", q.rows, k, q.single);
  const auto p = static_cast<py::ssize_t>(P);
  py::array_t<double> out = q.single ? new_array({6, p}) : new_array({static_cast<py::ssize_t>(q.rows), 6, p});
  double* o = out.mutable_data();
  {
    LongCall release;  // without the GIL, stoppable with Ctrl-C
    const std::size_t chunks = std::min<std::size_t>(q.rows, 8 * hardware_threads());
    parallel_for_ranges(q.rows, chunks, threads, [&](std::size_t b, std::size_t e, std::size_t) {
      JacobianWorkspace ws;
      Eigen::Matrix<double, 6, Eigen::Dynamic> J(6, static_cast<Eigen::Index>(P));
      for (std::size_t i = b; i < e; ++i) {
        const auto dir = d.size ? d.span().subspan(i * k, k) : std::span<const std::int8_t>();
        model.jacobian(q.span().subspan(i * k, k), dir, J, ws);
        double* row = o + i * 6 * P;
        for (Eigen::Index r = 0; r < 6; ++r)
          for (Eigen::Index c = 0; c < J.cols(); ++c)
            row[static_cast<std::size_t>(r) * P + static_cast<std::size_t>(c)] = J(r, c);
      }
    });
  }
  return out;
}

py::array_t<double> pose_array(const Affine& a) {
  py::array_t<double> out = new_array({4, 4});
  auto v = out.mutable_unchecked<2>();
  for (py::ssize_t r = 0; r < 4; ++r)
    for (py::ssize_t c = 0; c < 4; ++c) v(r, c) = 0.0;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) v(r, c) = a.R(r, c);
    v(r, 3) = a.t[r];
  }
  v(3, 3) = 1.0;
  return out;
}

// ---------------------------------------------------------------- effects

struct Effects {
  Machine machine;
  std::vector<double> at;
  std::string around;
  std::vector<ErrorEffect> effects;
};

Effects effects(const Machine& given, py::handle at, py::object errors, const std::string& around, bool travel_check) {
  if (around != "nominal" && around != "actual")
    throw py::value_error("around: expected 'nominal' or 'actual', found '" + around + "'");
  Effects r{given, configuration(given, at, "at"), around, {}};
  // About the nominal machine the effects are the errors' definitions (as mtcal effects does).
  if (around == "nominal") r.machine.clear_errors();
  check_joints(r.machine, r.at, "at", travel_check);
  std::vector<ErrorName> wanted;
  if (!errors.is_none())
    for (const auto& w : errors.cast<std::vector<std::string>>()) {
      auto en = ErrorName::parse(w);
      if (!en || !r.machine.has_error(*en))
        throw InputError({"errors", 0, w}, "unknown error name '" + w + "' for topology " + r.machine.topology.chain);
      wanted.push_back(*en);
    }
  r.effects = single_error_effects(r.machine, r.at, wanted);
  return r;
}

// ---------------------------------------------------------------- builder helpers

Vec3 vec3_of(py::handle obj, const char* name) {
  const auto v = as_std_vector(obj, name, 3);
  return {v[0], v[1], v[2]};
}

char letter_of_arg(const std::string& s, const char* name) {
  if (s.size() != 1) throw py::value_error(std::string(name) + ": expected one axis letter, found '" + s + "'");
  return s[0];
}

MotionFunction motion_function(py::object polynomial, py::object table, py::object fourier, double reversal) {
  const int given = !polynomial.is_none() + !table.is_none() + !fourier.is_none();
  if (given != 1) throw py::value_error("motion: expected exactly one of polynomial, table, fourier");
  if (!polynomial.is_none()) {
    const auto c = as_std_vector(polynomial, "polynomial");
    if (c.empty() || c.size() > 4)
      throw py::value_error("polynomial: expected 1 to 4 coefficients c0..c3, found " + std::to_string(c.size()));
    Polynomial p;
    std::copy(c.begin(), c.end(), p.coefficients.begin());
    p.reversal = reversal;
    return MotionFunction(p);
  }
  if (!table.is_none()) {
    const auto t = table.cast<py::dict>();
    Table tb;
    tb.positions = as_std_vector(t["positions"], "table['positions']");
    tb.forward = as_std_vector(t["forward"], "table['forward']");
    if (t.contains("backward")) tb.backward = as_std_vector(t["backward"], "table['backward']");
    return MotionFunction(tb);
  }
  const auto f = fourier.cast<py::dict>();
  Fourier fo;
  if (f.contains("constant")) fo.constant = f["constant"].cast<double>();
  if (f.contains("cos")) fo.cos_terms = as_std_vector(f["cos"], "fourier['cos']");
  if (f.contains("sin")) fo.sin_terms = as_std_vector(f["sin"], "fourier['sin']");
  fo.reversal = reversal;
  return MotionFunction(fo);
}

Machine with_params(const Machine& m, py::object values, const std::string& unit, py::kwargs kwargs) {
  MachineBuilder b(m);
  auto apply = [&](py::handle items) {
    for (auto item : items.cast<py::dict>()) {
      const auto name = item.first.cast<std::string>();
      b.parameter(name, item.second.cast<double>(), unit);
    }
  };
  if (!values.is_none()) apply(values);
  apply(kwargs);
  return b.build();
}

py::array_t<double> grid_array(const Machine& m, const GridValues& values) {
  const auto source = ConfigurationSource::grid(values);
  const std::size_t k = m.axes.size();
  py::array_t<double> out = new_array({static_cast<py::ssize_t>(source.size()), static_cast<py::ssize_t>(k)});
  double* o = out.mutable_data();
  for (std::size_t i = 0; i < source.size(); ++i) source.fill(i, o + i * k, nullptr);
  return out;
}

std::string axis_kind(const Axis& a) { return a.kind == AxisKind::Linear ? "linear" : "rotary"; }

}  // namespace

// A grid argument: the CLI's text "X=0:500:21,..." (mm, deg) or a mapping axis letter -> values in
// internal units (axes not named held at 0).
GridValues grid_values(const Machine& m, py::handle grid, const char* name) {
  if (py::isinstance<py::str>(grid)) return parse_grid(m, grid.cast<std::string>(), name);
  GridValues values(m.axes.size(), std::vector<double>{0.0});
  for (auto item : grid.cast<py::dict>()) {
    const auto letter = item.first.cast<std::string>();
    const auto k = letter.size() == 1 ? m.axis_index(letter[0]) : std::nullopt;
    if (!k) throw py::value_error(std::string(name) + ": axis '" + letter + "' is not in topology " + m.topology.chain);
    const std::string what = std::string(name) + "['" + letter + "']";
    const Rows r = as_rows(item.second, what.c_str(), std::nullopt, true);
    if (r.rows * r.cols == 0) throw py::value_error(what + ": expected at least one value");
    values[*k].assign(r.data, r.data + r.rows * r.cols);
  }
  return values;
}

void bind_model(py::module_& m) {
  py::class_<Axis>(m, "Axis", "One axis of a machine (read-only record; internal units mm and rad).")
      .def_property_readonly("letter", [](const Axis& a) { return std::string(1, a.letter); })
      .def_property_readonly("kind", &axis_kind, "'linear' or 'rotary'")
      .def_property_readonly(
          "unit", [](const Axis& a) { return std::string(joint_unit_name(a)); },
          "The users' unit of its joint values: 'mm' or 'deg'")
      .def_property_readonly(
          "direction", [](const Axis& a) { return to_array(a.direction()); },
          "Nominal unit direction (machine x, y, z)")
      .def_property_readonly(
          "point", [](const Axis& a) { return to_array(a.point); },
          "A point of the axis line (rotary) or the reference point of its errors (linear), mm")
      .def_property_readonly(
          "travel",
          [](const Axis& a) -> py::object {
            if (!a.travel) return py::none();
            return py::make_tuple(a.travel->min, a.travel->max);
          },
          "(min, max) in internal units (mm or rad), or None")
      .def_readonly("moves_workpiece", &Axis::moves_workpiece)
      .def("__repr__",
           [](const Axis& a) { return "<mtcal.Axis " + std::string(1, a.letter) + " " + axis_kind(a) + ">"; });

  py::class_<ErrorParameter>(m, "ErrorParameter", "One scalar parameter of the error model (as mtcal errors lists it).")
      .def_readonly("name", &ErrorParameter::name, "'EXX.1', 'EC0Y', 'EXt' ...")
      .def_property_readonly(
          "error", [](const ErrorParameter& p) { return p.error.str(); }, "The error it belongs to")
      .def_property_readonly(
          "kind", [](const ErrorParameter& p) { return std::string(to_string(p.error.kind)); },
          "'motion', 'location' or 'mounting'")
      .def_readonly("unit", &ErrorParameter::unit, "Internal unit: 'mm', 'rad', 'mm/mm', 'rad/mm^2' ...")
      .def_readonly("value", &ErrorParameter::value)
      .def("to_dict",
           [](const ErrorParameter& p) {
             py::dict d;
             d["name"] = p.name;
             d["error"] = p.error.str();
             d["kind"] = std::string(to_string(p.error.kind));
             d["unit"] = p.unit;
             d["value"] = p.value;
             return d;
           })
      .def("__repr__", [](const ErrorParameter& p) {
        return "<mtcal.ErrorParameter " + p.name + " = " + std::to_string(p.value) + " " + p.unit + ">";
      });

  py::class_<Machine>(m, "Machine",
                      "A machine model: topology, axes, tool and workpiece set-up, and every ISO 230 error "
                      "parameter by name. Values in internal units (mm, rad). Machine.load reads a machine file; "
                      "MachineBuilder builds one from Python values; with_params returns a modified copy.")
      .def_static(
          "load",
          [](const std::string& path, const std::vector<std::string>& params) {
            Machine mm = load_machine(path);
            for (const auto& p : params) load_parameters(mm, p);
            return mm;
          },
          "path"_a, py::kw_only(), "params"_a = std::vector<std::string>{},
          "Reads a machine file (YAML, docs/machine-file.md), then applies each parameter file of params in "
          "order (as mtcal --params). Raises InputError naming file, line and key.")
      .def_static("parse", &parse_machine, "text"_a, "source"_a = "<string>",
                  "A machine from YAML text; source names the text in messages.")
      .def_readonly("name", &Machine::name)
      .def_readonly("description", &Machine::description)
      .def_readonly("source", &Machine::source, "The file it was loaded from")
      .def_property_readonly(
          "topology", [](const Machine& mm) { return mm.topology.chain; },
          "Chain from workpiece to tool, e.g. 'wCBXfYZt'")
      .def_property_readonly(
          "axis_letters",
          [](const Machine& mm) { return std::string(mm.topology.axes.begin(), mm.topology.axes.end()); },
          "Axis letters in chain order: the columns of every configuration array")
      .def_property_readonly("axis_count", [](const Machine& mm) { return mm.axes.size(); })
      .def_readonly("axes", &Machine::axes, "The axes (Axis) in chain order")
      .def_property_readonly(
          "joint_factors",
          [](const Machine& mm) {
            std::vector<double> f;
            for (const auto& a : mm.axes) f.push_back(joint_unit_factor(a));
            return to_array(f);
          },
          "Per axis, the factor from the users' unit (mm, deg) to the internal one (mm, rad): 1 or pi/180")
      .def(
          "to_internal",
          [](const Machine& mm, py::handle user) {
            const Rows r = as_rows(user, "configs", mm.axes.size(), true);
            py::array_t<double> out =
                r.single ? new_array({static_cast<py::ssize_t>(r.cols)})
                         : new_array({static_cast<py::ssize_t>(r.rows), static_cast<py::ssize_t>(r.cols)});
            double* o = out.mutable_data();
            for (std::size_t i = 0; i < r.rows; ++i)
              for (std::size_t k = 0; k < r.cols; ++k)
                o[i * r.cols + k] = r.data[i * r.cols + k] * joint_unit_factor(mm.axes[k]);
            return out;
          },
          "configs"_a, "Configurations in users' units (mm, deg), shape (N, k) or (k,), to internal units (mm, rad).")
      .def(
          "to_user",
          [](const Machine& mm, py::handle internal) {
            const Rows r = as_rows(internal, "configs", mm.axes.size(), true);
            py::array_t<double> out =
                r.single ? new_array({static_cast<py::ssize_t>(r.cols)})
                         : new_array({static_cast<py::ssize_t>(r.rows), static_cast<py::ssize_t>(r.cols)});
            double* o = out.mutable_data();
            for (std::size_t i = 0; i < r.rows; ++i)
              for (std::size_t k = 0; k < r.cols; ++k)
                o[i * r.cols + k] = to_user_units(mm.axes[k], r.data[i * r.cols + k]);
            return out;
          },
          "configs"_a,
          "Configurations in internal units (mm, rad) to users' units (mm, deg, rounded to 12 significant digits).")
      .def_property_readonly(
          "tool_length", [](const Machine& mm) { return mm.tool.length; }, "mm")
      .def_property_readonly(
          "spindle_point", [](const Machine& mm) { return to_array(mm.tool.spindle_point); }, "mm")
      .def_property_readonly(
          "tool_axis", [](const Machine& mm) { return mm.tool.tool_axis; },
          "The tool points along -(this machine axis): 0 x, 1 y, 2 z")
      .def_property_readonly(
          "workpiece_origin", [](const Machine& mm) { return to_array(mm.workpiece.origin); }, "mm")
      .def_property_readonly(
          "parameters",
          [](const Machine& mm) {
            py::dict d;
            for (const auto& p : mm.parameters()) d[py::str(p.name)] = p.value;
            return d;
          },
          "Every parameter of the model, name -> value in its internal unit, in the model's order (a new dict: "
          "change values with with_params)")
      .def_property_readonly(
          "parameter_names",
          [](const Machine& mm) {
            std::vector<std::string> n;
            for (const auto& p : mm.parameters()) n.push_back(p.name);
            return n;
          },
          "Parameter names in the model's order: the columns of jacobian()")
      .def_property_readonly("parameter_count", &Machine::parameter_count)
      .def_property_readonly(
          "parameter_values",
          [](const Machine& mm) {
            std::vector<double> v;
            for (const auto& p : mm.parameters()) v.push_back(p.value);
            return to_array(v);
          },
          "Parameter values as an array, in the order of parameter_names")
      .def("parameter_table", &listed_parameters, "nonzero"_a = false,
           "The parameters as ErrorParameter records (name, error, kind, unit, value); only non-zero ones with "
           "nonzero=True (as mtcal errors --nonzero).")
      .def(
          "to_dict",
          [](const Machine& mm, bool nonzero) {
            const auto listed = listed_parameters(mm, nonzero);
            return to_py(to_json(mm, std::span<const ErrorParameter>(listed)));
          },
          "nonzero"_a = false, "The parameter listing as `mtcal errors --json` prints it.")
      .def("with_params", &with_params, "values"_a = py::none(), py::kw_only(), "unit"_a = "",
           R"(A copy with parameters set by name.

values: dict name -> value ("EXX.1", "EC0Y", "EXt"; names with a dot need the dict); keyword
arguments work for plain names (EC0Y=2e-5). unit: '' (default) for each parameter's internal
unit (mm, rad, mm/mm ...), or a unit name ('um', 'urad', 'um/m') for parameters in mm or rad.
Raises ModelError for an unknown name or a non-finite value.)")
      .def(
          "with_parameter_file",
          [](const Machine& mm, const std::string& path) {
            Machine c = mm;
            load_parameters(c, path);
            return c;
          },
          "path"_a, "A copy with a parameter file applied (mtcal_parameters: 1; e.g. from identify or rotary-axis).")
      .def(
          "with_only",
          [](const Machine& mm, const std::vector<std::string>& names) {
            Machine c = mm;
            c.keep_only(names);
            return c;
          },
          "names"_a, "A copy keeping only these errors or parameters (as --only); every other one is zero.")
      .def(
          "without_errors",
          [](const Machine& mm) {
            Machine c = mm;
            c.clear_errors();
            return c;
          },
          "A copy with every error zero (the nominal machine).")
      .def(
          "with_tool_length",
          [](const Machine& mm, double length) { return MachineBuilder(mm).tool_length(length).build(); }, "length"_a,
          "A copy with another tool length (mm, >= 0).")
      .def("to_yaml", &to_yaml, "Machine-file YAML that Machine.parse reads back to the same machine (internal units).")
      .def(
          "save", [](const Machine& mm, const std::string& path) { write_file_atomically(path, to_yaml(mm)); },
          "path"_a, "Writes to_yaml() to path (complete or not at all).")
      .def(
          "parameters_yaml",
          [](const Machine& mm, const std::vector<std::string>& errors, const std::string& comment) {
            std::vector<ErrorName> names;
            for (const auto& e : errors) {
              auto n = ErrorName::parse(e);
              if (!n || !mm.has_error(*n))
                throw InputError({"errors", 0, e}, "unknown error name '" + e + "' for topology " + mm.topology.chain);
              names.push_back(*n);
            }
            return parameters_yaml(mm, names, comment);
          },
          "errors"_a, "comment"_a = "", "A parameter file (mtcal_parameters: 1) with these errors' values.")
      .def(
          "parse_joints",
          [](const Machine& mm, const std::string& spec) { return to_array(parse_joint_values(mm, spec, "spec")); },
          "spec"_a, "'X=100,Y=50,B=30' (mm, deg; axes not named are 0) -> configuration in internal units.")
      .def(
          "format_joints",
          [](const Machine& mm, py::handle q) { return format_joint_values(mm, configuration(mm, q, "q")); }, "q"_a,
          "A configuration (internal units) as 'X=100,B=30' (mm, deg).")
      .def(
          "grid",
          [](const Machine& mm, py::handle spec, bool travel_check, std::size_t max_count) {
            const GridValues values = grid_values(mm, spec, "grid");
            check_grid(mm, values, "grid", travel_check, max_count);
            return grid_array(mm, values);
          },
          "spec"_a, py::kw_only(), "travel_check"_a = false, "max_count"_a = std::size_t{100'000'000},
          R"(Every configuration of a full grid, shape (N, k), internal units, the last axis varying fastest
(the order of `mtcal eval --grid`). spec: "X=-300:300:7,B=-90:90:5" (lo:hi:count, mm and deg; a
single value holds an axis; axes not named are 0) or a dict axis letter -> values in internal units.)")
      .def("__copy__", [](const Machine& mm) { return mm; })
      .def(
          "__deepcopy__", [](const Machine& mm, py::dict) { return mm; }, "memo"_a)
      .def("__repr__", [](const Machine& mm) {
        return "<mtcal.Machine '" + mm.name + "' " + mm.topology.chain + ", " + std::to_string(mm.parameter_count()) +
               " parameters>";
      });

  py::class_<MachineBuilder>(m, "MachineBuilder", R"(Builds a Machine item by item, every item checked at once.

Internal units (mm, rad). Topology first, then axes, tool, workpiece and errors in any order;
each method returns the builder, so calls chain:

    m = (mtcal.MachineBuilder().name("demo").topology("wXfYZt")
         .axis("X", travel=(0, 500)).axis("Y", travel=(0, 400)).axis("Z", travel=(-300, 0))
         .tool(length=100).motion("EXX", polynomial=[0, 5e-6]).error_value("EC0Y", 2e-5).build())

A wrong item raises ModelError "<item>: <what is wrong>".)")
      .def(py::init<>())
      .def(py::init<const Machine&>(), "start"_a, "Starts from an existing machine.")
      .def("name", &MachineBuilder::name, "name"_a, py::return_value_policy::reference_internal)
      .def("description", &MachineBuilder::description, "description"_a, py::return_value_policy::reference_internal)
      .def(
          "topology", [](MachineBuilder& b, const std::string& chain) -> MachineBuilder& { return b.topology(chain); },
          "chain"_a, py::return_value_policy::reference_internal,
          "'wCBXfYZt': workpiece w, axes, frame f, axes, tool t. Resets axes and errors.")
      .def(
          "axis",
          [](MachineBuilder& b, const std::string& letter, std::optional<double> sign, py::object travel,
             py::object point) -> MachineBuilder& {
            const char a = letter_of_arg(letter, "axis");
            if (sign) {
              const char axes[] = "XYZABC";
              const auto pos = std::string(axes).find(a);
              b.axis_direction(a, pos == std::string::npos ? 0 : static_cast<int>(pos % 3), *sign);
            }
            if (!travel.is_none()) {
              const auto t = as_std_vector(travel, "travel", 2);
              b.axis_travel(a, t[0], t[1]);
            }
            if (!point.is_none()) b.axis_point(a, vec3_of(point, "point"));
            return b;
          },
          "letter"_a, py::kw_only(), "sign"_a = py::none(), "travel"_a = py::none(), "point"_a = py::none(),
          py::return_value_policy::reference_internal,
          "An axis of the topology: sign +1/-1 of its direction (along its letter's machine axis), travel "
          "(min, max) in mm or rad, point [x, y, z] in mm.")
      .def(
          "tool",
          [](MachineBuilder& b, std::optional<double> length, py::object spindle_point,
             std::optional<int> axis) -> MachineBuilder& {
            if (length) b.tool_length(*length);
            if (!spindle_point.is_none()) b.tool_spindle_point(vec3_of(spindle_point, "spindle_point"));
            if (axis) b.tool_axis(*axis);
            return b;
          },
          py::kw_only(), "length"_a = py::none(), "spindle_point"_a = py::none(), "axis"_a = py::none(),
          py::return_value_policy::reference_internal,
          "Tool length (mm, >= 0), spindle gauge point [x, y, z] (mm), tool axis 0 x, 1 y, 2 z.")
      .def(
          "workpiece_origin",
          [](MachineBuilder& b, py::handle origin) -> MachineBuilder& {
            return b.workpiece_origin(vec3_of(origin, "origin"));
          },
          "origin"_a, py::return_value_policy::reference_internal)
      .def(
          "motion",
          [](MachineBuilder& b, const std::string& error, py::object polynomial, py::object table, py::object fourier,
             double reversal) -> MachineBuilder& {
            return b.motion(error, motion_function(polynomial, table, fourier, reversal));
          },
          "error"_a, py::kw_only(), "polynomial"_a = py::none(), "table"_a = py::none(), "fourier"_a = py::none(),
          "reversal"_a = 0.0, py::return_value_policy::reference_internal,
          R"(A motion error ("EXX") of an axis position q (mm or rad), internal units, one form:
polynomial=[c0, c1, c2, c3] (E = sum c_i q^i, + reversal * sign of the motion), table={"positions": [...],
"forward": [...], "backward": [...] (optional)}, fourier={"constant": c0, "cos": [...], "sin": [...]} (rotary axes).)")
      .def(
          "error_value",
          [](MachineBuilder& b, const std::string& error, double value) -> MachineBuilder& {
            return b.error_value(error, value);
          },
          "error"_a, "value"_a, py::return_value_policy::reference_internal,
          "A location (EC0Y) or mounting (EXt) error in mm or rad.")
      .def(
          "parameter",
          [](MachineBuilder& b, const std::string& name, double value, const std::string& unit) -> MachineBuilder& {
            return b.parameter(name, value, unit);
          },
          "name"_a, "value"_a, "unit"_a = "", py::return_value_policy::reference_internal,
          "One parameter by name ('EXX.1', 'EC0Y'); unit '' = its internal unit, or 'um', 'urad', 'um/m'.")
      .def_property_readonly("current", &MachineBuilder::current, "The machine as built so far (a copy)")
      .def("build", &MachineBuilder::build, "The machine, validated (ModelError naming the item otherwise).");

  py::class_<ErrorModel>(m, "ErrorModel",
                         "A machine compiled for evaluation: build once, evaluate many times "
                         "(mtcal.evaluate(machine, ...) compiles on each call).")
      .def(py::init<const Machine&>(), "machine"_a)
      .def_property_readonly("machine", &ErrorModel::machine)
      .def_property_readonly("axis_count", &ErrorModel::axis_count)
      .def(
          "evaluate",
          [](py::object self, py::handle configs, py::handle directions, int threads, bool travel_check,
             py::handle out) { return evaluate(self, configs, directions, threads, travel_check, out); },
          "configs"_a, "directions"_a = py::none(), py::kw_only(), "threads"_a = 0, "travel_check"_a = false,
          "out"_a = py::none(), "As mtcal.evaluate(model, ...): (N, 6) errors dx dy dz (mm) rx ry rz (rad).")
      .def(
          "jacobian",
          [](py::object self, py::handle configs, py::handle directions, int threads) {
            return jacobian(self, configs, directions, threads);
          },
          "configs"_a, "directions"_a = py::none(), py::kw_only(), "threads"_a = 0,
          "As mtcal.jacobian(model, ...): (N, 6, P).")
      .def(
          "actual_pose",
          [](const ErrorModel& em, py::handle q, py::object dir) {
            const auto qq = configuration(em.machine(), q, "q");
            Directions d;
            if (!dir.is_none()) d = as_directions(dir, "directions", 1, qq.size(), true);
            return pose_array(em.actual_pose(qq, d.span()));
          },
          "q"_a, "directions"_a = py::none(), "Tool pose in the workpiece frame with errors: 4x4 (mm).")
      .def(
          "nominal_pose",
          [](const ErrorModel& em, py::handle q) {
            return pose_array(em.nominal_pose(configuration(em.machine(), q, "q")));
          },
          "q"_a, "Tool pose in the workpiece frame without errors: 4x4 (mm).")
      .def("__repr__", [](const ErrorModel& em) { return "<mtcal.ErrorModel of '" + em.machine().name + "'>"; });

  py::class_<EvaluationRun>(m, "EvaluationRun",
                            "Every configuration's error with the summary of mtcal eval --points / --grid.")
      .def(
          "_write_report",
          [](const EvaluationRun& r, const std::string& path, const std::string& command) {
            const ErrorModel model(r.machine);
            const std::size_t k = r.machine.axes.size();
            ErrorStreamReport report(model, r.summary.count);
            report.add(ErrorChunk{0, k, r.q, r.dir, r.error});
            report.write(path, {command, {}, r.points_file, r.grid});
          },
          "path"_a, "command"_a)
      .def_property_readonly(
          "configs", [](const EvaluationRun& r) { return to_array(r.q, r.machine.axes.size()); },
          "(N, k) joint values, internal units, in the command's order (a grid: last axis fastest)")
      .def_property_readonly("directions",
                             [](const EvaluationRun& r) -> py::object {
                               if (r.dir.empty()) return py::none();
                               return to_int8_array(r.dir, r.machine.axes.size());
                             })
      .def_property_readonly(
          "errors", [](const EvaluationRun& r) { return to_array(r.error, 6); }, "(N, 6) dx dy dz (mm) rx ry rz (rad)")
      .def("__len__", [](const EvaluationRun& r) { return r.summary.count; })
      .def(
          "to_dict", [](const EvaluationRun& r) { return to_py(to_json(r.machine, r.summary)); },
          "As `mtcal eval --points/--grid --json`: configurations, seconds, max_translation {value (mm), at}, "
          "max_rotation {value (rad), at} (at in mm and deg).");
  m.def("evaluate_configurations", &evaluate_configurations, "machine"_a, "configs"_a = py::none(),
        "directions"_a = py::none(), py::kw_only(), "grid"_a = py::none(), "points"_a = "", "travel_check"_a = false,
        "threads"_a = 0,
        R"(The volumetric error at every configuration of configs (N, k) in internal units (with
optional directions), of a grid (the command's text "X=0:500:21,..." in mm and deg, or a dict
letter -> values in internal units) or of a points file (read_configurations' CSV), as `mtcal
eval --points/--grid`: EvaluationRun with configs, directions, errors (N, 6), to_dict() = the
command's --json, and write_report(run, path) = --report. Keeps every error in memory; evaluate()
is the array-only path.)");
  m.def("evaluate", &evaluate, "model"_a, "configs"_a, "directions"_a = py::none(), py::kw_only(), "threads"_a = 0,
        "travel_check"_a = false, "out"_a = py::none(), kEvaluateDoc);
  // The C++ batch call alone, timed in C++ on copies of the inputs into std::vectors and a reused
  // output: the reference of bench/python_evaluate.py (not part of the API).
  m.def(
      "_bench_evaluate_batch",
      [](const ErrorModel& model, py::handle configs, py::handle directions, int repeats, int threads) {
        const std::size_t k = model.axis_count();
        const Rows q = as_rows(configs, "configs", k, false);
        Directions d;
        if (!directions.is_none()) d = as_directions(directions, "directions", q.rows, k, false);
        const std::vector<double> qv(q.data, q.data + q.rows * k);
        const std::vector<std::int8_t> dv(d.data, d.data + d.size);
        std::vector<double> out(q.rows * 6);
        std::vector<double> seconds;
        LongCall release;  // without the GIL, stoppable with Ctrl-C
        for (int r = 0; r < repeats; ++r) {
          const auto t0 = std::chrono::steady_clock::now();
          model.evaluate_batch(qv, dv, out, BatchOptions{threads});
          seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        }
        return seconds;
      },
      "model"_a, "configs"_a, "directions"_a, "repeats"_a, "threads"_a = 0);
  m.def("jacobian", &jacobian, "model"_a, "configs"_a, "directions"_a = py::none(), py::kw_only(), "threads"_a = 0,
        kJacobianDoc);

  py::class_<Effects>(m, "Effects", "Effect of each single error on the tool at one configuration (mtcal effects).")
      .def(
          "_write_report",
          [](const Effects& e, const std::string& path, const std::string& command) {
            write_effects_report(path, e.machine, e.at, e.around, e.effects, {command, {}, "", ""});
          },
          "path"_a, "command"_a)
      .def_property_readonly("errors",
                             [](const Effects& e) {
                               std::vector<std::string> n;
                               for (const auto& x : e.effects) n.push_back(x.error.str());
                               return n;
                             })
      .def_property_readonly(
          "rotational",
          [](const Effects& e) {
            std::vector<bool> n;
            for (const auto& x : e.effects) n.push_back(x.rotational);
            return n;
          },
          "Per error: True when the effect is per 1 urad of it, else per 1 um")
      .def_property_readonly(
          "values",
          [](const Effects& e) {
            std::vector<double> v;
            for (const auto& x : e.effects) v.insert(v.end(), x.effect.begin(), x.effect.end());
            return to_array(v, 6);
          },
          "(E, 6): dx dy dz in um, rx ry rz in urad, per 1 um or 1 urad of each error")
      .def(
          "to_dict", [](const Effects& e) { return to_py(to_json(e.machine, e.at, e.around, e.effects)); },
          "As `mtcal effects --json`.");
  m.def("effects", &effects, "machine"_a, "at"_a, py::kw_only(), "errors"_a = py::none(), "around"_a = "nominal",
        "travel_check"_a = false,
        R"(Effect of each single error on the tool at configuration `at` (internal units, shape (k,)):
dx dy dz in um and rx ry rz in urad per 1 um or 1 urad of the error. errors: names to keep
(default all). around: 'nominal' (the errors' definitions) or 'actual' (with the machine's
errors: second-order cross terms included). As `mtcal effects`.)");

  // ---------------------------------------------------------------- files
  py::class_<CsvTable>(m, "CsvTable", "A numeric CSV table (read_csv): columns, values (N, C), source lines.")
      .def_readonly("columns", &CsvTable::columns)
      .def_property_readonly("values",
                             [](const CsvTable& t) {
                               std::vector<double> v;
                               for (const auto& r : t.rows) v.insert(v.end(), r.begin(), r.end());
                               py::array_t<double> a = new_array({static_cast<py::ssize_t>(t.rows.size()),
                                                                  static_cast<py::ssize_t>(t.columns.size())});
                               std::copy(v.begin(), v.end(), a.mutable_data());
                               return a;
                             })
      .def_readonly("lines", &CsvTable::lines, "1-based source line of each row")
      .def("__getitem__", [](const CsvTable& t, const std::string& name) {
        const int c = t.column(name);
        if (c < 0) throw py::key_error(name);
        std::vector<double> v;
        for (const auto& r : t.rows) v.push_back(r[static_cast<std::size_t>(c)]);
        return to_array(v);
      });
  m.def("read_csv", &read_csv, "path"_a,
        "A CSV file whose first non-comment line names the columns, every value a finite number (InputError naming "
        "file, line and column otherwise).");
  m.def("parse_csv", &parse_csv, "text"_a, "source"_a = "<string>");

  py::class_<ConfigurationList>(m, "ConfigurationList",
                                "Configurations read from a CSV (read_configurations), checked, internal units.")
      .def_property_readonly(
          "configs", [](const ConfigurationList& l) { return to_array(l.q, l.axes); },
          "(N, k) joint values, mm and rad")
      .def_property_readonly(
          "directions",
          [](const ConfigurationList& l) -> py::object {
            if (l.dir.empty()) return py::none();
            return to_int8_array(l.dir, l.axes);
          },
          "(N, k) int8 directions of motion, or None")
      .def_readonly("lines", &ConfigurationList::lines)
      .def("__len__", &ConfigurationList::size);
  m.def("read_configurations", &read_configurations, "machine"_a, "path"_a, py::kw_only(), "travel_check"_a = true,
        "Configurations from a CSV: columns named by axis letters (mm, deg), optional dir<axis> (+1/-1). Every row "
        "checked (travels with travel_check); InputError naming file, line and column.");
  m.def(
      "write_errors_csv",
      [](const std::string& path, const Machine& mm, py::handle configs, py::handle errors, py::handle directions) {
        const std::size_t k = mm.axes.size();
        const Rows q = as_rows(configs, "configs", k, false);
        const Rows e = as_rows(errors, "errors", 6, false, false);
        if (e.rows != q.rows)
          throw py::value_error("errors: expected " + std::to_string(q.rows) + " rows like configs, found " +
                                std::to_string(e.rows));
        Directions d;
        if (!directions.is_none()) d = as_directions(directions, "directions", q.rows, k, false);
        ErrorStreamCsv file(path, mm, d.size != 0);
        ErrorChunk chunk{0, k, q.span(), d.span(), e.span()};
        file.write(chunk);
        file.commit();
      },
      "path"_a, "machine"_a, "configs"_a, "errors"_a, "directions"_a = py::none(),
      "Writes configurations (internal units, written in mm and deg) with their errors (N, 6) as the CSV of "
      "`mtcal eval --out` (read back by read_configurations).");
  m.def(
      "write_text_file", [](const std::string& path, const std::string& text) { write_file_atomically(path, text); },
      "path"_a, "text"_a, "Writes text to path through a temporary file: complete or not at all.");
}

}  // namespace mtcal::python
