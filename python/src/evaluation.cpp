// Python bindings of the evaluations: volumetric accuracy, contributions, histograms, diagonals, ISO 230-2, ISO
// 230-4, method comparison, tool paths and the corrected G-code program; their files.
#include <chrono>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <sstream>

#include "common.hpp"
#include "results.hpp"
#include "mtcal/evaluation/ballbar.hpp"
#include "mtcal/evaluation/compare.hpp"
#include "mtcal/evaluation/diagonals.hpp"
#include "mtcal/evaluation/iso230_2.hpp"
#include "mtcal/evaluation/toolpath.hpp"
#include "mtcal/evaluation/volumetric_study.hpp"
#include "mtcal/evaluation/volumetric_tolerance.hpp"
#include "mtcal/io/points/error_csv.hpp"
#include "mtcal/io/instruments/iso230_files.hpp"
#include "mtcal/io/json/evaluation_json.hpp"
#include "mtcal/io/system/files.hpp"
#include "mtcal/compensation/gcode_correction.hpp"
#include "mtcal/io/gcode/program_input.hpp"
#include "mtcal/io/gcode/reader.hpp"
#include "mtcal/io/gcode/rewrite.hpp"
#include "mtcal/io/json/gcode_correction_json.hpp"
#include "mtcal/io/text/joints.hpp"
#include "mtcal/io/json/toolpath_json.hpp"
#include "mtcal/io/json/volumetric_json.hpp"
#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/report/toolpath.hpp"
#include "mtcal/report/volumetric.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal::python {

using namespace pybind11::literals;

