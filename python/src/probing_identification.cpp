// Python bindings of probing and identification: sphere contacts, rotary-axis location, probing plans, simulation,
// identification with its covariance, identifiability; their files.
#include <chrono>
#include <cmath>
#include <filesystem>
#include <numbers>

#include <Eigen/Core>

#include "common.hpp"
#include "mtcal/identification/fit_check.hpp"
#include "mtcal/identification/identification.hpp"
#include "mtcal/evaluation/error_stream.hpp"
#include "mtcal/identification/probing_plan.hpp"
#include "mtcal/io/system/files.hpp"
#include "mtcal/io/json/identification_json.hpp"
#include "mtcal/io/model/identified_parameters_file.hpp"
#include "mtcal/io/instruments/probe_log.hpp"
#include "mtcal/io/instruments/probing_files.hpp"
#include "mtcal/io/json/probing_json.hpp"
#include "mtcal/io/instruments/probing_plan_file.hpp"
#include "mtcal/model/joints.hpp"
#include "mtcal/probing/rotary_axis.hpp"
#include "mtcal/probing/rotary_probing.hpp"
#include "mtcal/probing/sphere_probing.hpp"
#include "mtcal/report/identification.hpp"
#include "mtcal/report/report.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal::python {

using namespace pybind11::literals;

