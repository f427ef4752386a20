// mtcal rotary-axis and probe-sim: rotary-axis location errors from touch-probe sphere probing.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>
#include <numbers>
#include <optional>
#include <utility>

#include <fmt/format.h>
#include <unistd.h>

#include "acceptance.hpp"
#include "budget.hpp"
#include "common.hpp"
#include "history.hpp"
#include "mtcal/compensation/linuxcnc_kins.hpp"
#include "mtcal/io/compensation/linuxcnc_probe.hpp"
#include "mtcal/io/compensation/output.hpp"
#include "mtcal/io/system/files.hpp"
#include "mtcal/io/text/joints.hpp"
#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/io/instruments/probe_log.hpp"
#include "mtcal/io/instruments/probing_files.hpp"
#include "mtcal/io/json/probing_json.hpp"
#include "mtcal/probing/rotary_axis.hpp"
#include "mtcal/probing/rotary_probing.hpp"
#include "mtcal/probing/sphere_probing.hpp"
#include "mtcal/report/probing.hpp"
#include "mtcal/report/recorded.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/util/parallel.hpp"
#include "mtcal/util/parse.hpp"

namespace mtcal::cli {
namespace {

struct RotaryOptions {
  std::string axis = "C";
  std::string contacts, centres, machine, method = "both", out, report, frame, contacts_dialect = "csv";
  double sphere_diameter = 0, stylus_diameter = 0, reject_sigma = 2.0, max_rms = 0.01;
  int bins = 40, threads = 0;
  bool json_out = false;
};

// Display scale: positions and radius in um/mm, angles in urad.
std::pair<double, const char*> display(std::size_t q) {
  if (q == 4) return {1.0, "mm"};
  if (q < 2) return {1e3, "um"};
  return {1e6, "urad"};
}

void check_rotary_options(const RotaryOptions& o) {
  if (o.axis.size() != 1 || o.axis[0] < 'A' || o.axis[0] > 'C')
    throw InputError({"--axis", 0, ""}, "expected A, B or C, found '" + printable(o.axis) + "'");
  if (o.contacts.empty() == o.centres.empty())
    throw InputError({"rotary-axis", 0, ""}, "expected exactly one of --contacts and --centres");
  if (!o.contacts.empty() && !(o.sphere_diameter > 0))
    throw InputError({"--sphere-diameter", 0, ""}, "expected the sphere diameter (mm) with --contacts");
  if (o.contacts_dialect != "csv" && o.machine.empty())
    throw InputError({"--contacts-dialect", 0, ""},
                     "a probe log holds axis values: --machine is needed to turn them into tool positions");
  check_outputs({o.contacts, o.centres, o.machine}, {o.out, o.report});
  if (!o.out.empty() && o.machine.empty())
    throw InputError({"--out", 0, ""},
                     "--out needs --machine: the position errors are relative to the axis's nominal "
                     "point, which the machine file gives");
  if (o.reject_sigma != 0 && o.reject_sigma < 1)
    throw InputError({"--reject-sigma", 0, ""},
                     fmt::format("expected 0 (no rejection) or at least 1, found {:g}", o.reject_sigma));
}

void print_rotary(const RotaryAxisResult& r, const RotaryOptions& o) {
  const auto names = rotary_quantity_names(r.axis.letter);
  const TriplesEstimate* tri = r.triples ? &*r.triples : nullptr;
  const LeastSquaresEstimate* lsq = r.least_squares ? &*r.least_squares : nullptr;
  const bool u_known = r.uncertainty_known();
  std::cout << fmt::format("rotary axis {}: {} indexations, sphere centres: {}\n", r.axis.letter,
                           r.centres.centres.size(), r.centres.method);
  std::cout << fmt::format("{:<8} {:<5} {:>30} {:>30}\n", "", "", tri ? "triples (Cubas & Yeh)" : "",
                           lsq ? "least squares" : "");
  for (std::size_t q = 0; q < kRotaryQuantities; ++q) {
    const auto [f, unit] = display(q);
    auto cell = [&, f = f](const RotaryEstimate* e) {
      if (!e) return std::string();
      return u_known ? fmt::format("{:.4f} +- {:.4f}", e->value[q] * f, e->uncertainty[q] * f)
                     : fmt::format("{:.4f} +- n/a", e->value[q] * f);
    };
    std::cout << fmt::format("{:<8} {:<5} {:>30} {:>30}\n", names[q], unit, cell(tri), cell(lsq));
  }
  if (!u_known) std::cout << "3 indexations: a circle exactly, no redundancy, so no uncertainty\n";
  if (tri)
    std::cout << fmt::format("triples: {} ({} degenerate); kept after the {:g}-sigma rule: {} of {}\n", tri->triples,
                             tri->degenerate, o.reject_sigma, tri->kept[0], tri->triples - tri->degenerate);
}

// "rx,ry,rz[,tx,ty,tz]": rotation angles in deg (Rz Ry Rx) and a translation in mm.
InstrumentFrame parse_frame(const std::string& spec) {
  const auto parts = split_list(spec);
  if (parts.size() != 3 && parts.size() != 6)
    throw InputError({"--frame", 0, ""},
                     "expected rx,ry,rz (deg) or rx,ry,rz,tx,ty,tz (deg, mm), found '" + spec + "'");
  std::vector<double> v;
  for (const auto& p : parts) {
    const auto x = parse_number(p);
    if (!x) throw InputError({"--frame", 0, ""}, "expected a number, found '" + p + "'");
    v.push_back(*x);
  }
  const double d = std::numbers::pi / 180;
  return frame_from_angles(v[0] * d, v[1] * d, v[2] * d,
                           v.size() == 6 ? Point3(v[3], v[4], v[5]) : Point3(Point3::Zero()));
}

void print_line(const RotaryAxisResult& r) {
  std::cout << fmt::format("rotary axis {}: {} positions; measured line (least-squares circle of the centres)\n",
                           r.axis.letter, r.centres.centres.size());
  std::cout << fmt::format("  direction  {:.9f} {:.9f} {:.9f}   ({:.4f} deg from the nominal direction)\n",
                           r.line.direction.x(), r.line.direction.y(), r.line.direction.z(),
                           r.line.tilt * 180 / std::numbers::pi);
  std::cout << fmt::format("  point      {:.6f} {:.6f} {:.6f} mm (nearest the nominal point)\n", r.line.point.x(),
                           r.line.point.y(), r.line.point.z());
  std::cout << fmt::format("  radius     {:.6f} mm, centres' rms {:.3f} um\n", r.line.radius, r.line.rms * 1e3);
}

// Triples per second and thread of the all-triples estimator, both passes: 8.9e6 measured (C(500, 3)
// = 20,708,500 triples of 500 simulated centres in 2.32 s of CPU time, --method triples --threads 1,
// docs/reliability.md), rounded down.
constexpr double kTriplesPerSecond = 5e6;

int run_rotary(const RotaryOptions& o) {
  check_rotary_options(o);
  NominalRotaryAxis axis = NominalRotaryAxis::by_letter(o.axis[0]);
  std::optional<Machine> machine;
  if (!o.machine.empty()) {
    machine = load_machine(o.machine);
    axis = NominalRotaryAxis::from(machine->axis(o.axis[0]));
  }
  auto contact_set = [&] {
    if (o.contacts_dialect == "csv") return read_contacts_csv(o.contacts, o.axis[0]);
    std::vector<LoggedAxisValues> log;
    for (auto& c : read_probe_log(*machine, o.contacts,
                                  o.contacts_dialect == "iso" ? ProbeLogFormat::IsoCsv : ProbeLogFormat::LinuxCNC))
      log.push_back({std::move(c.q), c.line});
    return contacts_from_log(*machine, o.axis[0], log, o.contacts);
  };
  IndexedCentres centres =
      o.contacts.empty()
          ? read_centres_csv(o.centres, o.axis[0])
          : centres_from_contacts(contact_set(), SphereProbing{o.sphere_diameter, o.stylus_diameter, o.max_rms});
  std::optional<InstrumentFrame> frame;
  if (!o.frame.empty()) apply_frame(centres, *(frame = parse_frame(o.frame)));
  if (!o.out.empty()) AtomicFile check(o.out);  // refuse a bad path before the work
  if (!o.report.empty()) AtomicFile check(o.report);
  RotaryAxisOptions options{o.method != "lsq", o.method != "triples", TriplesOptions{o.reject_sigma, o.bins, o.threads},
                            0.1};
  if (options.triples) {
    // C(n, 3) triples: 1000 indexations take about 20 s on one thread, 5000 about 40 minutes.
    const std::size_t n = centres.centres.size();
    const TriplesCost cost = triples_cost(n, o.bins);
    const double threads = static_cast<double>(std::min(worker_count(o.threads, 64), std::max<std::size_t>(1, n / 8)));
    check_estimate({fmt::format("--method {} of {} indexations ({:.3g} triples; --method lsq takes any number)",
                                o.method, n, cost.triples),
                    cost.bytes, cost.triples / kTriplesPerSecond / threads, 0});
    if (n > kMaxTriplesCentres)
      throw InputError({centres.source, 0, ""},
                       fmt::format("{} indexations are more than --method triples/both takes (at most {}); use "
                                   "--method lsq",
                                   n, kMaxTriplesCentres));
  }
  if (options.triples && ::isatty(STDERR_FILENO) && centres.centres.size() >= 100)
    options.triples_options.progress = [](std::size_t done, std::size_t total) {
      std::cerr << fmt::format("\r  triples: {:.0f}%", 100.0 * static_cast<double>(done) / static_cast<double>(total))
                << (done == total ? "\r               \r" : "") << std::flush;
    };
  const RotaryAxisResult r = locate_rotary_axis(axis, std::move(centres), options);
  if (!r.located) {
    // The measured line only: the location errors (small angles about the nominal line) do not
    // exist for it, so neither a parameter file nor the report of them is written.
    if (!o.out.empty() || !o.report.empty())
      throw InputError({"--axis", 0, o.axis},
                       fmt::format("the centres turn about a line {:.1f} deg from the nominal direction of {}: no "
                                   "location errors to write (--frame gives the instrument's axes; wrong --axis?)",
                                   r.line.tilt * 180 / std::numbers::pi, o.axis));
    for (const auto& n : r.notes) std::cerr << "mtcal: note: " << n << "\n";
    if (o.json_out) {
      Json j;
      j["axis"] = std::string(1, r.axis.letter);
      j["located"] = false;
      j["indexations"] = r.centres.centres.size();
      j["axis_point"] = {r.line.point.x(), r.line.point.y(), r.line.point.z()};
      j["axis_direction"] = {r.line.direction.x(), r.line.direction.y(), r.line.direction.z()};
      j["radius"] = r.line.radius;
      j["tilt"] = r.line.tilt;
      j["rms"] = r.line.rms;
      j["notes"] = r.notes;
      std::cout << json_text(j, 2) << "\n";
      return 0;
    }
    print_line(r);
    return 0;
  }
  for (const auto& n : r.notes) std::cerr << "mtcal: note: " << n << "\n";
  if (!o.out.empty()) write_rotary_parameters(o.out, r);
  if (!o.report.empty()) write_rotary_report(o.report, command_line(), machine ? &*machine : nullptr, r, o.max_rms);
  if (recording()) {
    // The contacts or centres and how they were read and evaluated, for the record's report
    // (docs/history.md "Measurement files"); the machine file is kept as the record's model file.
    note_model_files(o.machine, {});
    const std::string file = o.contacts.empty() ? o.centres : o.contacts;
    note_report_source(file, rotary_invocation(command_line(), file, o.axis[0],
                                               o.contacts.empty() ? "centres" : o.contacts_dialect, o.machine,
                                               o.sphere_diameter, o.stylus_diameter, o.max_rms, frame, o.method,
                                               o.reject_sigma, o.bins, session_metadata()));
  }
  if (o.json_out || recording()) {
    Json j = to_json(r);
    if (!o.out.empty()) j["out"] = o.out;
    if (!o.report.empty()) j["report"] = o.report;
    if (emit_json(j, o.json_out)) return 0;
  }
  print_rotary(r, o);
  print_line(r);
  if (!o.out.empty()) std::cout << "wrote " << o.out << "\n";
  if (!o.report.empty()) std::cout << "report " << o.report << "\n";
  return 0;
}

struct SimOptions {
  ModelOptions model;
  std::string axis = "C", angles = "0:350:36", hold, sphere = "150,0,50", out;
  double sphere_diameter = 30, stylus_diameter = 6, noise = 0, bias = 0;
  std::uint64_t seed = 1;
};

int run_sim(const SimOptions& o) {
  check_outputs(model_inputs(o.model), {o.out});
  const Machine m = load(o.model);
  if (o.axis.size() != 1)
    throw InputError({"--axis", 0, ""}, "expected one axis letter, found '" + printable(o.axis) + "'");
  const auto k = m.axis_index(o.axis[0]);
  if (!k)
    throw InputError({"--axis", 0, ""}, "axis '" + printable(o.axis) + "' is not in topology " + m.topology.chain);
  ProbingSimulation sim;
  sim.axis = o.axis[0];
  // --angles lo:hi:count in deg, as a grid of that one axis.
  const auto grid = parse_grid(m, o.axis + "=" + o.angles, "--angles");
  sim.angles = grid[*k];
  sim.held = o.hold.empty() ? std::vector<double>(m.axes.size(), 0.0) : parse_joint_values(m, o.hold, "--hold");
  check_joints(m, sim.held, "--hold", false);
  const auto parts = split_list(o.sphere);
  if (parts.size() != 3)
    throw InputError({"--sphere", 0, ""}, "expected x,y,z in mm, found '" + printable(o.sphere) + "'");
  for (int c = 0; c < 3; ++c) {
    const auto v = parse_number(parts[static_cast<std::size_t>(c)]);
    if (!v || std::abs(*v) > 1e6)
      throw InputError({"--sphere", 0, ""}, "expected a number within +-1e6 mm, found '" +
                                                printable(parts[static_cast<std::size_t>(c)]) + "'");
    sim.sphere[c] = *v;
  }
  if (!(o.sphere_diameter > 0) || !(o.stylus_diameter >= 0) || !(o.noise >= 0) || !std::isfinite(o.bias))
    throw InputError({"probe-sim", 0, ""}, "expected a sphere diameter > 0, a stylus diameter >= 0 and a noise >= 0");
  sim.probing = {o.sphere_diameter, o.stylus_diameter, 0.01};
  sim.noise = o.noise;
  sim.trigger_bias = o.bias;
  sim.seed = o.seed;
  if (!o.out.empty()) AtomicFile check(o.out);  // refuse a bad path before the work
  const auto probed = simulate_probing(m, sim);
  write_contacts_csv(o.out, m.axes[*k], probed);
  std::cout << fmt::format(
      "simulated {} indexations of {} x 5 contacts on {} (noise {} mm, trigger bias {} mm): wrote {}\n", probed.size(),
      o.axis, m.name, o.noise, o.bias, o.out);
  return 0;
}

struct LinuxcncProbeCliOptions {
  ModelOptions model;
  std::vector<std::string> spheres;
  double sphere_diameter = 25.4, stylus_diameter = 3.0;
  std::string out;
  bool json_out = false;
};

int run_linuxcnc_probe(const LinuxcncProbeCliOptions& o) {
  check_outputs(model_inputs(o.model), {o.out});
  if (o.spheres.empty()) throw InputError({"--sphere", 0, ""}, "expected at least one sphere centre x,y,z (mm)");
  const Machine m = load(o.model);
  LinuxcncProbeOptions p;
  p.stylus_diameter = o.stylus_diameter;
  for (const auto& spec : o.spheres) {
    const auto parts = split_list(spec);
    if (parts.size() != 3)
      throw InputError({"--sphere", 0, ""}, "expected x,y,z in mm, found '" + printable(spec) + "'");
    SimulatedSphere s;
    s.diameter = o.sphere_diameter;
    for (int c = 0; c < 3; ++c) {
      const auto v = parse_number(parts[static_cast<std::size_t>(c)]);
      if (!v || std::abs(*v) > 1e6)
        throw InputError({"--sphere", 0, ""}, "expected a number within +-1e6 mm, found '" +
                                                  printable(parts[static_cast<std::size_t>(c)]) + "'");
      s.centre[c] = *v;
    }
    p.spheres.push_back(s);
  }
  if (!(o.sphere_diameter > 0) || o.sphere_diameter > 1e4)
    throw InputError({"--sphere-diameter", 0, ""}, fmt::format("expected > 0 and <= 1e4 mm, found {:g}", o.sphere_diameter));
  if (!(o.stylus_diameter >= 0) || o.stylus_diameter > 1e3)
    throw InputError({"--stylus-diameter", 0, ""}, fmt::format("expected >= 0 and <= 1e3 mm, found {:g}", o.stylus_diameter));
  if (p.spheres.size() > kLinuxcncProbeMaxSpheres)
    throw InputError({"--sphere", 0, ""},
                     fmt::format("expected at most {} spheres, found {}", kLinuxcncProbeMaxSpheres, p.spheres.size()));
  const TargetOutput out = linuxcnc_probe_output(m, p);
  write_target_output(o.out, out);
  if (o.json_out) {
    print_json(linuxcnc_probe_json(m, p, out, o.out));
    return 0;
  }
  std::cout << fmt::format("simulated probe {} of {} ({}), {} sphere(s), stylus {:g} mm\n", p.component_name, m.name,
                           m.topology.chain, p.spheres.size(), p.stylus_diameter);
  for (const auto& f : out.files) std::cout << "wrote        " << o.out << "/" << f.name << "\n";
  return 0;
}

}  // namespace

std::vector<Command> add_probing_commands(CLI::App& app) {
  auto ro = std::make_shared<RotaryOptions>();
  auto* r = app.add_subcommand(
      "rotary-axis",
      "Location errors of a rotary axis (ISO 230-7: EX0C EY0C EA0C EB0C for C ...) from a sphere probed at many "
      "indexations: all-triples estimator (Cubas & Yeh 2022) and global least-squares circle, with uncertainties");
  r->add_option("--axis", ro->axis, "The rotary axis turned between indexations: A, B or C")->required();
  r->add_option("--contacts", ro->contacts,
                "CSV of probe contacts: the axis's angle (deg, column named by its letter), recorded stylus-tip "
                "centre x,y,z (mm), approach_x,approach_y,approach_z (direction of probe motion)");
  r->add_option("--contacts-dialect", ro->contacts_dialect,
                "What --contacts is: csv (the columns above), linuxcnc (a PROBEOPEN probe log: X Y Z A B C U V W a "
                "line) or iso (the #5061 CSV of mtcal probe-log); a log needs --machine")
      ->check(CLI::IsMember({"csv", "linuxcnc", "iso"}))
      ->capture_default_str();
  r->add_option("--centres", ro->centres, "CSV of sphere centres already known: the axis's angle (deg), x,y,z (mm)");
  r->add_option("--sphere-diameter", ro->sphere_diameter, "Calibration sphere diameter, mm (with --contacts)")
      ->transform(length_in(1.0, "LENGTH"))
      ->check(kFinite);
  r->add_option("--stylus-diameter", ro->stylus_diameter, "Stylus tip diameter, mm (with --contacts)")
      ->transform(length_in(1.0, "LENGTH"))
      ->check(kFinite);
  r->add_option("--machine", ro->machine,
                "Machine file giving the axis's nominal point and direction (default: "
                "through the origin along its letter's axis)");
  r->add_option("--method", ro->method, "Estimator: triples, lsq or both")
      ->check(CLI::IsMember({"triples", "lsq", "both"}))
      ->capture_default_str();
  r->add_option("--reject-sigma", ro->reject_sigma,
                "Triples farther than this many standard deviations are "
                "rejected (0: none)")
      ->check(CLI::Range(0.0, 100.0) & kFinite)
      ->capture_default_str();
  r->add_option("--max-rms", ro->max_rms, "Largest rms distance (mm) of contacts from their sphere")
      ->transform(length_in(1.0, "LENGTH"))
      ->check(CLI::PositiveNumber & kFinite)
      ->capture_default_str();
  r->add_option("--bins", ro->bins, "Histogram bins of the triples' distributions")->check(CLI::Range(1, 10000));
  r->add_option("--threads", ro->threads, "Threads for the triples (0: all cores)")->check(CLI::Range(0, 4096));
  r->add_flag("--json", ro->json_out,
              "Machine-readable output: ISO names in mm and rad, '_u' uncertainty, "
              "'_spread' spread, triples' histograms");
  r->add_option("--out", ro->out,
                "Write the location errors as a parameter file (mtcal eval --params ...); with "
                "--method both the least-squares values");
  r->add_option("--frame", ro->frame,
                "The instrument's axes in the machine's: rx,ry,rz in deg (rotation Rz Ry Rx) and optionally "
                "tx,ty,tz in mm; machine = R * instrument + t");
  r->add_option("--report", ro->report,
                "Write an HTML report: both estimators, centres and circle, residuals, "
                "the triples' distributions");

  auto so = std::make_shared<SimOptions>();
  auto* s = app.add_subcommand("probe-sim",
                               "Simulated touch-probe contacts on a sphere at indexations of a rotary "
                               "axis of a machine model (5-point protocol), with noise and trigger bias");
  add_model_options(s, so->model);  // the machine's errors (with --params, --only, --set) are what the probing sees
  s->add_option("--axis", so->axis, "Rotary axis that carries the workpiece, turned between indexations")
      ->capture_default_str();
  s->add_option("--angles", so->angles, "Indexations lo:hi:count in deg")->capture_default_str();
  s->add_option("--hold", so->hold, "Other joints, e.g. \"A=0\" (mm, deg; not named: 0)");
  s->add_option("--sphere", so->sphere, "Sphere centre at zero indexation, machine coordinates x,y,z in mm")
      ->capture_default_str();
  s->add_option("--sphere-diameter", so->sphere_diameter, "mm")
      ->transform(length_in(1.0, "LENGTH"))
      ->check(kFinite)
      ->capture_default_str();
  s->add_option("--stylus-diameter", so->stylus_diameter, "mm")
      ->transform(length_in(1.0, "LENGTH"))
      ->check(kFinite)
      ->capture_default_str();
  s->add_option("--noise", so->noise, "Standard deviation of each recorded coordinate, mm")
      ->transform(length_in(1.0, "LENGTH"))
      ->check(kFinite)
      ->capture_default_str();
  s->add_option("--trigger-bias", so->bias, "Probe pre-travel along the approach, mm")
      ->transform(length_in(1.0, "LENGTH"))
      ->check(kFinite)
      ->capture_default_str();
  s->add_option("--seed", so->seed, "Random seed of the noise")->capture_default_str();
  s->add_option("--out", so->out, "Contacts CSV to write (input of mtcal rotary-axis --contacts)")->required();

  auto lo = std::make_shared<LinuxcncProbeCliOptions>();
  auto* l = app.add_subcommand(
      "linuxcnc-probe",
      "A simulated touch probe for LinuxCNC: writes a HAL component (C, halcompile) that sets motion.probe-input "
      "when the stylus tip of the given machine model - its errors are the truth the probe sees - touches a "
      "sphere. docs/planning.md");
  add_model_options(l, lo->model);
  l->add_option("--sphere", lo->spheres,
                "Sphere centre x,y,z (mm, the machine's workpiece frame); repeat for more spheres (up to 16)");
  l->add_option("--sphere-diameter", lo->sphere_diameter, "Sphere diameter, mm")
      ->transform(length_in(1.0, "LENGTH"))
      ->check(kFinite)
      ->capture_default_str();
  l->add_option("--stylus-diameter", lo->stylus_diameter, "Stylus tip diameter, mm")
      ->transform(length_in(1.0, "LENGTH"))
      ->check(kFinite)
      ->capture_default_str();
  l->add_option("--out", lo->out, "Output directory (mtcal_probe.c, build.sh, linuxcnc-probe.hal, README.txt)")->required();
  l->add_flag("--json", lo->json_out, "Machine-readable summary: machine, component, spheres, files, out");
  l->footer(
      "Examples:\n"
      "  mtcal linuxcnc-probe -m examples/machines/rrttt-table-table.yaml --sphere 120,-80,60 --out probe/\n"
      "  sh probe/build.sh   # halcompile --install (Debian's linuxcnc-uspace-dev)\n");
  return {{r, [ro] { return run_rotary(*ro); }}, {s, [so] { return run_sim(*so); }}, {l, [lo] { return run_linuxcnc_probe(*lo); }}};
}

}  // namespace mtcal::cli