namespace {

using Clock = std::chrono::steady_clock;

py::array_t<double> vec3s(std::span<const Vec3> v) {
  py::array_t<double> a = new_array({static_cast<py::ssize_t>(v.size()), 3});
  double* o = a.mutable_data();
  for (std::size_t i = 0; i < v.size(); ++i)
    for (int c = 0; c < 3; ++c) o[3 * i + static_cast<std::size_t>(c)] = v[i][c];
  return a;
}

std::vector<Vec3> as_vec3s(py::handle obj, const char* name) {
  const Rows r = as_rows(obj, name, 3, false);
  std::vector<Vec3> out(r.rows);
  for (std::size_t i = 0; i < r.rows; ++i) out[i] = Vec3(r.data[3 * i], r.data[3 * i + 1], r.data[3 * i + 2]);
  return out;
}

// ---------------------------------------------------------------- maps and volumetric accuracy

// The map of the configurations or the grid argument (exactly one), as mtcal volumetric builds it.
ErrorMap build_map(const Machine& m, const ErrorModel& model, py::handle configs, py::handle directions,
                   py::handle grid, bool travel_check, int threads) {
  if (configs.is_none() == grid.is_none()) throw py::value_error("expected exactly one of configs, grid");
  if (!grid.is_none()) {
    const GridValues values = grid_values(m, grid, "grid");
    check_grid(m, values, "grid", travel_check, 200'000'000);
    return grid_error_map(model, values, {threads});
  }
  const std::size_t k = m.axes.size();
  const Rows q = as_rows(configs, "configs", k, false);
  if (q.rows == 0) throw py::value_error("configs: expected at least one configuration, found none");
  Directions d;
  if (!directions.is_none()) d = as_directions(directions, "directions", q.rows, k, false);
  if (travel_check) {
    std::vector<double> row(k);
    for (std::size_t i = 0; i < q.rows; ++i) {
      std::copy_n(q.data + i * k, k, row.begin());
      check_joints(m, row, "configs[" + std::to_string(i) + "]", true);
    }
  }
  LongCall release;  // without the GIL, stoppable with Ctrl-C
  return error_map(model, std::vector<double>(q.data, q.data + q.rows * k), d.span(), {threads});
}

JointBox box_of(const Machine& m, py::handle box, const char* name) {
  if (py::isinstance<py::str>(box)) return parse_box(m, box.cast<std::string>(), name);
  JointBox b;
  const std::size_t k = m.axes.size();
  b.lo.assign(k, -std::numeric_limits<double>::infinity());
  b.hi.assign(k, std::numeric_limits<double>::infinity());
  b.named.assign(k, false);
  for (auto item : box.cast<py::dict>()) {
    const auto letter = item.first.cast<std::string>();
    const auto i = letter.size() == 1 ? m.axis_index(letter[0]) : std::nullopt;
    if (!i) throw py::value_error(std::string(name) + ": axis '" + letter + "' is not in topology " + m.topology.chain);
    const std::string what = std::string(name) + "['" + letter + "']";
    const auto v = as_std_vector(item.second, what.c_str(), 2);
    b.lo[*i] = v[0];
    b.hi[*i] = v[1];
    b.named[*i] = true;
  }
  return b;
}

struct VolumetricResult {
  Machine machine;
  ErrorMap map;
  VolumetricStudy study;
  double seconds_map = 0;
  std::string grid_text, box_text;  // the grid and box as given in the command's text form, for the report
};

VolumetricResult volumetric(const Machine& m, py::handle configs, py::handle directions, py::handle grid,
                            py::handle box, int box_scan, py::handle centre, py::handle histogram, py::handle grouping,
                            bool travel_check, int threads) {
  VolumetricRequest r;
  if (!box.is_none()) r.box = box_of(m, box, "box");
  r.box_scan = box_scan;
  if (!centre.is_none()) {
    if (box_scan == 0) throw py::value_error("centre: goes with box_scan");
    r.centre = configuration(m, centre, "centre");
  }
  if (!histogram.is_none() && !(py::isinstance<py::bool_>(histogram) && !histogram.cast<bool>())) {
    r.histogram = true;
    if (py::isinstance<py::str>(histogram)) {
      if (histogram.cast<std::string>() != "auto")
        throw py::value_error("histogram: expected True, 'auto' or a bin count, found '" +
                              histogram.cast<std::string>() + "'");
    } else if (!py::isinstance<py::bool_>(histogram)) {
      const auto bins = histogram.cast<long long>();
      if (bins < 1 || bins > 1'000'000)
        throw py::value_error("histogram: expected a bin count from 1 to 1e6, found " + std::to_string(bins));
      r.histogram_bins = static_cast<std::size_t>(bins);
    }
  }
  if (!grouping.is_none() && !(py::isinstance<py::bool_>(grouping) && !grouping.cast<bool>())) {
    r.grouping.emplace();
    if (py::isinstance<py::dict>(grouping)) {
      const auto g = grouping.cast<py::dict>();
      if (g.contains("angle")) r.grouping->angle_tolerance = g["angle"].cast<double>();
      if (g.contains("magnitude")) r.grouping->magnitude_tolerance = g["magnitude"].cast<double>();
    }
  }
  r.threads = threads;
  const ErrorModel model(m);
  VolumetricResult out{m, {}, {}, 0, {}, {}};
  if (py::isinstance<py::str>(grid)) out.grid_text = grid.cast<std::string>();
  if (py::isinstance<py::str>(box)) out.box_text = box.cast<std::string>();
  const auto t0 = Clock::now();
  out.map = build_map(m, model, configs, directions, grid, travel_check, threads);
  out.seconds_map = std::chrono::duration<double>(Clock::now() - t0).count();
  LongCall release;  // without the GIL, stoppable with Ctrl-C
  out.study = study_volumetric(m, out.map, r);
  return out;
}

struct ContributionResult {
  Machine machine;
  ContributionStudy study;
};

ContributionResult contributions(const Machine& m, py::handle at, py::handle pair, py::handle configs,
                                 py::handle directions, py::handle grid, bool what_if, bool travel_check, int threads,
                                 std::optional<double> target_va) {
  const int modes = !at.is_none() + !pair.is_none() + !configs.is_none() + !grid.is_none();
  if (modes != 1) throw py::value_error("expected exactly one of at, pair, configs, grid");
  if (target_va && (!(*target_va >= 0) || !std::isfinite(*target_va)))
    throw py::value_error("target_va: expected a VA >= 0 in mm");
  if (target_va && (!at.is_none() || !pair.is_none()))
    throw py::value_error("target_va: goes with a map (configs or grid), not with at or pair");
  if (!at.is_none()) {
    auto a = configuration(m, at, "at");
    check_joints(m, a, "at", travel_check);
    return {m, contributions_at(m, std::move(a))};
  }
  if (!pair.is_none()) {
    const auto p = pair.cast<py::sequence>();
    if (p.size() != 2) throw py::value_error("pair: expected two configurations (from, to)");
    auto b = configuration(m, p[0], "pair[0]");
    auto a = configuration(m, p[1], "pair[1]");
    check_joints(m, b, "pair", travel_check);
    check_joints(m, a, "pair", travel_check);
    return {m, contributions_between(m, std::move(b), std::move(a))};
  }
  const ErrorModel model(m);
  const ErrorMap map = build_map(m, model, configs, directions, grid, travel_check, threads);
  LongCall release;  // without the GIL, stoppable with Ctrl-C
  return {m, critical_pair_contributions(m, map, what_if, threads, target_va)};
}

struct DiagonalsResult {
  Machine machine;
  std::vector<DiagonalProfile> profiles;
  std::string box_text;  // the box in the command's text form when given so, for the report
};

DiagonalsResult diagonals(const Machine& m, py::handle box_arg, std::size_t points, bool face, bool travel_check) {
  // As mtcal diagonals: the linear axes X Y Z need a range; every other axis is held at its value or 0.
  JointBox box = box_of(m, box_arg, "box");
  for (std::size_t k = 0; k < m.axes.size(); ++k)
    if (!box.named[k]) {
      const char l = m.axes[k].letter;
      if (m.axes[k].kind == AxisKind::Linear && (l == 'X' || l == 'Y' || l == 'Z'))
        throw InputError({"box", 0, std::string(1, l)},
                         std::string("expected a range lo:hi for ") + l + " (the box's linear axes), found none");
      box.lo[k] = box.hi[k] = 0.0;
    }
  check_joints(m, box.lo, "box", travel_check);
  check_joints(m, box.hi, "box", travel_check);
  const ErrorModel model(m);
  return {m, diagonal_displacements(model, box.lo, box.hi, {points, face}),
          py::isinstance<py::str>(box_arg) ? box_arg.cast<std::string>() : std::string()};
}

// ---------------------------------------------------------------- ISO 230-2

py::object runs_array(const std::vector<std::vector<double>>& runs) {
  const std::size_t n = runs.empty() ? 0 : runs[0].size();
  bool rect = true;
  for (const auto& r : runs) rect = rect && r.size() == n;
  if (!rect) {
    py::list l;
    for (const auto& r : runs) l.append(to_array(r));
    return l;
  }
  std::vector<double> flat;
  for (const auto& r : runs) flat.insert(flat.end(), r.begin(), r.end());
  if (n == 0) return new_array({static_cast<py::ssize_t>(runs.size()), 0});
  return to_array(flat, n);
}

std::vector<std::vector<double>> runs_of(py::handle obj, const char* name, std::size_t targets) {
  const Rows r = as_rows(obj, name, std::nullopt, false);
  if (r.rows != targets)
    throw py::value_error(std::string(name) + ": expected one row per target (" + std::to_string(targets) +
                          "), found " + std::to_string(r.rows));
  std::vector<std::vector<double>> out(r.rows);
  for (std::size_t i = 0; i < r.rows; ++i) out[i].assign(r.data + i * r.cols, r.data + (i + 1) * r.cols);
  return out;
}

PositioningRuns make_runs(py::handle targets, py::handle up, py::handle down, const std::string& unit,
                          const std::string& source) {
  PositioningRuns runs;
  runs.source = source;
  runs.unit = unit;
  runs.targets = as_std_vector(targets, "targets");
  runs.up = runs_of(up, "up", runs.targets.size());
  runs.down = runs_of(down, "down", runs.targets.size());
  return runs;
}

// ---------------------------------------------------------------- ISO 230-4

const char* direction_name(CircleDirection d) { return d == CircleDirection::CW ? "cw" : "ccw"; }

CircleDirection direction_of(const std::string& s, const char* name) {
  if (s == "cw") return CircleDirection::CW;
  if (s == "ccw") return CircleDirection::CCW;
  throw py::value_error(std::string(name) + ": expected 'cw' or 'ccw', found '" + s + "'");
}

BallbarTrace make_trace(const std::vector<std::string>& directions, py::handle angles, py::handle radii,
                        const std::string& source) {
  const auto a = as_std_vector(angles, "angles");
  const auto r = as_std_vector(radii, "radii", a.size());
  if (directions.size() != a.size())
    throw py::value_error("directions: expected " + std::to_string(a.size()) + " values like angles, found " +
                          std::to_string(directions.size()));
  BallbarTrace t;
  t.source = source;
  for (std::size_t i = 0; i < a.size(); ++i)
    t.points.push_back({direction_of(directions[i], "directions"), a[i], r[i]});
  return t;
}

// The bar's length defines the test: required, as `mtcal ballbar --radius` (no default that could
// silently differ from the bar used).
void check_radius(double radius) {
  if (!(radius > 0) || !std::isfinite(radius)) {
    std::ostringstream found;
    found << radius;
    throw py::value_error(
        "radius: expected the nominal radius of the test in mm (the ballbar's length, e.g. radius=150), found " +
        found.str());
  }
}

BallbarResult ballbar(const BallbarTrace& trace, double radius, const std::string& plane, double overshoot_start,
                      double overshoot_stop, std::optional<std::string> direction, double feed, bool diagnose) {
  if (plane != "XY" && plane != "YZ" && plane != "ZX")
    throw py::value_error("plane: expected 'XY', 'YZ' or 'ZX', found '" + plane + "'");
  check_radius(radius);
  BallbarOptions bo;
  bo.nominal_radius = radius;
  bo.overshoot_start = overshoot_start;
  bo.overshoot_stop = overshoot_stop;
  if (direction) bo.only = direction_of(*direction, "direction");
  BallbarResult r{evaluate_ballbar(trace, bo), std::nullopt, plane, radius, feed, trace};
  if (!bo.only && diagnose) r.diagnosis = diagnose_ballbar(trace, bo, plane);
  return r;
}

py::object optional_number(const std::optional<double>& v) { return v ? py::object(py::float_(*v)) : py::none(); }

// ---------------------------------------------------------------- tool paths

struct ToolpathResult {
  Machine machine;
  ToolpathSummary summary;
  ToolpathChunk points;               // every point of the program, the chunks appended
  std::string interpreter = "mtcal";  // who read the program (GcodeProgram::interpreter)
  ToolpathReportInputs report{};      // what the report names: the program, the step, the options
};

// {"X": 100, ...} (mm, deg) -> the axes named, letters of the machine only; `name` is the argument.
std::array<std::optional<double>, 6> axis_values(const Machine& m, py::handle values, const std::string& name) {
  std::array<std::optional<double>, 6> o{};
  if (values.is_none()) return o;
  if (!py::isinstance<py::dict>(values))
    throw py::type_error(name + ": expected a dict axis letter -> value (mm, deg), e.g. {\"X\": 100}");
  for (auto item : values.cast<py::dict>()) {
    const auto letter = item.first.cast<std::string>();
    const std::string axes = "XYZABC";
    const auto slot = letter.size() == 1 ? axes.find(letter[0]) : std::string::npos;
    if (slot == std::string::npos || !m.axis_index(letter[0]))
      throw py::value_error(name + ": axis '" + letter + "' is not in topology " + m.topology.chain);
    const double v = item.second.cast<double>();
    if (!std::isfinite(v)) throw py::value_error(name + ": axis '" + letter + "' is not a finite number");
    o[slot] = v;
  }
  return o;
}

GcodePosition origin_of(const Machine& m, py::handle origin, const std::string& name = "origin") {
  GcodePosition o{};
  const auto values = axis_values(m, origin, name);
  for (std::size_t k = 0; k < 6; ++k) o[k] = values[k].value_or(0.0);
  return o;
}

// The setup a program runs under and who reads it, as the commands' --tool-table --tool-units
// --parameters --parameter-units --work-offset --g28 --g30 --interpreter --rs274 --rs274-timeout.
struct GcodeReading {
  std::string interpreter = "auto";
  std::optional<std::string> rs274;
  double rs274_timeout = 300;
  std::string tool_table, tool_units = "mm", parameters, parameter_units = "mm";
  py::object work_offsets = py::none(), g28 = py::none(), g30 = py::none();