namespace {

using Clock = std::chrono::steady_clock;

py::array_t<double> matrix_array(const Eigen::MatrixXd& a) {
  py::array_t<double> out = new_array({static_cast<py::ssize_t>(a.rows()), static_cast<py::ssize_t>(a.cols())});
  double* o = out.mutable_data();
  for (Eigen::Index r = 0; r < a.rows(); ++r)
    for (Eigen::Index c = 0; c < a.cols(); ++c) o[r * a.cols() + c] = a(r, c);
  return out;
}

py::array_t<double> points_array(const std::vector<Point3>& p) {
  std::vector<double> v;
  for (const auto& x : p) v.insert(v.end(), x.data(), x.data() + 3);
  if (v.empty()) return new_array({0, 3});
  return to_array(v, 3);
}

std::vector<Point3> points_of(py::handle obj, const char* name, std::size_t rows) {
  const Rows r = as_rows(obj, name, 3, false);
  if (r.rows != rows)
    throw py::value_error(std::string(name) + ": expected " + std::to_string(rows) + " rows, found " +
                          std::to_string(r.rows));
  std::vector<Point3> out(r.rows);
  for (std::size_t i = 0; i < r.rows; ++i) out[i] = Point3(r.data[3 * i], r.data[3 * i + 1], r.data[3 * i + 2]);
  return out;
}

char axis_letter(const std::string& s, const char* name) {
  if (s.size() != 1 || s[0] < 'A' || s[0] > 'C')
    throw py::value_error(std::string(name) + ": expected A, B or C, found '" + s + "'");
  return s[0];
}

// ---------------------------------------------------------------- contacts and centres

ContactSet make_contacts(py::handle angles_deg, py::handle points, py::handle approaches, const std::string& axis,
                         const std::string& source) {
  ContactSet s;
  s.source = source;
  s.axis = axis_letter(axis, "axis");
  const auto a = as_std_vector(angles_deg, "angles_deg");
  const auto p = points_of(points, "points", a.size());
  std::vector<Point3> ap(a.size(), -Point3::UnitZ());
  if (!approaches.is_none()) ap = points_of(approaches, "approaches", a.size());
  for (std::size_t i = 0; i < a.size(); ++i) s.contacts.push_back({a[i], {p[i], ap[i].normalized()}, 0});
  return s;
}

IndexedCentres make_centres(py::handle angles, py::handle centres, const std::string& source) {
  IndexedCentres c;
  c.source = source;
  const auto a = as_std_vector(angles, "angles");
  const auto p = points_of(centres, "centres", a.size());
  for (std::size_t i = 0; i < a.size(); ++i) c.centres.push_back({a[i], p[i]});
  return c;
}

RotaryAxisResult rotary_axis(py::handle data, const std::string& axis, const Machine* machine,
                             std::optional<double> sphere_diameter, double stylus_diameter, double max_rms,
                             const std::string& method, double reject_sigma, int bins, int threads,
                             py::handle frame) {
  if (method != "both" && method != "triples" && method != "lsq")
    throw py::value_error("method: expected 'both', 'triples' or 'lsq', found '" + method + "'");
  if (reject_sigma != 0 && reject_sigma < 1)
    throw py::value_error("reject_sigma: expected 0 (no rejection) or at least 1, found " +
                          std::to_string(reject_sigma));
  const char letter = axis_letter(axis, "axis");
  NominalRotaryAxis nominal =
      machine ? NominalRotaryAxis::from(machine->axis(letter)) : NominalRotaryAxis::by_letter(letter);
  IndexedCentres centres;
  if (py::isinstance<ContactSet>(data)) {
    if (!sphere_diameter || !(*sphere_diameter > 0))
      throw py::value_error("sphere_diameter: expected the sphere diameter (mm) with contacts");
    const auto& contacts = data.cast<const ContactSet&>();
    if (contacts.axis != letter)
      throw py::value_error(std::string("axis: the contacts are of axis ") + contacts.axis + ", not " + letter);
    centres = centres_from_contacts(contacts, SphereProbing{*sphere_diameter, stylus_diameter, max_rms});
  } else if (py::isinstance<IndexedCentres>(data)) {
    centres = data.cast<IndexedCentres>();
  } else {
    throw py::type_error("data: expected a ContactSet or IndexedCentres");
  }
  if (!frame.is_none()) {
    // The instrument's axes in the machine's (rotary-axis --frame): rx, ry, rz in deg (Rz Ry Rx), and tx, ty, tz in mm.
    const auto v = as_std_vector(frame, "frame");
    if (v.size() != 3 && v.size() != 6)
      throw py::value_error("frame: expected (rx, ry, rz) in deg or (rx, ry, rz, tx, ty, tz) in deg and mm, found " +
                            std::to_string(v.size()) + " values");
    const double d = std::numbers::pi / 180;
    apply_frame(centres, frame_from_angles(v[0] * d, v[1] * d, v[2] * d,
                                           v.size() == 6 ? Point3(v[3], v[4], v[5]) : Point3(Point3::Zero())));
  }
  RotaryAxisOptions options{method != "lsq", method != "triples", TriplesOptions{reject_sigma, bins, threads}};
  // The module has no time limit option (the CLI checks the triples' time against --max-time):
  // 1000 centres (1.7e8 triples, about 20 s on one thread) is the bound here.
  constexpr std::size_t kMaxPythonTriplesCentres = 1000;
  if (options.triples && centres.centres.size() > kMaxPythonTriplesCentres)
    throw InputError({centres.source, 0, ""}, std::to_string(centres.centres.size()) +
                                                  " indexations make too many triples for method triples/both (at "
                                                  "most " +
                                                  std::to_string(kMaxPythonTriplesCentres) + "); use method 'lsq'");
  LongCall release;  // without the GIL, stoppable with Ctrl-C
  return locate_rotary_axis(nominal, std::move(centres), options);
}

py::dict estimate_dict(const RotaryEstimate& e, char letter, const std::array<double, kRotaryQuantities>& v) {
  const auto names = rotary_quantity_names(letter);
  py::dict d;
  for (std::size_t q = 0; q < kRotaryQuantities; ++q) d[py::str(names[q])] = v[q];
  (void)e;
  return d;
}

struct SimulatedContacts {
  Axis axis;
  std::vector<ProbedIndexation> probed;
};

ContactSet contact_set(const SimulatedContacts& s) {
  ContactSet c;
  c.source = "simulated";
  c.axis = s.axis.letter;
  for (const auto& p : s.probed)
    for (const auto& ct : p.contacts) c.contacts.push_back({to_user_units(s.axis, p.angle), ct, 0});
  return c;
}

// ---------------------------------------------------------------- identification

std::vector<ScaleBar> scale_bars_of(py::handle obj) {
  std::vector<ScaleBar> out;
  if (obj.is_none()) return out;
  for (auto item : obj.cast<py::sequence>()) {
    if (py::isinstance<py::str>(item)) {
      out.push_back(parse_scale_bar(item.cast<std::string>(), "scale_bars"));
    } else {
      const auto t = item.cast<py::sequence>();
      if (t.size() != 3) throw py::value_error("scale_bars: expected 'A:B:LENGTH' or (ball_a, ball_b, length)");
      out.push_back({py::str(t[0]), py::str(t[1]), t[2].cast<double>(), "scale_bars"});
    }
  }
  return out;
}

IdentificationOptions identification_options(py::handle estimate, py::handle scale_bars, bool pretravel, double sigma,
                                             double rank_tolerance) {
  IdentificationOptions o;
  if (!estimate.is_none()) {
    if (py::isinstance<py::str>(estimate))
      o.estimate = {estimate.cast<std::string>()};
    else
      o.estimate = estimate.cast<std::vector<std::string>>();
  }
  o.estimate_source = "estimate";
  o.scale_bars = scale_bars_of(scale_bars);
  o.estimate_pretravel = pretravel;
  if (!(sigma > 0) || !std::isfinite(sigma)) throw py::value_error("sigma: expected a standard deviation > 0 in mm");
  o.sigma_ball = o.sigma_facet = o.sigma_scale_bar = o.sigma_ballbar = o.sigma_laser = sigma;
  o.rank_tolerance = rank_tolerance;
  return o;
}

struct Identified {
  Machine prior;
  IdentificationRun run;
  std::string measurements;  // the measurement file read (hashed into a report), or "" for a plan made in memory
};

Identified identify(const Machine& prior, const ProbingPlan& meas, py::handle estimate, py::handle scale_bars,
                    bool pretravel, double sigma, const std::string& loss, double rank_tolerance,
                    std::size_t monte_carlo, std::uint64_t seed, py::handle workspace, const Machine* truth,
                    int threads, bool require_fit) {
  IdentificationOptions opt = identification_options(estimate, scale_bars, pretravel, sigma, rank_tolerance);
  if (loss == "huber")
    opt.loss = IdentificationOptions::Loss::Huber;
  else if (loss == "cauchy")
    opt.loss = IdentificationOptions::Loss::Cauchy;
  else if (loss != "none")
    throw py::value_error("loss: expected 'none', 'huber' or 'cauchy', found '" + loss + "'");
  AssessmentOptions ao;
  if (!workspace.is_none()) {
    ao.workspace = grid_values(prior, workspace, "workspace");
    check_grid(prior, ao.workspace, "workspace", false, 2'000'000);
  }
  if (truth && ao.workspace.empty())
    throw InputError({"truth", 0, ""}, "truth needs workspace (the grid over which the models are compared)");
  ao.monte_carlo_runs = monte_carlo;
  ao.seed = seed;
  ao.threads = threads;
  ao.truth = truth;
  std::error_code ec;
  Identified r{prior, [&] {
                 LongCall release;  // without the GIL, stoppable with Ctrl-C
                 return identify_and_assess(prior, meas, opt, ao);
               }(),
               std::filesystem::is_regular_file(meas.source, ec) ? meas.source : std::string()};
  // As the command: a poor fit is a warning, or with require_fit (--require-fit) an error.
  const FitCheck fit = check_fit(r.run.result);
  if (fit.poor) {
    const std::string why = poor_fit_message(fit);
    if (require_fit) throw InputError({meas.source, 0, ""}, why + "; nothing written (require_fit)");
    py::module_::import("warnings").attr("warn")(why, py::reinterpret_borrow<py::object>(PyExc_UserWarning), 2);
  }
  return r;
}

struct Subsets {
  SubsetAnalysis analysis;
  SubsetOptions options;
  double seconds = 0;
};

py::object identifiability(const Machine& m, const ProbingPlan& plan, py::handle estimate, py::handle candidates,
                           std::size_t choose, py::handle always, py::handle scale_bars, bool pretravel, double sigma,
                           double rank_tolerance, std::size_t list, const std::string& sort, int threads) {
  const IdentificationOptions opt = identification_options(estimate, scale_bars, pretravel, sigma, rank_tolerance);
  if (choose == 0) {
    if (opt.estimate.empty()) throw py::value_error("estimate: expected names, or candidates with choose");
    Identifiability id;
    {
      LongCall release;  // without the GIL, stoppable with Ctrl-C
      id = mtcal::identifiability(m, plan, opt);
    }
    return py::cast(std::move(id));
  }
  if (candidates.is_none()) throw py::value_error("candidates: choose needs candidates");
  if (sort != "condition" && sort != "residue")
    throw py::value_error("sort: expected 'condition' or 'residue', found '" + sort + "'");
  Subsets s;
  s.options.candidates = candidates.cast<std::vector<std::string>>();
  if (!always.is_none()) s.options.always = always.cast<std::vector<std::string>>();
  s.options.choose = choose;
  s.options.threads = threads;
  s.options.rank_tolerance = std::max(rank_tolerance, 1e-7);  // the normal matrix resolves no finer (as the CLI)
  s.options.keep = list;
  s.options.by_residue = sort == "residue";
  s.options.candidates_source = "candidates";
  s.options.always_source = "always";
  s.options.choose_source = "choose";
  s.options.by_residue_source = "sort";
  s.options.rank_tolerance_source = "rank_tolerance";
  {
    LongCall release;  // without the GIL, stoppable with Ctrl-C
    const auto t0 = Clock::now();
    s.analysis = full_rank_subsets(m, plan, s.options, opt);
    s.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  }
  return py::cast(std::move(s));
}

py::dict artefact_dict(const std::vector<ProbeFeature>& features, const ArtefactState& a) {
  return to_py(artefact_json(features, a)).cast<py::dict>();
}

}  // namespace

