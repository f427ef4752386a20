// Python bindings of a rehearsed calibration campaign (docs/campaign.md): the drawn truth, reached poses, the campaign.
#include <memory>
#include <optional>

#include "common.hpp"
#include "mtcal/evaluation/pose_check.hpp"
#include "mtcal/identification/campaign.hpp"
#include "mtcal/identification/error_draw.hpp"
#include "mtcal/io/json/campaign_json.hpp"
#include "mtcal/io/model/drawn_parameters_file.hpp"
#include "mtcal/io/model/identification_result_file.hpp"
#include "mtcal/io/points/reached_poses_file.hpp"
#include "mtcal/report/campaign.hpp"

namespace mtcal::python {

using namespace pybind11::literals;

namespace {

struct ReachedPoses {
  std::vector<ReachedPose> poses;
  std::string source;
};

struct PoseCheckResult {
  PoseCheck check;
  std::vector<ReachedPose> poses;
};

struct CampaignRun {
  Machine machine;
  CampaignResult result;
  CampaignReportInputs inputs;
};

std::pair<double, double> range_of(py::handle r, const char* name) {
  const auto v = as_std_vector(r, name, 2);
  if (!(v[0] >= 0) || v[1] < v[0])
    throw py::value_error(std::string(name) + ": expected (lo, hi) with 0 <= lo <= hi");
  return {v[0], v[1]};
}

}  // namespace

void bind_rehearsal(py::module_& m) {
  py::class_<ErrorDraw>(m, "ErrorDraw", "A drawn truth (mtcal errors --draw): the truth and the nominal model.")
      .def_readonly("truth", &ErrorDraw::truth, "The nominal machine with the drawn errors (every other error zero)")
      .def_readonly("nominal", &ErrorDraw::nominal, "The same machine and forms, every error zero")
      .def_readonly("seed", &ErrorDraw::seed)
      .def("to_dict", [](const ErrorDraw& d) { return to_py(to_json(d)); },
           "As the 'draw' of `mtcal errors --draw --json`: seed, drawn[error size unit table parameters].")
      .def(
          "write_truth",
          [](const ErrorDraw& d, const std::string& path, const std::string& description) {
            write_truth_parameters(path, d, description);
          },
          "path"_a, "description"_a = "Drawn by mtcal (Python) draw_errors",
          "The parameter file of errors --draw --out: every error of the machine, the drawn values.")
      .def(
          "write_nominal",
          [](const ErrorDraw& d, const std::string& path, const std::string& description) {
            write_nominal_parameters(path, d, description);
          },
          "path"_a, "description"_a = "Drawn by mtcal (Python) draw_errors",
          "The parameter file of errors --draw --out-nominal: the same errors and forms, every value zero.");
  m.def(
      "draw_errors",
      [](const Machine& mm, std::uint64_t seed, const std::vector<std::string>& only,
         const std::vector<std::string>& tables, std::size_t table_points, py::handle length_um,
         py::handle angle_urad) {
        ErrorDrawOptions o;
        o.seed = seed;
        o.only = only;
        o.tables = tables;
        o.table_points = table_points;
        const auto [llo, lhi] = range_of(length_um, "length_um");
        const auto [alo, ahi] = range_of(angle_urad, "angle_urad");
        o.length_lo = llo * 1e-3, o.length_hi = lhi * 1e-3, o.angle_lo = alo * 1e-6, o.angle_hi = ahi * 1e-6;
        o.only_source = "only";
        o.tables_source = "tables";
        o.size_source = "length_um";
        return draw_errors(mm, o);
      },
      "machine"_a, "seed"_a, py::kw_only(), "only"_a = std::vector<std::string>{},
      "tables"_a = std::vector<std::string>{}, "table_points"_a = 13, "length_um"_a = py::make_tuple(5.0, 50.0),
      "angle_urad"_a = py::make_tuple(10.0, 100.0),
      R"(A truth drawn on the machine's nominal geometry (mtcal errors --draw SEED): every location error,
or only these errors/parameters, plus the motion errors in tables drawn as tables; sizes uniform in
length_um / angle_urad (lo, hi), random signs; the same seed gives the same truth everywhere.)");

  py::class_<ReachedPoses>(m, "ReachedPoses", "Commanded world poses and the joints reached (read_reached_poses).")
      .def_readonly("source", &ReachedPoses::source)
      .def("__len__", [](const ReachedPoses& r) { return r.poses.size(); });
  m.def(
      "read_reached_poses",
      [](const Machine& mm, const std::string& path) { return ReachedPoses{read_reached_poses(mm, path), path}; },
      "machine"_a, "path"_a,
      "A reached-pose CSV (X,Y,Z,<rotary> commanded in mm and deg; qX,qY,qZ,q<rotary> reached), as pose-check --poses.");
  py::class_<PoseCheckResult>(m, "PoseCheck", "The tool point at reached poses (check_reached_poses).")
      .def_property_readonly("max_error", [](const PoseCheckResult& r) { return r.check.max_error; }, "mm")
      .def_property_readonly("va", [](const PoseCheckResult& r) { return r.check.va.va.value; }, "mm")
      .def_property_readonly("errors",
                             [](const PoseCheckResult& r) {
                               std::vector<double> e;
                               for (const auto& d : r.check.poses)
                                 for (int c = 0; c < 3; ++c) e.push_back(d.error[c]);
                               return to_array(e, 3);
                             },
                             "(N, 3) actual - commanded tool point, mm")
      .def(
          "to_dict",
          [](const PoseCheckResult& r, bool per_pose) { return to_py(to_json(r.check, r.poses, per_pose)); },
          py::kw_only(), "per_pose"_a = false, "As `mtcal pose-check --json` (without machine).");
  m.def(
      "check_reached_poses",
      [](const Machine& mm, const ReachedPoses& poses, std::optional<double> tool_length) {
        PoseCheckOptions o;
        o.tool_length = tool_length;
        return PoseCheckResult{check_reached_poses(mm, poses.poses, o, poses.source), poses.poses};
      },
      "machine"_a, "poses"_a, py::kw_only(), "tool_length"_a = py::none(),
      "The machine (the truth) at the reached joints: actual - commanded per pose, max |e|, VA (mtcal pose-check).");

  py::class_<IdentifiedSummary>(m, "IdentifiedSummary", "What identify --json printed, read back.")
      .def_readonly("source", &IdentifiedSummary::source)
      .def_readonly("converged", &IdentifiedSummary::converged)
      .def_property_readonly("parameters", [](const IdentifiedSummary& s) {
        py::dict d;
        for (const auto& p : s.parameters) d[py::str(p.name)] = py::make_tuple(p.value, p.u);
        return d;
      }, "{name: (value, u)} in internal units");
  m.def("read_identification_json", &read_identification_json, "path"_a,
        "The JSON `mtcal identify --json` printed (saved to a file), as campaign --identified reads it.");
  py::class_<CampaignRun>(m, "CampaignResult", "A campaign judged (mtcal campaign).")
      .def("to_dict", [](const CampaignRun& c) { return to_py(to_json(c.result, c.machine)); },
           "As `mtcal campaign --json` (without report).")
      .def(
          "write_report",
          [](const CampaignRun& c, const std::string& path, const std::string& command) {
            campaign_report_page(c.machine, c.result, c.inputs, command.empty() ? "mtcal (Python) campaign" : command)
                .write(path);
          },
          "path"_a, "command"_a = "", "The HTML report of campaign --report.")
      .def(
          "_write_report",  // for write_report(result, path, pdf=, png_dir=, metadata=): --report-pdf, --report-png
          [](const CampaignRun& c, const std::string& path, const std::string& command) {
            campaign_report_page(c.machine, c.result, c.inputs, command).write(path);
          },
          "path"_a, "command"_a);
  m.def(
      "campaign",
      [](const Machine& mm, const ProbingPlan& before, const ProbingPlan& after, const IdentifiedSummary* identified,
         const Machine* truth, const ReachedPoses* poses_before, const ReachedPoses* poses_after,
         const std::string& reference, double noise) {
        if (reference != "nominal" && reference != "identified" && reference != "mean")
          throw py::value_error("reference: expected 'nominal', 'identified' or 'mean', found '" + reference + "'");
        if ((poses_before || poses_after) && !truth)
          throw py::value_error("truth: the reached poses are evaluated on the truth: give it");
        if (!(noise >= 0)) throw py::value_error("noise: expected a standard deviation >= 0 in mm");
        std::optional<PoseCheck> pb, pa;
        if (poses_before) pb = check_reached_poses(*truth, poses_before->poses, {}, poses_before->source);
        if (poses_after) pa = check_reached_poses(*truth, poses_after->poses, {}, poses_after->source);
        CampaignOptions o;
        o.reference = reference == "identified" ? BallReference::Identified
                      : reference == "mean"     ? BallReference::Mean
                                                : BallReference::Nominal;
        o.probing_noise = noise;
        o.before_source = before.source;
        o.after_source = after.source;
        CampaignRun run{mm, campaign_report(mm, before, after, identified, truth, pb ? &*pb : nullptr, pa ? &*pa : nullptr, o),
                        {}};
        run.inputs.before = before.source;
        run.inputs.after = after.source;
        if (identified) run.inputs.identified = identified->source;
        if (poses_before) run.inputs.poses_before = poses_before->source;
        if (poses_after) run.inputs.poses_after = poses_after->source;
        return run;
      },
      "machine"_a, "before"_a, "after"_a, py::kw_only(), "identified"_a = nullptr, "truth"_a = nullptr,
      "poses_before"_a = nullptr, "poses_after"_a = nullptr, "reference"_a = "nominal", "noise"_a = 0.0,
      R"(The campaign (mtcal campaign): before and after are measurements of the same plan
(read_probing_plan); identified from read_identification_json; truth the machine with the true
errors (Machine.load(path, params=[truth file])); poses from read_reached_poses; noise: the probing noise in mm.)");
}

}  // namespace mtcal::python