  bool given() const {
    return interpreter != "auto" || rs274 || rs274_timeout != 300 || !tool_table.empty() || tool_units != "mm" ||
           !parameters.empty() || parameter_units != "mm" || !work_offsets.is_none() || !g28.is_none() ||
           !g30.is_none();
  }
  static double scale(const std::string& units, const char* name) {
    if (units == "mm") return 1.0;
    if (units == "in") return 25.4;  // mm per inch
    throw py::value_error(std::string(name) + ": expected 'mm' or 'in', found '" + units + "'");
  }
  GcodeSetupInputs setup(const Machine& m) const {
    GcodeSetupInputs in;
    in.tool_table = tool_table;
    in.tool_scale = scale(tool_units, "tool_units");
    in.parameters = parameters;
    in.parameter_scale = scale(parameter_units, "parameter_units");
    if (!work_offsets.is_none()) {
      if (!py::isinstance<py::dict>(work_offsets))
        throw py::type_error("work_offsets: expected a dict system -> {axis: value}, e.g. {\"G55\": {\"X\": 100}}");
      for (auto item : work_offsets.cast<py::dict>()) {
        const auto name = item.first.cast<std::string>();
        const auto index = work_system_index(name);
        if (!index)
          throw py::value_error("work_offsets: expected a system G54 G55 G56 G57 G58 G59 G59.1 G59.2 G59.3, found '" +
                                name + "'");
        in.work_offsets.push_back({*index, axis_values(m, item.second, "work_offsets[" + name + "]")});
      }
    }
    if (!g28.is_none()) in.g28 = origin_of(m, g28, "g28");
    if (!g30.is_none()) in.g30 = origin_of(m, g30, "g30");
    return in;
  }
  mtcal::GcodeInputOptions options() const {
    mtcal::GcodeInputOptions o;
    o.interpreter = parse_gcode_interpreter(interpreter, "interpreter");
    if (rs274) o.rs274.executable = *rs274;
    o.rs274_named = rs274.has_value();
    if (!(rs274_timeout >= 0.1 && rs274_timeout <= 86400))
      throw py::value_error("rs274_timeout: expected seconds in [0.1, 86400], found " + std::to_string(rs274_timeout));
    o.rs274.timeout = rs274_timeout;
    return o;
  }
};

std::string axes_of(const Machine& m) {
  std::string axes;
  for (const auto& ax : m.axes) axes += ax.letter;
  return axes;
}

ToolpathResult toolpath(const Machine& m, py::handle program, double step, double angle_step, bool skip_rapids,
                        py::handle origin, bool directions, bool travel_check, int threads, const GcodeReading& reading) {
  ToolpathOptions opt;
  opt.step = step;
  opt.angle_step = angle_step;
  opt.skip_rapids = skip_rapids;
  opt.origin = origin_of(m, origin);
  opt.directions = directions;
  opt.travel_check = travel_check;
  opt.batch.threads = threads;
  ToolpathInterpolator check(m, opt);  // a bad step is refused before any reading
  const ErrorModel model(m);
  ToolpathResult r{m, {}, {}};
  r.report.step = step;
  r.report.skip_rapids = skip_rapids;
  r.report.directions = directions;
  auto sink = [&](const ToolpathChunk& c) {
    auto append = [](auto& to, const auto& from) { to.insert(to.end(), from.begin(), from.end()); };
    append(r.points.line, c.line);
    append(r.points.n, c.n);
    append(r.points.motion, c.motion);
    append(r.points.s, c.s);
    append(r.points.q, c.q);
    append(r.points.dir, c.dir);
    append(r.points.error, c.error);
  };
  if (py::isinstance<GcodeProgram>(program)) {
    if (reading.given())
      throw py::value_error(
          "interpreter, rs274, tool_table, parameters, work_offsets, g28, g30: they set up the reading of a program "
          "file; a GcodeProgram is read already (give the path instead)");
    const auto& p = program.cast<const GcodeProgram&>();
    r.interpreter = p.interpreter;
    r.report.program = p.source;
    r.report.program_file = std::filesystem::is_regular_file(p.source);  // read_gcode's; parse_gcode's names none
    LongCall release;  // without the GIL, stoppable with Ctrl-C
    r.summary = simulate_toolpath(model, p, opt, sink);
  } else {
    const auto path = program.cast<std::string>();
    r.report.program = path;
    const GcodeSetupInputs setup = reading.setup(m);
    const mtcal::GcodeInputOptions options = reading.options();
    LongCall release;  // without the GIL, stoppable with Ctrl-C
    GcodeInput in = open_gcode(path, axes_of(m), setup, options);
    r.interpreter = in.interpreter;
    r.summary = simulate_toolpath(model, *in.moves, opt, sink);
  }
  return r;
}

// ---------------------------------------------------------------- corrected G-code (mtcal compensate --gcode)

struct CorrectedGcode {
  Machine machine;
  std::string program, interpreter;
  GcodeCorrectionResult result;
  CorrectedProgram corrected;
  double seconds = 0;
};

CorrectedGcode correct_gcode(const Machine& m, const std::string& path, double max_deviation, bool linearise_arcs,
                             py::handle origin, int decimals, bool directions, bool orientation, bool travel_check,
                             const GcodeReading& reading) {
  GcodeCorrectionOptions opt;
  opt.max_deviation = max_deviation;
  opt.linearise_arcs = linearise_arcs;
  opt.directions = directions;
  opt.orientation = orientation;
  opt.travel_check = travel_check;
  opt.origin = origin_of(m, origin);
  GcodeRewriteOptions ro;
  ro.decimals = decimals;
  const GcodeSetupInputs setup = reading.setup(m);
  const mtcal::GcodeInputOptions options = reading.options();
  const auto t0 = std::chrono::steady_clock::now();
  CorrectedGcode c{m, path, "mtcal", {}, {}, 0};
  {
    LongCall release;  // without the GIL, stoppable with Ctrl-C
    // As the command: the program read (by the interpreter chosen), then its text rewritten.
    const GcodeProgram program = read_gcode_program(path, axes_of(m), setup, options);
    const std::string text = read_text_file(path, "G-code program");
    c.interpreter = program.interpreter;
    c.result = correct_program(ErrorModel(m), program, opt);
    c.corrected = corrected_program(m, program, text, c.result.moves, ro);
  }
  c.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return c;
}

}  // namespace