void bind_probing_identification(py::module_& m) {
  // ---------------------------------------------------------------- rotary axis
  py::class_<ContactSet>(m, "ContactSet", "Touch-probe contacts at indexations of a rotary axis.")
      .def(py::init(&make_contacts), "angles_deg"_a, "points"_a, "approaches"_a = py::none(), py::kw_only(),
           "axis"_a = "C", "source"_a = "contacts",
           "angles_deg (n,): the axis's angle per contact (deg); points (n, 3): recorded stylus-tip centres "
           "(mm); approaches (n, 3): directions of probe motion (default -z).")
      .def_readonly("source", &ContactSet::source)
      .def_property_readonly("axis", [](const ContactSet& s) { return std::string(1, s.axis); })
      .def_property_readonly("angles_deg",
                             [](const ContactSet& s) {
                               std::vector<double> v;
                               for (const auto& c : s.contacts) v.push_back(c.angle_deg);
                               return to_array(v);
                             })
      .def_property_readonly("points",
                             [](const ContactSet& s) {
                               std::vector<Point3> v;
                               for (const auto& c : s.contacts) v.push_back(c.contact.point);
                               return points_array(v);
                             })
      .def_property_readonly("approaches",
                             [](const ContactSet& s) {
                               std::vector<Point3> v;
                               for (const auto& c : s.contacts) v.push_back(c.contact.approach);
                               return points_array(v);
                             })
      .def("__len__", [](const ContactSet& s) { return s.contacts.size(); });
  py::class_<IndexedCentres>(m, "IndexedCentres", "Sphere centres per indexation (angles in rad, centres in mm).")
      .def(py::init(&make_centres), "angles"_a, "centres"_a, py::kw_only(), "source"_a = "centres")
      .def_readonly("source", &IndexedCentres::source)
      .def_readonly("method", &IndexedCentres::method, "'five-point', 'least-squares', 'mixed' or 'given'")
      .def_property_readonly("angles",
                             [](const IndexedCentres& c) {
                               std::vector<double> v;
                               for (const auto& x : c.centres) v.push_back(x.angle);
                               return to_array(v);
                             })
      .def_property_readonly("centres",
                             [](const IndexedCentres& c) {
                               std::vector<Point3> v;
                               for (const auto& x : c.centres) v.push_back(x.centre);
                               return points_array(v);
                             })
      .def("__len__", [](const IndexedCentres& c) { return c.centres.size(); });
  m.def(
      "read_contacts_csv",
      [](const std::string& path, const std::string& axis) {
        return read_contacts_csv(path, axis_letter(axis, "axis"));
      },
      "path"_a, "axis"_a, "Contacts CSV: the axis's angle (deg, column named by its letter), x,y,z, approach_x..z.");
  m.def(
      "read_contacts_log",
      [](const Machine& machine, const std::string& path, const std::string& axis, const std::string& dialect) {
        const char letter = axis_letter(axis, "axis");
        ProbeLogFormat format = ProbeLogFormat::LinuxCNC;
        if (dialect == "iso")
          format = ProbeLogFormat::IsoCsv;
        else if (dialect != "linuxcnc")
          throw py::value_error("dialect: expected 'linuxcnc' or 'iso', found '" + dialect + "'");
        std::vector<LoggedAxisValues> log;
        for (auto& c : read_probe_log(machine, path, format)) log.push_back({std::move(c.q), c.line});
        return contacts_from_log(machine, letter, log, path);
      },
      "machine"_a, "path"_a, "axis"_a, py::kw_only(), "dialect"_a = "linuxcnc",
      "Contacts of a probe log through the machine's kinematics, as `mtcal rotary-axis --contacts LOG "
      "--contacts-dialect linuxcnc|iso --machine M`: a PROBEOPEN log (X Y Z A B C U V W a line, dialect "
      "'linuxcnc') or the #5061 CSV of mtcal probe-log (dialect 'iso').");
  m.def(
      "read_centres_csv",
      [](const std::string& path, const std::string& axis) {
        return read_centres_csv(path, axis_letter(axis, "axis"));
      },
      "path"_a, "axis"_a, "Centres CSV: the axis's angle (deg), x,y,z (mm).");
  m.def(
      "centres_from_contacts",
      [](const ContactSet& c, double sphere_diameter, double stylus_diameter, double max_rms) {
        return centres_from_contacts(c, SphereProbing{sphere_diameter, stylus_diameter, max_rms});
      },
      "contacts"_a, py::kw_only(), "sphere_diameter"_a, "stylus_diameter"_a = 0.0, "max_rms"_a = 0.01,
      "One sphere fit per indexation (five-point protocol or least squares), diameters in mm.");

  py::class_<RotaryEstimate>(m, "RotaryEstimate",
                             "Location errors of a rotary axis by one estimator (mm and rad), with uncertainties.")
      .def_property_readonly(
          "value", [](const RotaryEstimate& e) { return to_array(e.value); },
          "The six quantities: 2 position errors (mm), 2 orientation errors (rad), radius (mm), tilt (rad)")
      .def_property_readonly(
          "uncertainty", [](const RotaryEstimate& e) { return to_array(e.uncertainty); },
          "Standard uncertainties, same order")
      .def_property_readonly("spread", [](const RotaryEstimate& e) { return to_array(e.spread); })
      .def_property_readonly("axis_point", [](const RotaryEstimate& e) { return to_array(e.axis_point); })
      .def_property_readonly("axis_direction", [](const RotaryEstimate& e) { return to_array(e.axis_direction); });
  py::class_<TriplesEstimate, RotaryEstimate>(m, "TriplesEstimate")
      .def_readonly("triples", &TriplesEstimate::triples)
      .def_readonly("degenerate", &TriplesEstimate::degenerate)
      .def_property_readonly("rejected_share", [](const TriplesEstimate& e) { return to_array(e.rejected_share); });
  py::class_<LeastSquaresEstimate, RotaryEstimate>(m, "LeastSquaresEstimate");
  py::class_<RotaryAxisResult>(m, "RotaryAxisResult", "Rotary-axis location errors (ISO 230-7) from sphere centres.")
      .def_property_readonly("axis", [](const RotaryAxisResult& r) { return std::string(1, r.axis.letter); })
      .def_property_readonly(
          "names",
          [](const RotaryAxisResult& r) {
            const auto n = rotary_quantity_names(r.axis.letter);
            return std::vector<std::string>(n.begin(), n.end());
          },
          "Names of the six quantities, e.g. EX0C EY0C EA0C EB0C radius tilt")
      .def_readonly("centres", &RotaryAxisResult::centres)
      .def_readonly("triples", &RotaryAxisResult::triples)
      .def_readonly("least_squares", &RotaryAxisResult::least_squares)
      .def_property_readonly("best", &RotaryAxisResult::best, py::return_value_policy::copy,
                             "The least-squares estimate when there is one, else the triples'")
      .def_property_readonly(
          "values", [](const RotaryAxisResult& r) { return estimate_dict(r.best(), r.axis.letter, r.best().value); },
          "best(): name -> value (mm, rad)")
      .def_property_readonly(
          "uncertainties",
          [](const RotaryAxisResult& r) -> py::object {
            if (!r.uncertainty_known()) return py::none();
            return estimate_dict(r.best(), r.axis.letter, r.best().uncertainty);
          },
          "best(): name -> standard uncertainty; None with 3 centres (no redundancy)")
      .def_property_readonly("tilt", &RotaryAxisResult::tilt, "rad")
      .def(
          "to_dict", [](const RotaryAxisResult& r) { return to_py(to_json(r)); }, "As `mtcal rotary-axis --json`.")
      .def("parameters_yaml", &rotary_parameters_yaml, "The location errors as a parameter file (mtcal_parameters: 1).")
      .def(
          "write_parameters",
          [](const RotaryAxisResult& r, const std::string& path) { write_rotary_parameters(path, r); }, "path"_a,
          "Writes parameters_yaml() to path (Machine.with_parameter_file reads it).");
  m.def(
      "rotary_axis",
      [](py::handle data, const std::string& axis, const Machine* machine, std::optional<double> sphere_diameter,
         double stylus_diameter, double max_rms, const std::string& method, double reject_sigma, int bins,
         int threads, py::handle frame) {
        return rotary_axis(data, axis, machine, sphere_diameter, stylus_diameter, max_rms, method, reject_sigma, bins,
                           threads, frame);
      },
      "data"_a, py::kw_only(), "axis"_a = "C", "machine"_a = nullptr, "sphere_diameter"_a = py::none(),
      "stylus_diameter"_a = 0.0, "max_rms"_a = 0.01, "method"_a = "both", "reject_sigma"_a = 2.0, "bins"_a = 40,
      "threads"_a = 0, "frame"_a = py::none(),
      R"(Location errors of rotary axis `axis` from a sphere probed at many indexations (ISO 230-7):
data is a ContactSet (needs sphere_diameter, stylus_diameter in mm: one sphere fit per indexation)
or IndexedCentres. machine gives the axis's nominal line (default: through the origin along its
letter's axis). method 'both', 'triples' (Cubas & Yeh 2022) or 'lsq'. frame: the instrument's axes
in the machine's, (rx, ry, rz) deg or (rx, ry, rz, tx, ty, tz) deg and mm (machine = R instrument +
t, R = Rz Ry Rx), applied to the centres (--frame). As `mtcal rotary-axis`.)");
  py::class_<SimulatedContacts>(m, "SimulatedContacts", "Contacts of simulated probing (simulate_sphere_probing).")
      .def_property_readonly("contacts", &contact_set, "As a ContactSet")
      .def(
          "csv", [](const SimulatedContacts& s) { return contacts_csv(s.axis, s.probed); },
          "The contacts CSV that read_contacts_csv reads")
      .def(
          "write_csv",
          [](const SimulatedContacts& s, const std::string& path) { write_contacts_csv(path, s.axis, s.probed); },
          "path"_a);
  m.def(
      "simulate_sphere_probing",
      [](const Machine& mm, const std::string& axis, py::handle angles, py::handle held, py::handle sphere,
         double sphere_diameter, double stylus_diameter, double noise, double trigger_bias, std::uint64_t seed) {
        ProbingSimulation sim;
        sim.axis = axis_letter(axis, "axis");
        const auto k = mm.axis_index(sim.axis);
        if (!k) throw InputError({"axis", 0, ""}, "axis '" + axis + "' is not in topology " + mm.topology.chain);
        sim.angles = as_std_vector(angles, "angles");
        sim.held = held.is_none() ? std::vector<double>(mm.axes.size(), 0.0) : configuration(mm, held, "held");
        const auto c = as_std_vector(sphere, "sphere", 3);
        sim.sphere = Point3(c[0], c[1], c[2]);
        if (!(sphere_diameter > 0) || !(stylus_diameter >= 0) || !(noise >= 0) || !std::isfinite(trigger_bias))
          throw py::value_error("expected a sphere diameter > 0, a stylus diameter >= 0 and a noise >= 0");
        sim.probing = {sphere_diameter, stylus_diameter, 0.01};
        sim.noise = noise;
        sim.trigger_bias = trigger_bias;
        sim.seed = seed;
        return SimulatedContacts{mm.axes[*k], simulate_probing(mm, sim)};
      },
      "machine"_a, py::kw_only(), "axis"_a = "C", "angles"_a, "held"_a = py::none(),
      "sphere"_a = std::vector<double>{150, 0, 50}, "sphere_diameter"_a = 30.0, "stylus_diameter"_a = 6.0,
      "noise"_a = 0.0, "trigger_bias"_a = 0.0, "seed"_a = std::uint64_t{1},
      "Simulated 5-point probing of a sphere at indexations `angles` (rad) of a rotary axis on the model, "
      "noise (mm, per coordinate) and trigger bias (mm). As `mtcal probe-sim`.");

  // ---------------------------------------------------------------- probing plans
  py::class_<ProbeFeature>(m, "ProbeFeature", "An artefact feature: a ball or a facet (workpiece frame, mm).")
      .def_readonly("id", &ProbeFeature::id)
      .def_property_readonly("kind",
                             [](const ProbeFeature& f) { return feature_kind_name(f.kind); })
      .def_property_readonly("position", [](const ProbeFeature& f) { return to_array(f.position); })
      .def_property_readonly("normal", [](const ProbeFeature& f) { return to_array(f.normal); });
  py::class_<ProbingPlan>(m, "ProbingPlan", "A probing plan or measurement (balls and facets at indexations).")
      .def_readonly("source", &ProbingPlan::source)
      .def_readonly("measured", &ProbingPlan::measured, "True when the records hold readings")
      .def_readonly("features", &ProbingPlan::features)
      .def_property_readonly("size", [](const ProbingPlan& p) { return p.records.size(); })
      .def("__len__", [](const ProbingPlan& p) { return p.records.size(); })
      .def_property_readonly("residual_count", &ProbingPlan::residual_count)
      .def_property_readonly(
          "configs",
          [](const ProbingPlan& p) {
            std::vector<double> v;
            std::size_t k = p.records.empty() ? 0 : p.records[0].q.size();
            for (const auto& r : p.records) v.insert(v.end(), r.q.begin(), r.q.end());
            return k ? to_array(v, k) : new_array({0, 0});
          },
          "(R, k) joint values per record, internal units; the linear ones are readings or targets")
      .def_property_readonly("feature_index",
                             [](const ProbingPlan& p) {
                               std::vector<std::size_t> v;
                               for (const auto& r : p.records) v.push_back(r.feature);
                               return v;
                             })
      .def_property_readonly("indexation", [](const ProbingPlan& p) {
        std::vector<int> v;
        for (const auto& r : p.records) v.push_back(r.indexation);
        return v;
      });
  m.def("read_probing_plan", &read_probing_csv, "machine"_a, "path"_a,
        "A plan or measurement CSV (docs/identification.md); InputError with file, line and column.");
  m.def("parse_probing_plan", &parse_probing_csv, "machine"_a, "text"_a, "source"_a = "<string>");
  m.def("probing_csv", &probing_csv, "machine"_a, "plan"_a, "comment"_a = "", "The plan's CSV text.");
  m.def("write_probing_csv", &write_probing_csv, "path"_a, "machine"_a, "plan"_a, "comment"_a = "");

  py::class_<Simulation>(m, "Simulation", "What a virtual machine reads for a plan (simulate).")
      .def_readonly("measurements", &Simulation::measurements)
      .def_property_readonly(
          "truth", [](const Simulation& s) { return artefact_dict(s.measurements.features, s.truth); },
          "The artefact's true state: {'balls': {id: [x, y, z]}, 'facets': {id: offset}}");
  struct SimulationResult {
    Simulation sim;
    double noise, artefact_error;
    std::uint64_t seed;
  };
  py::class_<SimulationResult>(m, "SimulationResult")
      .def_property_readonly("measurements", [](const SimulationResult& r) { return r.sim.measurements; })
      .def_property_readonly("truth",
                             [](const SimulationResult& r) {
                               return artefact_dict(r.sim.measurements.features, r.sim.truth);
                             })
      .def(
          "to_dict",
          [](const SimulationResult& r) {
            return to_py(to_json(r.sim, r.noise * 1e3, r.artefact_error * 1e3, r.seed, ""));
          },
          "As `mtcal simulate --json`.");
  m.def(
      "simulate",
      [](const Machine& mm, const ProbingPlan& plan, double noise, double artefact_error, std::uint64_t seed,
         py::handle scale_bars) {
        SimulationOptions so;
        so.noise = noise;
        so.artefact_error = artefact_error;
        so.seed = seed;
        so.scale_bars = scale_bars_of(scale_bars);
        if (!(noise >= 0) || !(artefact_error >= 0)) throw py::value_error("noise, artefact_error: expected >= 0 (mm)");
        LongCall release;  // without the GIL, stoppable with Ctrl-C
        return SimulationResult{simulate_probing(mm, plan, so), noise, artefact_error, seed};
      },
      "machine"_a, "plan"_a, py::kw_only(), "noise"_a = 0.0, "artefact_error"_a = 0.0, "seed"_a = std::uint64_t{1},
      "scale_bars"_a = py::none(),
      R"(Virtual machine (Viprey 2015 fig. 4): the readings `machine` gives for a probing plan, with
Gaussian noise (mm per reading) and an uncalibrated artefact (artefact_error, mm). scale_bars:
'A:B:LENGTH' strings or (ball_a, ball_b, length). As `mtcal simulate`.)");

  py::class_<Identifiability>(m, "Identifiability", "Rank and conditioning of the scaled Jacobian of a plan.")
      .def_readonly("columns", &Identifiability::columns)
      .def_readonly("rank", &Identifiability::rank)
      .def_property_readonly("singular_values", [](const Identifiability& i) { return to_array(i.singular_values); })
      .def_readonly("condition", &Identifiability::condition)
      .def_readonly("condition_identifiable", &Identifiability::condition_identifiable)
      .def_readonly("identifiable", &Identifiability::identifiable)
      .def_readonly("unidentifiable", &Identifiability::unidentifiable)
      .def_readonly("null_directions", &Identifiability::null_directions)
      .def(
          "to_dict", [](const Identifiability& i) { return to_py(to_json(i)); }, "As `mtcal identifiability --json`.");
  py::class_<Subsets>(m, "SubsetAnalysis", "Every full-rank K-subset of candidate parameters (Viprey 2015).")
      .def_property_readonly("examined", [](const Subsets& s) { return s.analysis.examined; })
      .def_property_readonly("full_rank", [](const Subsets& s) { return s.analysis.full_rank; })
      .def_property_readonly(
          "subsets",
          [](const Subsets& s) {
            py::list l;
            for (const auto& x : s.analysis.subsets) {
              std::vector<std::string> names;
              for (auto i : x.members) names.push_back(s.analysis.candidates[i]);
              l.append(py::make_tuple(names, x.condition, x.residue));
            }
            return l;
          },
          "(parameters, condition, residue) best first")
      .def(
          "to_dict", [](const Subsets& s) { return to_py(to_json(s.analysis, s.options, s.seconds)); },
          "As `mtcal identifiability --choose K --json`.");
  m.def("identifiability", &identifiability, "machine"_a, "plan"_a, "estimate"_a = py::none(), py::kw_only(),
        "candidates"_a = py::none(), "choose"_a = std::size_t{0}, "always"_a = py::none(), "scale_bars"_a = py::none(),
        "pretravel"_a = false, "sigma"_a = 1e-3, "rank_tolerance"_a = 1e-8, "list"_a = std::size_t{20},
        "sort"_a = "condition", "threads"_a = 0,
        R"(What a probing plan can identify: rank, singular values, unidentifiable combinations of
`estimate` (Identifiability); or with candidates and choose=K every full-rank K-subset
(SubsetAnalysis). As `mtcal identifiability`.)");

  py::class_<Identified>(m, "IdentificationRun", "An identification with its assessment (identify).")
      .def(
          "_write_report",
          [](const Identified& r, const std::string& path, const std::string& command) {
            identification_report(r.prior, r.run, {{}, r.measurements, "", ""}, command).write(path);
          },
          "path"_a, "command"_a)
      .def_property_readonly("converged", [](const Identified& r) { return r.run.result.converged; })
      .def_property_readonly("iterations", [](const Identified& r) { return r.run.result.iterations; })
      .def_property_readonly("termination", [](const Identified& r) { return r.run.result.termination; })
      .def_property_readonly("sigma0", [](const Identified& r) { return r.run.result.sigma0; })
      .def_property_readonly(
          "names",
          [](const Identified& r) {
            std::vector<std::string> v;
            for (const auto& p : r.run.result.parameters) v.push_back(p.name);
            return v;
          },
          "Estimated parameters, in the order of values, uncertainties and covariance")
      .def_property_readonly("units",
                             [](const Identified& r) {
                               std::vector<std::string> v;
                               for (const auto& p : r.run.result.parameters) v.push_back(p.unit);
                               return v;
                             })
      .def_property_readonly("values",
                             [](const Identified& r) {
                               std::vector<double> v;
                               for (const auto& p : r.run.result.parameters) v.push_back(p.value);
                               return to_array(v);
                             })
      .def_property_readonly(
          "uncertainties",
          [](const Identified& r) {
            std::vector<double> v;
            for (const auto& p : r.run.result.parameters) v.push_back(p.u);
            return to_array(v);
          },
          "Standard uncertainties (root of the covariance's diagonal); NaN if rank deficient")
      .def_property_readonly(
          "parameters",
          [](const Identified& r) {
            py::dict d;
            for (const auto& p : r.run.result.parameters) d[py::str(p.name)] = py::make_tuple(p.value, p.u);
            return d;
          },
          "name -> (value, standard uncertainty), internal units")
      .def_property_readonly(
          "covariance", [](const Identified& r) { return matrix_array(r.run.result.covariance); },
          "(P, P) covariance sigma0^2 (J^T J)^-1 of the estimated parameters")
      .def_property_readonly("correlation", [](const Identified& r) { return matrix_array(r.run.result.correlation); })
      .def_property_readonly("identifiability", [](const Identified& r) { return r.run.result.identifiability; })
      .def_property_readonly(
          "machine", [](const Identified& r) { return r.run.result.machine; }, "The prior machine with the estimates")
      .def_property_readonly("artefact",
                             [](const Identified& r) { return artefact_dict(r.run.features, r.run.result.artefact); })
      .def_property_readonly(
          "rms",
          [](const Identified& r) {
            py::dict d;
            d["ball"] = r.run.result.rms_ball;
            d["facet"] = r.run.result.rms_facet;
            d["scale_bar"] = r.run.result.rms_scale_bar;
            return d;
          },
          "Unweighted residual RMS per kind, mm")
      .def_property_readonly(
          "monte_carlo",
          [](const Identified& r) -> py::object {
            if (!r.run.monte_carlo) return py::none();
            const auto& mc = *r.run.monte_carlo;
            py::dict d;
            d["runs"] = mc.runs;
            d["failed"] = mc.failed;
            d["mean"] = to_array(mc.mean);
            d["stdev"] = to_array(mc.stdev);
            std::vector<double> flat;
            for (const auto& s : mc.samples) flat.insert(flat.end(), s.begin(), s.end());
            d["samples"] = mc.mean.empty() ? new_array({0, 0}) : to_array(flat, mc.mean.size());
            return d;
          },
          "With monte_carlo runs: runs, failed, mean, stdev, samples (runs, P)")
      .def_property_readonly(
          "va", [](const Identified& r) { return r.run.va; },
          "VA of the identified model over the workspace (mm), or None")
      .def(
          "to_dict",
          [](const Identified& r, const std::string& out, const std::string& report) {
            return to_py(to_json(r.run, out, report));
          },
          "out"_a = "", "report"_a = "", "As `mtcal identify --json`.")
      .def(
          "parameters_yaml",
          [](const Identified& r, const std::string& source) {
            return identified_parameters_yaml(r.prior, r.run.result, source);
          },
          "measurements_source"_a = "measurements", "The identified errors as a parameter file.")
      .def(
          "write_parameters",
          [](const Identified& r, const std::string& path, const std::string& source) {
            write_identified_parameters(path, r.prior, r.run.result, source);
          },
          "path"_a, "measurements_source"_a = "measurements",
          "Writes parameters_yaml() to path (as `mtcal identify --out`).");
  m.def("identify", &identify, "machine"_a, "measurements"_a, "estimate"_a, py::kw_only(), "scale_bars"_a = py::none(),
        "pretravel"_a = false, "sigma"_a = 1e-3, "loss"_a = "none", "rank_tolerance"_a = 1e-8,
        "monte_carlo"_a = std::size_t{0}, "seed"_a = std::uint64_t{1}, "workspace"_a = py::none(), "truth"_a = nullptr,
        "threads"_a = 0, "require_fit"_a = false,
        R"(Identify machine parameters from probing measurements (nonlinear least squares on the exact
model): estimate names parameters ("EX0C", "EXX.1") or errors ("EXX": every coefficient).
sigma: standard deviation of a reading (mm) weighting the residuals. loss 'none', 'huber',
'cauchy'. monte_carlo: runs of re-drawn noise. workspace: grid (spec or dict) for the VA and
the comparison with truth (a Machine). A fit poorer than the readings' sigma explains (sigma0
above its chi-square bound, to_dict()["fit"]) gives a UserWarning, as the command warns; with
require_fit=True (--require-fit) it raises InputError instead. Returns IdentificationRun: values,
uncertainties, covariance (P, P), correlation, identified machine. As `mtcal identify`.)");
}

}  // namespace mtcal::python
