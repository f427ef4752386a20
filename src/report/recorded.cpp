// A recorded result's report made again: the command's path with the store's files.
#include "mtcal/report/recorded.hpp"

#include <algorithm>
#include <optional>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "mtcal/evaluation/ballbar.hpp"
#include "mtcal/evaluation/compare.hpp"
#include "mtcal/evaluation/iso230_2.hpp"
#include "mtcal/io/instruments/iso230_files.hpp"
#include "mtcal/io/instruments/probe_log.hpp"
#include "mtcal/io/instruments/probing_files.hpp"
#include "mtcal/io/instruments/probing_plan_file.hpp"
#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/probing/rotary_probing.hpp"
#include "mtcal/report/evaluation.hpp"
#include "mtcal/report/identification.hpp"
#include "mtcal/report/prediction.hpp"
#include "mtcal/report/probing.hpp"
#include "mtcal/report/report.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {

namespace {

Json invocation_json(const std::string& command_line, const std::string& file, Json options,
                     const ToleranceVerdict& verdict, const ReportMetadata& metadata) {
  Json j = Json::object();
  j["command_line"] = command_line;
  j["file"] = file;
  j["options"] = std::move(options);
  Json checks = Json::array();
  for (const auto& c : verdict.checks)
    checks.push_back({{"quantity", c.quantity}, {"value", c.value}, {"limit", c.limit}, {"pass", c.pass}});
  j["verdict"] = checks;
  Json meta = Json::array();
  for (const auto& [k, v] : metadata.entries()) meta.push_back({k, v});
  j["report_metadata"] = meta;
  return j;
}

}  // namespace

Json positioning_invocation(const std::string& command_line, const std::string& file, const std::string& format,
                            const std::string& unit, const std::string& target_unit, double wrap,
                            const ToleranceVerdict& verdict, const ReportMetadata& metadata) {
  return invocation_json(command_line, file,
                         {{"format", format}, {"unit", unit}, {"target_unit", target_unit}, {"wrap", wrap}}, verdict,
                         metadata);
}

Json ballbar_invocation(const std::string& command_line, const std::string& file, const std::string& plane,
                        double radius, double feed, double overshoot_start, double overshoot_stop,
                        const std::string& direction, const ToleranceVerdict& verdict, const ReportMetadata& metadata) {
  return invocation_json(command_line, file,
                         {{"plane", plane},
                          {"radius", radius},
                          {"feed", feed},
                          {"overshoot_start", overshoot_start},
                          {"overshoot_stop", overshoot_stop},
                          {"direction", direction}},
                         verdict, metadata);
}

Json comparison_invocation(const std::string& command_line, const std::string& file, const ReportMetadata& metadata) {
  return invocation_json(command_line, file, Json::object(), ToleranceVerdict{}, metadata);
}

Json regression_invocation(const std::string& command_line, const std::string& file, const std::string& x,
                           const std::string& y, const std::string& models, const ReportMetadata& metadata) {
  return invocation_json(command_line, file, {{"x", x}, {"y", y}, {"models", models}}, ToleranceVerdict{}, metadata);
}

Json rotary_invocation(const std::string& command_line, const std::string& file, char axis,
                       const std::string& dialect, const std::string& machine, double sphere_diameter,
                       double stylus_diameter, double max_rms, const std::optional<InstrumentFrame>& frame,
                       const std::string& method, double reject_sigma, int bins, const ReportMetadata& metadata) {
  Json f = Json::array();
  if (frame) {
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) f.push_back(frame->rotation(i, k));
    for (int i = 0; i < 3; ++i) f.push_back(frame->translation[i]);
  }
  return invocation_json(command_line, file,
                         {{"axis", std::string(1, axis)},
                          {"dialect", dialect},
                          {"machine", machine},
                          {"sphere_diameter", sphere_diameter},
                          {"stylus_diameter", stylus_diameter},
                          {"max_rms", max_rms},
                          {"frame", f},
                          {"method", method},
                          {"reject_sigma", reject_sigma},
                          {"bins", bins}},
                         ToleranceVerdict{}, metadata);
}