void bind_evaluation(py::module_& m) {
  // ---------------------------------------------------------------- volumetric
  py::class_<ErrorMap>(m, "ErrorMap", "Translational errors at a set of configurations (error_map, volumetric).")
      .def_property_readonly(
          "configs", [](const ErrorMap& e) { return to_array(e.q, e.axes); }, "(N, k) joint values, internal units")
      .def_property_readonly("directions",
                             [](const ErrorMap& e) -> py::object {
                               if (e.dir.empty()) return py::none();
                               return to_int8_array(e.dir, e.axes);
                             })
      .def_property_readonly(
          "errors", [](const ErrorMap& e) { return vec3s(e.error); }, "(N, 3) dx dy dz, mm")
      .def("__len__", &ErrorMap::size);
  m.def(
      "error_map",
      [](const Machine& mm, py::handle configs, py::handle directions, py::handle grid, bool travel_check,
         int threads) {
        const ErrorModel model(mm);
        return build_map(mm, model, configs, directions, grid, travel_check, threads);
      },
      "machine"_a, "configs"_a = py::none(), "directions"_a = py::none(), py::kw_only(), "grid"_a = py::none(),
      "travel_check"_a = false, "threads"_a = 0,
      "The translational error map (mm) of configs (N, k) in internal units, or of a grid (Machine.grid's spec).");
  m.def(
      "write_error_map_csv",
      [](const std::string& path, const Machine& mm, const ErrorMap& map) { write_error_map_csv(path, mm, map); },
      "path"_a, "machine"_a, "map"_a, "The map as `mtcal volumetric --out` writes it.");

  py::class_<PointPair>(m, "PointPair", "Two points i, j of a set and the value of their difference (mm).")
      .def_readonly("value", &PointPair::value)
      .def_readonly("i", &PointPair::i)
      .def_readonly("j", &PointPair::j)
      .def("__iter__", [](const PointPair& p) { return py::iter(py::make_tuple(p.value, p.i, p.j)); })
      .def("__repr__", [](const PointPair& p) {
        return "<mtcal.PointPair " + std::to_string(p.value) + " mm (" + std::to_string(p.i) + ", " +
               std::to_string(p.j) + ")>";
      });
  py::class_<VolumetricAccuracy>(m, "VolumetricAccuracy",
                                 "Fletcher's VA: the largest |e_i - e_j| over all pairs, and per component.")
      .def_readonly("points", &VolumetricAccuracy::points)
      .def_readonly("pairs", &VolumetricAccuracy::pairs)
      .def_readonly("va", &VolumetricAccuracy::va, "PointPair: value (mm), i, j")
      .def_property_readonly(
          "components",
          [](const VolumetricAccuracy& v) { return std::vector<PointPair>(v.component.begin(), v.component.end()); },
          "x, y, z PointPairs")
      .def_readonly("distance_evaluations", &VolumetricAccuracy::distance_evaluations)
      .def("to_dict", [](const VolumetricAccuracy& v) {
        py::dict d;
        d["points"] = v.points;
        d["pairs"] = v.pairs;
        d["va"] = v.va.value;
        d["i"] = v.va.i;
        d["j"] = v.va.j;
        for (int c = 0; c < 3; ++c)
          d[py::str(std::string("va_") + "xyz"[c])] = v.component[static_cast<std::size_t>(c)].value;
        return d;
      });
  m.def(
      "volumetric_accuracy",
      [](py::handle errors) {
        const auto e = as_vec3s(errors, "errors");
        LongCall release;  // without the GIL, stoppable with Ctrl-C
        return volumetric_accuracy(e);
      },
      "errors"_a, "Exact VA of error vectors, shape (N, 3) in mm: the same number every pair's comparison gives.");

  py::class_<Distribution>(m, "Distribution", "A distribution with its histogram (equal bins from lo).")
      .def_readonly("count", &Distribution::count)
      .def_readonly("mean", &Distribution::mean)
      .def_readonly("min", &Distribution::min)
      .def_readonly("max", &Distribution::max)
      .def_property_readonly("lo", [](const Distribution& d) { return d.histogram.lo; })
      .def_property_readonly("width", [](const Distribution& d) { return d.histogram.width; })
      .def_property_readonly("counts",
                             [](const Distribution& d) {
                               py::array_t<std::uint64_t> a(static_cast<py::ssize_t>(d.histogram.counts.size()));
                               std::copy(d.histogram.counts.begin(), d.histogram.counts.end(), a.mutable_data());
                               return a;
                             })
      .def_property_readonly(
          "edges",
          [](const Distribution& d) {
            std::vector<double> e;
            for (std::size_t b = 0; b <= d.histogram.counts.size(); ++b)
              e.push_back(d.histogram.lo + static_cast<double>(b) * d.histogram.width);
            return to_array(e);
          },
          "Bin edges (len(counts) + 1)")
      .def(
          "quantile", [](const Distribution& d, double p) { return d.histogram.quantile(p); }, "p"_a)
      .def("to_dict", [](const Distribution& d) { return to_py(to_json(d)); });
  m.def(
      "pair_histogram",
      [](py::handle errors, std::size_t bins, double upper, int threads) {
        const auto e = as_vec3s(errors, "errors");
        LongCall release;  // without the GIL, stoppable with Ctrl-C
        return pair_distribution(
            e, bins == 0 ? rice_bins(static_cast<double>(e.size()) * (static_cast<double>(e.size()) - 1) / 2) : bins,
            upper, threads);
      },
      "errors"_a, "bins"_a = 0, "upper"_a = 0.0, py::kw_only(), "threads"_a = 0,
      "Distribution of |e_i - e_j| over all pairs of errors (N, 3) in mm; bins 0: the Rice rule; upper >= VA (0: "
      "computed).");
  m.def(
      "value_histogram",
      [](py::handle values, std::size_t bins) {
        const auto v = as_std_vector(values, "values");
        return value_distribution(v, bins == 0 ? rice_bins(static_cast<double>(v.size())) : bins);
      },
      "values"_a, "bins"_a = 0, "Distribution of values over equal bins between their min and max.");

  py::class_<Contribution>(m, "Contribution", "First-order contribution of one error (mm).")
      .def_property_readonly("error", [](const Contribution& c) { return c.error.str(); })
      .def_property_readonly("effect", [](const Contribution& c) { return to_array(c.effect); })
      .def_readonly("along", &Contribution::along)
      .def_readonly("share", &Contribution::share);
  py::class_<ContributionAnalysis>(m, "ContributionAnalysis")
      .def_property_readonly("exact", [](const ContributionAnalysis& c) { return to_array(c.exact); })
      .def_property_readonly("first_order", [](const ContributionAnalysis& c) { return to_array(c.first_order); })
      .def_readonly("residual", &ContributionAnalysis::residual)
      .def_readonly("items", &ContributionAnalysis::items, "Contributions, largest |along| first")
      .def(
          "to_dict", [](const ContributionAnalysis& c, std::size_t top) { return to_py(to_json(c, top)); },
          "top"_a = std::size_t{1000000});

  py::class_<VolumetricResult>(m, "VolumetricResult", "What mtcal volumetric computes of a map.")
      .def("_tolerance_values", [](const VolumetricResult& r) { return tolerance_values(r.study.va); })
      .def(
          "_write_report",
          [](const VolumetricResult& r, const std::string& path, const std::string& command, py::handle acceptance) {
            const ToleranceVerdict verdict =
                acceptance.is_none() ? ToleranceVerdict{} : acceptance.cast<const Acceptance&>().verdict;
            write_volumetric_report(path, ErrorModel(r.machine), r.map, r.study, r.box_text,
                                    {command, {}, "", r.grid_text}, verdict);
          },
          "path"_a, "command"_a, "acceptance"_a = py::none())
      .def_property_readonly(
          "va", [](const VolumetricResult& r) { return r.study.va.va.value; }, "mm")
      .def_property_readonly(
          "va_xyz",
          [](const VolumetricResult& r) {
            std::vector<double> v;
            for (const auto& c : r.study.va.component) v.push_back(c.value);
            return to_array(v);
          },
          "per component x, y, z (mm)")
      .def_property_readonly("accuracy", [](const VolumetricResult& r) { return r.study.va; })
      .def_property_readonly(
          "critical_pair", [](const VolumetricResult& r) { return py::make_tuple(r.study.va.va.i, r.study.va.va.j); },
          "Indices (i, j) into map of the critical pair")
      .def_readonly("map", &VolumetricResult::map)
      .def_property_readonly(
          "contributions", [](const VolumetricResult& r) { return r.study.critical; },
          "ContributionAnalysis of the critical difference")
      .def_property_readonly(
          "histogram",
          [](const VolumetricResult& r) -> py::object { return r.study.pairs ? py::cast(*r.study.pairs) : py::none(); },
          "Distribution of |e_i - e_j| over pairs (with histogram=...)")
      .def_property_readonly(
          "error_distribution",
          [](const VolumetricResult& r) -> py::object {
            return r.study.magnitudes ? py::cast(*r.study.magnitudes) : py::none();
          },
          "Distribution of |e_i| over the map (with histogram=...)")
      .def_property_readonly("box_va",
                             [](const VolumetricResult& r) -> py::object {
                               return r.study.box_va ? py::cast(*r.study.box_va) : py::none();
                             })
      .def(
          "to_dict", [](const VolumetricResult& r) { return to_py(to_json(r.machine, r.map, r.study, r.seconds_map)); },
          "As `mtcal volumetric --json` (keys in docs/volumetric.md).");
  m.def("volumetric", &volumetric, "machine"_a, "configs"_a = py::none(), "directions"_a = py::none(), py::kw_only(),
        "grid"_a = py::none(), "box"_a = py::none(), "box_scan"_a = 0, "centre"_a = py::none(),
        "histogram"_a = py::none(), "grouping"_a = py::none(), "travel_check"_a = false, "threads"_a = 0,
        R"(Volumetric accuracy (Fletcher 2009), as `mtcal volumetric`.

configs (N, k) in internal units (mm, rad) with optional directions, or grid ("X=0:500:21,..."
in mm and deg as the CLI's --grid, or a dict letter -> values in internal units). box: a
sub-box ("X=0:250,Y=0:200" or {"X": (lo, hi)} internal). box_scan: N centred boxes (centre:
a configuration). histogram: True/'auto' or a bin count. grouping: True or
{"angle": 0.1, "magnitude": 0.9}. Returns VolumetricResult (va in mm, to_dict()).)");

  py::class_<ContributionResult>(m, "ContributionResult", "What mtcal contributions computes.")
      .def(
          "_write_report",
          [](const ContributionResult& r, const std::string& path, const std::string& command) {
            write_contributions_report(path, r.machine, r.study, {command, {}, "", ""});
          },
          "path"_a, "command"_a)
      .def_property_readonly(
          "mode", [](const ContributionResult& r) { return r.study.mode; }, "'at', 'pair' or 'critical_pair'")
      .def_property_readonly("analysis", [](const ContributionResult& r) { return r.study.analysis; })
      .def_property_readonly("va",
                             [](const ContributionResult& r) -> py::object {
                               return r.study.va ? py::cast(*r.study.va) : py::none();
                             })
      .def_property_readonly(
          "what_if",
          [](const ContributionResult& r) {
            py::dict d;
            for (const auto& w : r.study.what_if) d[py::str(w.error.str())] = w.va;
            return d;
          },
          "error -> VA of the map without it (mm), smallest first")
      .def(
          "to_dict",
          [](const ContributionResult& r, std::size_t top) { return to_py(to_json(r.machine, r.study, top)); },
          "top"_a = std::size_t{10}, "As `mtcal contributions --json --top N`.");
  m.def("contributions", &contributions, "machine"_a, py::kw_only(), "at"_a = py::none(), "pair"_a = py::none(),
        "configs"_a = py::none(), "directions"_a = py::none(), "grid"_a = py::none(), "what_if"_a = true,
        "travel_check"_a = false, "threads"_a = 0, "target_va"_a = py::none(),
        R"(Contribution of every error (first order, mm) to the error at configuration `at`, to
e(to) - e(from) for pair=(from, to), or to the critical pair of a map (configs or grid) with the
exact VA without each error (what_if). target_va (mm; with a map): the greedy sequence of errors to
correct to reach this VA (--target-va). Configurations in internal units. As `mtcal contributions`.)");

  py::class_<DiagonalProfile>(m, "DiagonalProfile", "One ISO 230-6 diagonal: deviation along it (mm).")
      .def_readonly("name", &DiagonalProfile::name)
      .def_property_readonly("start", [](const DiagonalProfile& d) { return to_array(d.start); })
      .def_property_readonly("end", [](const DiagonalProfile& d) { return to_array(d.end); })
      .def_property_readonly("direction", [](const DiagonalProfile& d) { return to_array(d.direction); })
      .def_readonly("length", &DiagonalProfile::length)
      .def_property_readonly("position", [](const DiagonalProfile& d) { return to_array(d.position); })
      .def_property_readonly("deviation", [](const DiagonalProfile& d) { return to_array(d.deviation); })
      .def_readonly("range", &DiagonalProfile::range);
  py::class_<DiagonalsResult>(m, "DiagonalsResult")
      .def(
          "_write_report",
          [](const DiagonalsResult& r, const std::string& path, const std::string& command) {
            write_diagonals_report(path, r.machine, r.profiles, r.box_text, {command, {}, "", ""});
          },
          "path"_a, "command"_a)
      .def_readonly("profiles", &DiagonalsResult::profiles)
      .def(
          "to_dict", [](const DiagonalsResult& r) { return to_py(to_json(r.machine, r.profiles)); },
          "As `mtcal diagonals --json`.")
      .def(
          "write_csv", [](const DiagonalsResult& r, const std::string& path) { write_diagonals_csv(path, r.profiles); },
          "path"_a, "As `mtcal diagonals --out`: diagonal, position (mm), deviation (mm).");
  m.def("diagonals", &diagonals, "machine"_a, "box"_a, py::kw_only(), "points"_a = std::size_t{21}, "face"_a = true,
        "travel_check"_a = false,
        "ISO 230-6 body (and face) diagonals of a box (\"X=0:500,Y=0:400,Z=-300:0\" in mm, or a dict letter -> (lo, "
        "hi) internal) simulated on the model, as `mtcal diagonals`.");

  // ---------------------------------------------------------------- ISO 230-2
  py::class_<PositioningRuns>(m, "PositioningRuns", "Measured positions of one axis: targets, runs up and down.")
      .def(py::init(&make_runs), "targets"_a, "up"_a, "down"_a, py::kw_only(), "unit"_a = "mm", "source"_a = "input",
           "targets (m,), up and down (m, n): measured positions per target and run.")
      .def_readonly("source", &PositioningRuns::source)
      .def_readonly("unit", &PositioningRuns::unit)
      .def_readonly("target_unit", &PositioningRuns::target_unit, "Unit of the targets ('': the values' unit)")
      .def_readonly("deviations", &PositioningRuns::deviations,
                    "True: up and down hold deviations (measured - target) in unit, not measured positions")
      .def_readonly("metadata", &PositioningRuns::metadata,
                    "What the file says beside the runs, (key, value) in file order")
      .def_readonly("warnings", &PositioningRuns::warnings, "What the reader kept but did not use")
      .def_property_readonly("targets", [](const PositioningRuns& r) { return to_array(r.targets); })
      .def_property_readonly(
          "up", [](const PositioningRuns& r) { return runs_array(r.up); }, "(m, n) measured")
      .def_property_readonly(
          "down", [](const PositioningRuns& r) { return runs_array(r.down); }, "(m, n) measured");
  m.def(
      "read_positioning",
      [](const std::string& path, const std::string& format, const std::string& unit, const std::string& target_unit,
         double wrap) {
        if (!(wrap >= 0) || !std::isfinite(wrap)) throw py::value_error("wrap: expected a finite number >= 0");
        PositioningRuns runs = read_positioning_file(path, format, unit, target_unit);
        if (wrap > 0) runs = merge_wrapped_targets(runs, wrap);  // as iso230-2 --wrap
        return runs;
      },
      "path"_a, py::kw_only(), "format"_a = "auto", "unit"_a = "mm", "target_unit"_a = "", "wrap"_a = 0.0,
      "ISO 230-2 runs from a file: a table (target, run, direction, measured or deviation; values in unit "
      "unless the header says), the key=value .dat form or a Renishaw .rtl/.rta export (they say their "
      "units); format 'auto', 'csv', 'dat' or 'laser'. wrap: a rotary test's targets this far apart (e.g. 360) "
      "are one position of the axis, their runs pooled (iso230-2 --wrap; 0: none).");
  py::class_<PositioningEvaluation>(m, "PositioningEvaluation", "ISO 230-2 results (in the runs' unit).")
      .def_readonly("unit", &PositioningEvaluation::unit)
      .def_readonly("runs", &PositioningEvaluation::runs)
      .def_readonly("A", &PositioningEvaluation::A)
      .def_readonly("A_up", &PositioningEvaluation::A_up)
      .def_readonly("A_down", &PositioningEvaluation::A_down)
      .def_readonly("B", &PositioningEvaluation::B)
      .def_readonly("B_mean", &PositioningEvaluation::B_mean)
      .def_readonly("R", &PositioningEvaluation::R)
      .def_readonly("R_up", &PositioningEvaluation::R_up)
      .def_readonly("R_down", &PositioningEvaluation::R_down)
      .def_readonly("E", &PositioningEvaluation::E)
      .def_readonly("E_up", &PositioningEvaluation::E_up)
      .def_readonly("E_down", &PositioningEvaluation::E_down)
      .def_readonly("M", &PositioningEvaluation::M)
      .def_property_readonly(
          "table",
          [](const PositioningEvaluation& e) {
            py::dict d;
            auto col = [&](const char* name, double TargetEvaluation::*f) {
              std::vector<double> v;
              for (const auto& t : e.targets) v.push_back(t.*f);
              d[name] = to_array(v);
            };
            col("target", &TargetEvaluation::target);
            col("mean_up", &TargetEvaluation::mean_up);
            col("mean_down", &TargetEvaluation::mean_down);
            col("mean", &TargetEvaluation::mean);
            col("reversal", &TargetEvaluation::reversal);
            col("s_up", &TargetEvaluation::s_up);
            col("s_down", &TargetEvaluation::s_down);
            col("R_up", &TargetEvaluation::R_up);
            col("R_down", &TargetEvaluation::R_down);
            col("R", &TargetEvaluation::R);
            return d;
          },
          "Per target, name -> array: target mean_up mean_down mean reversal s_up s_down R_up R_down R")
      .def(
          "to_dict", [](const PositioningEvaluation& e) { return to_py(to_json(e)); },
          "As `mtcal iso230-2 --json` (docs/evaluations.md).");
  m.def(
      "iso230_2",
      [](py::handle targets_or_runs, py::handle up, py::handle down, const std::string& unit,
         const std::string& source) {
        if (py::isinstance<PositioningRuns>(targets_or_runs)) {
          if (!up.is_none() || !down.is_none()) throw py::value_error("up, down: not with PositioningRuns");
          return evaluate_positioning(targets_or_runs.cast<const PositioningRuns&>());
        }
        if (up.is_none() || down.is_none()) throw py::value_error("up, down: expected both with targets");
        return evaluate_positioning(make_runs(targets_or_runs, up, down, unit, source));
      },
      "runs"_a, "up"_a = py::none(), "down"_a = py::none(), py::kw_only(), "unit"_a = "mm", "source"_a = "input",
      R"(ISO 230-2 evaluation of linear positioning: A, B, R, E, M (with _up/_down) and per-target values.

runs: PositioningRuns (read_positioning), or the target positions (m,) with up and down
measured positions (m, n): target i, run j, in `unit`. Deviations x_ij = measured - target.
Returns PositioningEvaluation (values in the runs' unit). As `mtcal iso230-2`.)");

  // ---------------------------------------------------------------- ISO 230-4
  py::class_<BallbarTrace>(m, "BallbarTrace", "A ballbar trace: per sample direction, angle (rad) and bar length (mm).")
      .def(py::init(&make_trace), "directions"_a, "angles"_a, "radii"_a, py::kw_only(), "source"_a = "trace",
           "directions: 'cw'/'ccw' per sample; angles in rad (CCW from the plane's first axis); radii in mm.")
      .def_readonly("source", &BallbarTrace::source)
      .def_property_readonly("directions",
                             [](const BallbarTrace& t) {
                               std::vector<std::string> d;
                               for (const auto& p : t.points) d.emplace_back(direction_name(p.direction));
                               return d;
                             })
      .def_property_readonly(
          "angles",
          [](const BallbarTrace& t) {
            std::vector<double> v;
            for (const auto& p : t.points) v.push_back(p.angle);
            return to_array(v);
          },
          "rad")
      .def_property_readonly(
          "radii",
          [](const BallbarTrace& t) {
            std::vector<double> v;
            for (const auto& p : t.points) v.push_back(p.radius);
            return to_array(v);
          },
          "mm")
      .def("__len__", [](const BallbarTrace& t) { return t.points.size(); });
  m.def("read_ballbar_csv", &read_ballbar_csv, "path"_a, "A trace CSV direction,angle_deg,radius_mm.");
  m.def(
      "write_ballbar_csv", [](const std::string& path, const BallbarTrace& t) { write_ballbar_csv(path, t.points); },
      "path"_a, "trace"_a, "Writes a trace as CSV direction,angle_deg,radius_mm.");
  m.def(
      "predict_ballbar",
      [](const Machine& mm, const std::string& plane, py::handle centre, double radius, double step) {
        check_radius(radius);
        BallbarTrace t;
        t.source = "predicted";
        t.points = predict_ballbar(mm, plane, configuration(mm, centre, "centre"), radius, step);
        return t;
      },
      "machine"_a, "plane"_a, "centre"_a, py::kw_only(), "radius"_a, "step"_a = std::numbers::pi / 180,
      "The trace a ballbar would record on the model: circle of radius mm (required) in plane 'XY'/'YZ'/'ZX' about the "
      "centre configuration (internal units), both directions, one sample every step rad.");
  py::class_<CircularDeviation>(m, "CircularDeviation", "ISO 230-4 quantities of one direction's path (mm).")
      .def_readonly("points", &CircularDeviation::points)
      .def_readonly("G", &CircularDeviation::G)
      .def_readonly("G_minimum_zone", &CircularDeviation::G_minimum_zone)
      .def_property_readonly("centre",
                             [](const CircularDeviation& d) { return py::make_tuple(d.centre_x, d.centre_y); })
      .def_readonly("F_max", &CircularDeviation::F_max)
      .def_readonly("F_min", &CircularDeviation::F_min)
      .def_readonly("F_mean", &CircularDeviation::F_mean)
      .def("to_dict", [](const CircularDeviation& d) { return to_py(to_json(d)); });
  py::class_<TraceTerm>(m, "TraceTerm", "One term of the ballbar diagnosis.")
      .def_readonly("name", &TraceTerm::name)
      .def_readonly("unit", &TraceTerm::unit)
      .def_readonly("value", &TraceTerm::value)
      .def_readonly("uncertainty", &TraceTerm::uncertainty)
      .def_readonly("share", &TraceTerm::share);
  py::class_<BallbarResult>(m, "BallbarResult", "ISO 230-4 circular test results (mm) and the diagnosis.")
      .def_property_readonly("cw", [](const BallbarResult& r) { return r.evaluation.cw; })
      .def_property_readonly("ccw", [](const BallbarResult& r) { return r.evaluation.ccw; })
      .def_property_readonly("G_b", [](const BallbarResult& r) { return optional_number(r.evaluation.G_b); })
      .def_property_readonly("H", [](const BallbarResult& r) { return optional_number(r.evaluation.H); })
      .def_property_readonly("F_max", [](const BallbarResult& r) { return r.evaluation.F_max; })
      .def_property_readonly("F_min", [](const BallbarResult& r) { return r.evaluation.F_min; })
      .def_property_readonly(
          "diagnosis",
          [](const BallbarResult& r) -> py::object {
            if (!r.diagnosis) return py::none();
            return py::cast(r.diagnosis->terms);
          },
          "TraceTerms of the diagnostic model, or None")
      .def(
          "to_dict",
          [](const BallbarResult& r) { return to_py(to_json(r.evaluation, r.diagnosis, r.plane, r.radius, r.feed)); },
          "As `mtcal ballbar --json`.");
  m.def("ballbar", &ballbar, "trace"_a, py::kw_only(), "radius"_a, "plane"_a = "XY", "overshoot_start"_a = 0.0,
        "overshoot_stop"_a = 0.0, "direction"_a = py::none(), "feed"_a = 0.0, "diagnose"_a = true,
        R"(ISO 230-4 circular test of a BallbarTrace: G per direction (least-squares and minimum-zone
centres), G(b), H, F (mm); with both directions the diagnostic trace model. radius: nominal (mm),
required (the bar's length defines the test; the trace file does not state it);
overshoots in deg; direction 'cw'/'ccw' evaluates one only. As `mtcal ballbar`.)");

  // ---------------------------------------------------------------- method comparison
  py::class_<ComparisonData>(m, "ComparisonData", "A long table method,test,parameter,value with two methods.")
      .def_readonly("source", &ComparisonData::source)
      .def_readonly("methods", &ComparisonData::methods)
      .def_property_readonly("size", [](const ComparisonData& d) { return d.values.size(); });
  m.def("read_comparison_csv", &read_comparison_csv, "path"_a);
  m.def("parse_comparison_csv", &parse_comparison_csv, "text"_a, "source"_a = "<string>");
  py::class_<MethodComparison>(m, "MethodComparison")
      .def_readonly("methods", &MethodComparison::methods)
      .def(
          "to_dict", [](const MethodComparison& c) { return to_py(to_json(c)); }, "As `mtcal compare --json`.");
  m.def("compare_methods", &compare_methods, "data"_a,
        "Per parameter: both methods' mean and standard deviation, difference, overlap, correlation.");

  // ---------------------------------------------------------------- G-code and tool paths
  py::class_<GcodeProgram>(m, "GcodeProgram", "A G-code program read whole (read_gcode, parse_gcode).")
      .def_readonly("source", &GcodeProgram::source)
      .def_property_readonly(
          "moves", [](const GcodeProgram& p) { return p.moves.size(); }, "Blocks that move")
      .def_property_readonly("counts",
                             [](const GcodeProgram& p) {
                               py::dict d;
                               d["lines"] = p.counts.lines;
                               d["blocks"] = p.counts.blocks;
                               d["moves"] = p.counts.moves;
                               d["ignored_words"] = p.counts.ignored_words;
                               d["m_words"] = p.counts.m_words;
                               d["s_words"] = p.counts.s_words;
                               d["t_words"] = p.counts.t_words;
                               d["tool_changes"] = p.counts.tool_changes;
                               d["cycles"] = p.counts.cycles;
                               d["warnings"] = p.counts.warnings;
                               return d;
                             })
      .def_readonly("warnings", &GcodeProgram::warnings,
                    "Words read but not simulated: 'file:line: column c: word why' (the first 100)")
      .def_property_readonly(
          "end_points",
          [](const GcodeProgram& p) {
            std::vector<double> v;
            for (const auto& mv : p.moves) v.insert(v.end(), mv.end.begin(), mv.end.end());
            return to_array(v, 6);
          },
          "(moves, 6) end point of each move: X Y Z (mm) A B C (deg), program coordinates");
  m.def(
      "read_gcode",
      [](const std::string& path, const std::string& axes) {
        GcodeOptions o;
        o.axes = axes;
        return read_gcode(path, o);
      },
      "path"_a, py::kw_only(), "axes"_a = "XYZABC", "A G-code program (G0 G1 G2 G3, G17-G19, G20/G21, G90/G91).");
  m.def(
      "parse_gcode",
      [](const std::string& text, const std::string& source, const std::string& axes) {
        GcodeOptions o;
        o.axes = axes;
        return parse_gcode(text, source, o);
      },
      "text"_a, "source"_a = "<string>", py::kw_only(), "axes"_a = "XYZABC");
  py::class_<ToolpathResult>(m, "ToolpathResult", "Points along a program and the volumetric error at each.")
      .def(
          "_write_report",
          [](const ToolpathResult& r, const std::string& path, const std::string& command) {
            // The plots thin the points as the command's sampler does while the program streams.
            ToolpathPlotSampler sampler(r.machine.axes.size());
            sampler.add(r.points);
            write_toolpath_report(path, ErrorModel(r.machine), r.summary, sampler, r.report, {command, {}, "", ""});
          },
          "path"_a, "command"_a)
      .def_property_readonly(
          "lines", [](const ToolpathResult& r) { return r.points.line; }, "Source line of each point")
      .def_property_readonly(
          "s", [](const ToolpathResult& r) { return to_array(r.points.s); }, "Path length, mm")
      .def_property_readonly(
          "configs", [](const ToolpathResult& r) { return to_array(r.points.q, r.machine.axes.size()); },
          "(N, k) internal units")
      .def_property_readonly("directions",
                             [](const ToolpathResult& r) -> py::object {
                               if (r.points.dir.empty()) return py::none();
                               return to_int8_array(r.points.dir, r.machine.axes.size());
                             })
      .def_property_readonly(
          "errors", [](const ToolpathResult& r) { return to_array(r.points.error, 6); },
          "(N, 6) dx dy dz (mm) rx ry rz (rad)")
      .def(
          "write_csv",
          [](const ToolpathResult& r, const std::string& path) {
            ToolpathCsv file(path, r.machine);
            file.write(r.points);
            file.commit();
          },
          "path"_a, "The points as `mtcal toolpath --out` writes them.")
      .def(
          "to_dict",
          [](const ToolpathResult& r) {
            Json j = to_json(r.machine, r.summary);
            j["interpreter"] = r.interpreter;  // as `mtcal toolpath --json`
            return to_py(j);
          },
          "The summary as `mtcal toolpath --json`.");
  py::class_<CorrectedGcode>(m, "CorrectedGcode", "A G-code program corrected for the machine's errors.")
      .def_property_readonly(
          "text", [](const CorrectedGcode& c) { return c.corrected.text; }, "The corrected program")
      .def_property_readonly(
          "expanded", [](const CorrectedGcode& c) { return c.corrected.expanded; },
          "Every move written anew (cycles, offsets) instead of corrected in place")
      .def_property_readonly("warnings", [](const CorrectedGcode& c) { return c.result.warnings; })
      .def(
          "write",
          [](const CorrectedGcode& c, const std::string& path) { write_file_atomically(path, c.corrected.text); },
          "path"_a, "Writes the corrected program (complete or not at all), as --out.")
      .def(
          "to_dict",
          [](const CorrectedGcode& c, const std::string& out) {
            return to_py(to_json(c.machine, c.program, c.interpreter, c.result, c.corrected, c.seconds, out));
          },
          "out"_a = "",
          "As `mtcal compensate --gcode --json`: machine, program, interpreter, written, correction {moves, "
          "moves_corrected, subdivisions, ...}, rewrite {lines_in, lines_changed, lines_added}, seconds, out.");
  // The setup and the interpreter of a program file, as the commands' options of the same names.
  auto reading_of = [](std::string interpreter, std::optional<std::string> rs274, double rs274_timeout,
                       std::string tool_table, std::string tool_units, std::string parameters,
                       std::string parameter_units, py::object work_offsets, py::object g28, py::object g30) {
    return GcodeReading{std::move(interpreter), std::move(rs274), rs274_timeout, std::move(tool_table),
                        std::move(tool_units),  std::move(parameters), std::move(parameter_units),
                        std::move(work_offsets), std::move(g28), std::move(g30)};
  };
  const char* reading_doc = R"(
The program file is read as the command reads it: interpreter "auto" (mtcal's reader unless the
program needs LinuxCNC's), "mtcal" or "rs274" (--interpreter); rs274: LinuxCNC's interpreter, a
path or a name on PATH (--rs274; named, it must exist); rs274_timeout: seconds (--rs274-timeout);
tool_table: a LinuxCNC tool table (--tool-table), tool_units "mm" or "in" (--tool-units);
parameters: a LinuxCNC parameter file, .var (--parameters), parameter_units (--parameter-units);
work_offsets: {"G55": {"X": 100, "Y": 50}} (mm, deg; over the parameter file's, --work-offset);
g28, g30: the positions G28 and G30 return to, {"X": 0, ...} (--g28, --g30).)";
  m.def(
      "correct_gcode",
      [reading_of](const Machine& machine, const std::string& program, double max_deviation, bool linearise_arcs,
                   py::handle origin, int decimals, bool directions, bool orientation, bool travel_check,
                   std::string interpreter, std::optional<std::string> rs274, double rs274_timeout,
                   std::string tool_table, std::string tool_units, std::string parameters,
                   std::string parameter_units, py::object work_offsets, py::object g28, py::object g30) {
        return correct_gcode(machine, program, max_deviation, linearise_arcs, origin, decimals, directions,
                             orientation, travel_check,
                             reading_of(std::move(interpreter), std::move(rs274), rs274_timeout,
                                        std::move(tool_table), std::move(tool_units), std::move(parameters),
                                        std::move(parameter_units), std::move(work_offsets), std::move(g28),
                                        std::move(g30)));
      },
      "machine"_a, "program"_a, py::kw_only(), "max_deviation"_a = 0.001, "linearise_arcs"_a = false,
      "origin"_a = py::none(), "decimals"_a = 6, "directions"_a = true, "orientation"_a = true,
      "travel_check"_a = true, "interpreter"_a = "auto", "rs274"_a = py::none(), "rs274_timeout"_a = 300.0,
      "tool_table"_a = "", "tool_units"_a = "mm", "parameters"_a = "", "parameter_units"_a = "mm",
      "work_offsets"_a = py::none(), "g28"_a = py::none(), "g30"_a = py::none(),
      (std::string(R"(The corrected G-code program, as `mtcal compensate --gcode FILE --out OUT`
(docs/compensation-gcode.md): the commanded positions that put the actual tool on the programmed
path, moves cut until the tool point stays within max_deviation (mm) of it. Corrected in place when
each block is one move in program coordinates, else every move written anew (expanded). origin:
program zero in machine axis positions {"X": 100, ...} (mm, deg); decimals: digits written after the
point; directions=False: as --no-direction, orientation=False: as --no-orientation,
travel_check=False: as --no-travel-check. Returns CorrectedGcode: text, expanded, warnings,
write(path), to_dict(out).)") + reading_doc)
          .c_str());
  m.def(
      "toolpath",
      [reading_of](const Machine& machine, py::handle program, double step, double angle_step, bool skip_rapids,
                   py::handle origin, bool directions, bool travel_check, int threads, std::string interpreter,
                   std::optional<std::string> rs274, double rs274_timeout, std::string tool_table,
                   std::string tool_units, std::string parameters, std::string parameter_units,
                   py::object work_offsets, py::object g28, py::object g30) {
        return toolpath(machine, program, step, angle_step, skip_rapids, origin, directions, travel_check, threads,
                        reading_of(std::move(interpreter), std::move(rs274), rs274_timeout, std::move(tool_table),
                                   std::move(tool_units), std::move(parameters), std::move(parameter_units),
                                   std::move(work_offsets), std::move(g28), std::move(g30)));
      },
      "machine"_a, "program"_a, py::kw_only(), "step"_a = 0.5, "angle_step"_a = 0.5, "skip_rapids"_a = false,
      "origin"_a = py::none(), "directions"_a = true, "travel_check"_a = true, "threads"_a = 0,
      "interpreter"_a = "auto", "rs274"_a = py::none(), "rs274_timeout"_a = 300.0, "tool_table"_a = "",
      "tool_units"_a = "mm", "parameters"_a = "", "parameter_units"_a = "mm", "work_offsets"_a = py::none(),
      "g28"_a = py::none(), "g30"_a = py::none(),
      (std::string(R"(Tool-path simulation: the volumetric error along a G-code program (a path, or a
GcodeProgram read already), points at most step mm / angle_step deg apart. origin: program zero in
machine axis positions {"X": 100, ...} (mm, deg). As `mtcal toolpath`; skip_rapids: --skip-rapids,
directions=False: --no-direction, travel_check=False: --no-travel-check.)") + reading_doc)
          .c_str());
}

}  // namespace mtcal::python