Json identification_invocation(const std::string& command_line, const std::string& file, const std::string& machine,
                               const std::vector<std::string>& params, const std::vector<std::string>& estimate,
                               const std::vector<std::string>& scale_bars, bool pretravel, double sigma_um,
                               double rank_tolerance, const std::string& loss, const std::vector<std::string>& not_kept,
                               const ReportMetadata& metadata) {
  return invocation_json(command_line, file,
                         {{"machine", machine},
                          {"params", params},
                          {"estimate", estimate},
                          {"scale_bars", scale_bars},
                          {"pretravel", pretravel},
                          {"sigma_um", sigma_um},
                          {"rank_tolerance", rank_tolerance},
                          {"loss", loss},
                          {"not_kept", not_kept}},
                         ToleranceVerdict{}, metadata);
}

namespace {

// The commands whose report is made from the store, and how their reports list them.
constexpr const char* kReportedCommands[] = {"iso230-2", "ballbar", "compare", "regress", "rotary-axis", "identify"};
constexpr const char* kReportedCommandsText = "iso230-2, ballbar, compare, regress, rotary-axis and identify";

bool report_made_from_store(const std::string& command) {
  for (const char* c : kReportedCommands)
    if (command == c) return true;
  return false;
}

// Strict reads of the invocation the recording command wrote (InputError naming the record).
struct RecordInvocation {
  const Json& j;
  std::string where;
  const Json& at(const Json& o, const char* key) const {
    if (!o.is_object() || !o.contains(key)) throw InputError({where, 0, key}, std::string("expected the key '") + key + "', found none");
    return o.at(key);
  }
  std::string text(const Json& o, const char* key) const {
    const Json& v = at(o, key);
    if (!v.is_string()) throw InputError({where, 0, key}, "expected text, found " + std::string(v.type_name()));
    return v.get<std::string>();
  }
  double number(const Json& o, const char* key) const {
    const Json& v = at(o, key);
    if (!v.is_number()) throw InputError({where, 0, key}, "expected a number, found " + std::string(v.type_name()));
    return v.get<double>();
  }
};

// The record's input at `path` (which the invocation names under `key`) and the store's copy of
// it when the store holds one of `kind`; `what` names the file in the messages.
struct StoredInput {
  InputHash input;
  std::optional<ModelFile> file;
  const char* what;
  // Why the report cannot be made without it.
  std::string missing() const {
    return fmt::format("the store does not hold the {} {} (SHA-256 {}) of this record", what, input.path, input.sha256);
  }
};

StoredInput stored_input(HistoryStore& store, const CalibrationRecord& r, const RecordInvocation& in,
                         const std::string& path, const char* key, const char* kind, const char* what) {
  const auto i = std::find_if(r.inputs.begin(), r.inputs.end(), [&](const InputHash& x) { return x.path == path; });
  if (i == r.inputs.end())
    throw InputError({in.where, 0, key}, fmt::format("the {} '{}' is none of the record's inputs", what, printable(path)));
  StoredInput s{*i, store.model_file(i->sha256), what};
  if (s.file && s.file->kind != kind) s.file.reset();
  return s;
}

Json parsed_record_invocation(const CalibrationRecord& r) {
  const Json j = Json::parse(r.invocation, nullptr, false);
  if (!j.is_object()) throw InputError({"record " + r.id, 0, "invocation"}, "expected a JSON object");
  return j;
}

// Why there is no report before the invocation is read: another command, or none kept.
std::string report_unsupported(HistoryStore& store, const CalibrationRecord& r) {
  if (r.command == "fit-motion" || r.command == "pose-check")
    return "mtcal " + r.command + " has no --report";
  if (!report_made_from_store(r.command))
    return "the report of mtcal " + r.command + " is not made from the store yet (those of " + kReportedCommandsText +
           " are)";
  if (!r.invocation.empty()) return "";
  std::string why =
      "the record does not say how its command ran (records made before schema version 6, by an mtcal that kept it "
      "for iso230-2 and ballbar only, by history import or from Python)";
  std::string files;
  std::size_t n = 0;
  for (const auto& i : r.inputs)
    if (const auto f = store.model_file(i.sha256); !f || f->kind != "measurements")
      files += (n++ ? ", " : "") + i.path + " (SHA-256 " + i.sha256 + ")";
  if (n > 0) why += std::string(", and the store does not hold its input file") + (n > 1 ? "s " : " ") + files;
  return why;
}

ToleranceVerdict recorded_verdict(const RecordInvocation& in) {
  ToleranceVerdict verdict;
  for (const auto& c : in.at(in.j, "verdict")) {
    const Json& pass = in.at(c, "pass");
    if (!pass.is_boolean()) throw InputError({in.where, 0, "pass"}, "expected true or false");
    verdict.checks.push_back({in.text(c, "quantity"), in.number(c, "value"), in.number(c, "limit"), pass.get<bool>()});
  }
  return verdict;
}

ReportMetadata recorded_metadata(const RecordInvocation& in) {
  ReportMetadata metadata;
  for (const auto& kv : in.at(in.j, "report_metadata")) {
    if (!kv.is_array() || kv.size() != 2 || !kv[0].is_string() || !kv[1].is_string())
      throw InputError({in.where, 0, "report_metadata"}, "expected [key, value] pairs of text");
    metadata.set(kv[0].get<std::string>(), kv[1].get<std::string>(), in.where + " report_metadata");
  }
  return metadata;
}

// The record's invocation and its measurement file's text from the store, with the machine file
// and the parameter files where the invocation names them (options "machine", "params":
// rotary-axis --machine, identify -m and --params), or why the report cannot be made (the reason
// of report_unsupported, what the record's command line gave that the store does not keep, or
// the file the store lacks).
struct StoredMeasurement {
  Json invocation;
  InputHash input;
  std::string text;
  std::optional<ModelFile> machine;
  std::string machine_path;
  std::vector<std::pair<std::string, ModelFile>> params;  // path as given, file
  std::string why;
};

// rotary-axis's path (cmd_probing.cpp run_rotary) with the stored contacts or centres, the stored
// machine file (machine_file: null when the command had no --machine) and the recorded options.
std::string recorded_rotary_html(const RecordInvocation& in, const InputHash& input, const std::string& text,
                                 const ModelFile* machine_file, const std::string& machine_path,
                                 const std::string& date) {
  const Json& o = in.at(in.j, "options");
  const std::string letter = in.text(o, "axis");
  if (letter.size() != 1 || letter[0] < 'A' || letter[0] > 'C')
    throw InputError({in.where, 0, "axis"}, "expected A, B or C, found '" + printable(letter) + "'");
  const char a = letter[0];
  NominalRotaryAxis axis = NominalRotaryAxis::by_letter(a);
  std::optional<Machine> machine;
  if (machine_file) {
    machine = parse_machine(machine_file->content, machine_path);
    axis = NominalRotaryAxis::from(machine->axis(a));
  }
  const double max_rms = in.number(o, "max_rms");
  const std::string dialect = in.text(o, "dialect");
  IndexedCentres centres;
  if (dialect == "centres") {
    centres = parse_centres_csv(text, input.path, a);
  } else {
    ContactSet contacts;
    if (dialect == "csv") {
      contacts = parse_contacts_csv(text, input.path, a);
    } else if (dialect == "iso" || dialect == "linuxcnc") {
      if (!machine) throw InputError({in.where, 0, "machine"}, "expected the machine file a probe log needs, found none");
      std::vector<LoggedAxisValues> log;
      for (auto& c : parse_probe_log(*machine, text, input.path,
                                     dialect == "iso" ? ProbeLogFormat::IsoCsv : ProbeLogFormat::LinuxCNC))
        log.push_back({std::move(c.q), c.line});
      contacts = contacts_from_log(*machine, a, log, input.path);
    } else {
      throw InputError({in.where, 0, "dialect"},
                       "expected csv, iso, linuxcnc or centres, found '" + printable(dialect) + "'");
    }
    centres = centres_from_contacts(contacts, SphereProbing{in.number(o, "sphere_diameter"),
                                                            in.number(o, "stylus_diameter"), max_rms});
  }
  // The instrument's frame as the command applied it: rotation row by row, then translation.
  const Json& f = in.at(o, "frame");
  if (!f.is_array() || (!f.empty() && f.size() != 12))
    throw InputError({in.where, 0, "frame"}, "expected [] or 12 numbers (rotation by rows, translation)");
  if (!f.empty()) {
    InstrumentFrame frame;
    for (std::size_t k = 0; k < 12; ++k) {
      if (!f[k].is_number()) throw InputError({in.where, 0, "frame"}, "expected a number, found " + std::string(f[k].type_name()));
      const double v = f[k].get<double>();
      if (k < 9)
        frame.rotation(static_cast<int>(k / 3), static_cast<int>(k % 3)) = v;
      else
        frame.translation[static_cast<int>(k - 9)] = v;
    }
    apply_frame(centres, frame);
  }
  const std::string method = in.text(o, "method");
  const RotaryAxisOptions options{
      method != "lsq", method != "triples",
      TriplesOptions{in.number(o, "reject_sigma"), static_cast<int>(in.number(o, "bins")), 0, {}}, 0.1};
  const RotaryAxisResult result = locate_rotary_axis(axis, std::move(centres), options);
  if (!result.located)
    throw InputError({in.where, 0, "axis"}, "the centres turn about a line far from the axis's nominal direction: "
                                            "the command made no report of them");
  return rotary_report(in.text(in.j, "command_line"), machine ? &*machine : nullptr, result, max_rms, input.sha256,
                       recorded_metadata(in))
      .html(date);
}

std::vector<std::string> texts(const RecordInvocation& in, const Json& o, const char* key) {
  std::vector<std::string> v;
  const Json& a = in.at(o, key);
  if (!a.is_array()) throw InputError({in.where, 0, key}, "expected a list of text");
  for (const auto& x : a) {
    if (!x.is_string()) throw InputError({in.where, 0, key}, "expected text, found " + std::string(x.type_name()));
    v.push_back(x.get<std::string>());
  }
  return v;
}

// identify's path (cmd_identification.cpp run_identify) with the stored machine, parameter and
// measurement files and the recorded options; a record whose command used what the store does
// not keep has no report (stored_measurement).
std::string recorded_identify_html(const RecordInvocation& in, const StoredMeasurement& s, const std::string& date) {
  const Json& o = in.at(in.j, "options");
  if (!s.machine) throw InputError({in.where, 0, "machine"}, "expected the machine file identify loaded, found none");
  Machine prior = parse_machine(s.machine->content, s.machine_path);
  IdentificationReportInputs files;
  IdentificationReportHashes hashes;
  for (const auto& [path, file] : s.params) {
    apply_parameter_file(prior, file.content, path);
    files.parameter_files.push_back(path);
    hashes.parameter_files.push_back(file.sha256);
  }
  const ProbingPlan measurements = parse_probing_csv(prior, s.text, s.input.path);
  IdentificationOptions opt;
  opt.estimate = texts(in, o, "estimate");
  opt.estimate_source = "--estimate";
  for (const auto& b : texts(in, o, "scale_bars")) opt.scale_bars.push_back(parse_scale_bar(b, "--scale-bar"));
  const Json& pretravel = in.at(o, "pretravel");
  if (!pretravel.is_boolean()) throw InputError({in.where, 0, "pretravel"}, "expected true or false");
  opt.estimate_pretravel = pretravel.get<bool>();
  opt.sigma_ball = opt.sigma_facet = opt.sigma_scale_bar = opt.sigma_ballbar = opt.sigma_laser =
      in.number(o, "sigma_um") * 1e-3;
  opt.rank_tolerance = in.number(o, "rank_tolerance");
  const std::string loss = in.text(o, "loss");
  if (loss != "none" && loss != "huber" && loss != "cauchy")
    throw InputError({in.where, 0, "loss"}, "expected none, huber or cauchy, found '" + printable(loss) + "'");
  opt.loss = loss == "huber"    ? IdentificationOptions::Loss::Huber
             : loss == "cauchy" ? IdentificationOptions::Loss::Cauchy
                                : IdentificationOptions::Loss::None;
  const IdentificationRun run = identify_and_assess(prior, measurements, opt, AssessmentOptions{});
  files.measurements = s.input.path;
  hashes.measurements = s.input.sha256;
  return identification_report(prior, run, files, hashes, in.text(in.j, "command_line"), recorded_metadata(in))
      .html(date);
}

// The command's path (cmd_evaluation.cpp) with the stored file's text and the recorded options.
std::string recorded_html(const CalibrationRecord& r, const RecordInvocation& in, const StoredMeasurement& s,
                          const std::string& date) {
  const InputHash& input = s.input;
  const std::string& text = s.text;
  if (r.command == "rotary-axis")
    return recorded_rotary_html(in, input, text, s.machine ? &*s.machine : nullptr, s.machine_path, date);
  if (r.command == "identify") return recorded_identify_html(in, s, date);
  const Json& o = in.at(in.j, "options");
  const std::string command = in.text(in.j, "command_line");
  if (r.command == "iso230-2") {
    PositioningRuns runs =
        parse_positioning_file(text, input.path, in.text(o, "format"), in.text(o, "unit"), in.text(o, "target_unit"));
    if (const double wrap = in.number(o, "wrap"); wrap > 0) runs = merge_wrapped_targets(runs, wrap);
    const PositioningEvaluation e = evaluate_positioning(runs);
    return positioning_report(command, runs, input.sha256, e, recorded_verdict(in), recorded_metadata(in)).html(date);
  }
  if (r.command == "regress") {
    const std::string x = in.text(o, "x"), y = in.text(o, "y");
    const TableRegression g = regress_table(parse_csv(text, input.path), input.path, x, y,
                                            parse_model_specs(in.text(o, "models"), in.where + " models"));
    return regression_report(g.comparison, g.x, g.y, input.path, input.sha256, x, y, command, recorded_metadata(in))
        .html(date);
  }
  if (r.command == "compare")
    return comparison_report(command, compare_methods(parse_comparison_csv(text, input.path)), input.sha256,
                             recorded_metadata(in))
        .html(date);
  BallbarOptions bo;
  bo.nominal_radius = in.number(o, "radius");
  bo.overshoot_start = in.number(o, "overshoot_start");
  bo.overshoot_stop = in.number(o, "overshoot_stop");
  const std::string direction = in.text(o, "direction");
  if (direction == "cw") bo.only = CircleDirection::CW;
  if (direction == "ccw") bo.only = CircleDirection::CCW;
  const std::string plane = in.text(o, "plane");
  const BallbarTrace t = parse_ballbar_csv(text, input.path);
  const auto e = evaluate_ballbar(t, bo);
  std::optional<TraceDiagnosis> diagnosis;
  if (!bo.only) diagnosis = diagnose_ballbar(t, bo, plane);
  return ballbar_report(command, t, input.sha256, e, diagnosis, plane, bo.nominal_radius, in.number(o, "feed"),
                        recorded_verdict(in), recorded_metadata(in))
      .html(date);
}

std::string invocation_where(const CalibrationRecord& r) { return "record " + r.id + " invocation"; }

StoredMeasurement stored_measurement(HistoryStore& store, const CalibrationRecord& r) {
  StoredMeasurement s;
  if (s.why = report_unsupported(store, r); !s.why.empty()) return s;
  s.invocation = parsed_record_invocation(r);
  const RecordInvocation in{s.invocation, invocation_where(r)};
  if (const Json& o = in.at(s.invocation, "options"); o.is_object() && o.contains("not_kept")) {
    const auto not_kept = texts(in, o, "not_kept");
    std::string list;
    for (std::size_t i = 0; i < not_kept.size(); ++i)
      list += (i == 0 ? "" : i + 1 == not_kept.size() ? " and " : ", ") + not_kept[i];
    if (!list.empty()) {
      s.why = "the report of this mtcal " + r.command + " depends on " + list +
              " of its command line, which the store does not keep";
      return s;
    }
  }
  StoredInput measurements =
      stored_input(store, r, in, in.text(in.j, "file"), "file", "measurements", "measurement file");
  s.input = measurements.input;
  if (!measurements.file) {
    s.why = measurements.missing();
    return s;
  }
  s.text = std::move(measurements.file->content);
  const Json& o = in.at(s.invocation, "options");
  if (!o.is_object() || !o.contains("machine")) return s;
  s.machine_path = in.text(o, "machine");
  if (s.machine_path.empty()) return s;
  StoredInput machine = stored_input(store, r, in, s.machine_path, "machine", "machine", "machine file");
  if (!machine.file) {
    s.why = machine.missing();
    return s;
  }
  s.machine = std::move(machine.file);
  if (!o.contains("params")) return s;
  for (const auto& path : texts(in, o, "params")) {
    StoredInput p = stored_input(store, r, in, path, "params", "parameters", "parameter file");
    if (!p.file) {
      s.why = p.missing();
      return s;
    }
    s.params.emplace_back(path, std::move(*p.file));
  }
  return s;
}

}  // namespace

RecordedReport recorded_report(HistoryStore& store, const CalibrationRecord& r, const std::string& date) {
  StoredMeasurement s = stored_measurement(store, r);
  if (!s.why.empty()) return {"", std::move(s.why)};
  return {recorded_html(r, RecordInvocation{s.invocation, invocation_where(r)}, s, date), ""};
}

std::string recorded_report_missing(HistoryStore& store, const CalibrationRecord& r) {
  return stored_measurement(store, r).why;
}

}  // namespace mtcal
