// mtcal command line: a thin layer that parses options, calls the library and prints results.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <functional>
#include <memory>
#include <unistd.h>
#include <iostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "mtcal/io/csv.hpp"
#include "mtcal/io/files.hpp"
#include "mtcal/io/joints.hpp"
#include "mtcal/io/machine_file.hpp"
#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/report/report.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/util/parse.hpp"
#include "mtcal/version.hpp"
#include "common.hpp"
#include "eval_report.hpp"

using namespace mtcal;
using namespace mtcal::cli;
using json = nlohmann::ordered_json;

namespace {

std::string fmt_num(double v) { return fmt::format("{:.9g}", v); }

int run_eval(const ModelOptions& mo, const std::string& at, const std::string& points,
             const std::string& grid, const std::string& out, const std::string& report, bool as_json,
             bool no_travel_check, int threads) {
  const int modes = !at.empty() + !points.empty() + !grid.empty();
  if (modes != 1) throw InputError({"eval", 0, ""}, "expected exactly one of --at, --points, --grid");
  {
    auto inputs = model_inputs(mo);
    inputs.push_back(points);
    check_outputs(inputs, {out, report});
  }
  const Machine m = load(mo);
  const ErrorModel model(m);
  const std::size_t n = m.axes.size();

  if (!at.empty()) {
    if (!out.empty()) throw InputError({"--out", 0, ""}, "--out goes with --points or --grid, not --at");
    if (!report.empty()) throw InputError({"--report", 0, ""}, "--report goes with --points or --grid, not --at");
    const auto q = parse_joint_values(m, at, "--at");
    check_joints(m, q, "--at", !no_travel_check);
    const VolumetricError e = model.evaluate(q);
    if (!e.translation.allFinite() || !e.rotation.allFinite())
      throw Error("the model gives a non-finite error at --at " + at + " (check the machine's error values)");
    const double v[6] = {e.translation.x(), e.translation.y(), e.translation.z(),
                         e.rotation.x(),    e.rotation.y(),    e.rotation.z()};
    if (as_json) {
      json j;
      for (int c = 0; c < 6; ++c) j[kOutputKeys[c]] = v[c];
      std::cout << j.dump(2) << "\n";
    } else {
      for (int c = 0; c < 6; ++c)
        std::cout << fmt::format("{} {:>16} {}\n", kOutputKeys[c], fmt_num(v[c]), c < 3 ? "mm" : "rad");
    }
    return 0;
  }

  // Batched modes: configurations come by index from the CSV rows or the grid, and are
  // evaluated in chunks so that a grid of any size runs in bounded memory.
  std::size_t count = 0;
  bool with_dir = false;
  std::function<void(std::size_t, double*, std::int8_t*)> fill;
  Configurations configs;
  std::vector<std::vector<double>> grid_values;
  if (!points.empty()) {
    configs = read_configurations(m, points, !no_travel_check);
    count = configs.size(n);
    with_dir = !configs.dir.empty();
    fill = [&](std::size_t r, double* qr, std::int8_t* dr) {
      std::copy_n(&configs.q[r * n], n, qr);
      if (dr) std::copy_n(&configs.dir[r * n], n, dr);
    };
  } else {
    grid_values = checked_grid(m, grid, !no_travel_check);
    count = grid_count(grid_values);
    // Mixed-radix index: the last axis of the chain varies fastest.
    fill = [&](std::size_t i, double* qr, std::int8_t*) {
      for (std::size_t k = n; k-- > 0;) {
        const std::size_t len = grid_values[k].size();
        qr[k] = grid_values[k][i % len];
        i /= len;
      }
    };
  }

  std::unique_ptr<AtomicFile> file;
  if (!out.empty()) {
    file = std::make_unique<AtomicFile>(out);
    std::string header;
    for (std::size_t k = 0; k < n; ++k) header += (k ? "," : "") + std::string(1, m.axes[k].letter);
    if (with_dir)
      for (std::size_t k = 0; k < n; ++k) header += std::string(",dir") + m.axes[k].letter;
    for (const char* k : kOutputKeys) header += std::string(",") + k;
    file->stream() << header << "\n";
  }

  std::optional<EvalReport> collect;
  if (!report.empty()) {
    AtomicFile probe_path(report);  // refuse a bad report path before the work
    collect.emplace(model, count);
  }

  const std::size_t chunk = std::size_t{1} << 20;
  const bool progress = count > chunk && ::isatty(STDERR_FILENO);
  std::vector<double> q(std::min(count, chunk) * n), res(std::min(count, chunk) * 6);
  std::vector<std::int8_t> dir(with_dir ? std::min(count, chunk) * n : 0);
  std::vector<double> q_t(n), q_r(n);  // configurations of the largest errors
  double bt = -1, br = -1, seconds = 0;
  fmt::memory_buffer buf;
  for (std::size_t first = 0; first < count; first += chunk) {
    const std::size_t len = std::min(chunk, count - first);
    for (std::size_t r = 0; r < len; ++r) fill(first + r, &q[r * n], with_dir ? &dir[r * n] : nullptr);
    const auto t0 = std::chrono::steady_clock::now();
    model.evaluate_batch(std::span(q).first(len * n), std::span(dir).first(with_dir ? len * n : 0),
                         std::span(res).first(len * 6), BatchOptions{threads});
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    for (std::size_t r = 0; r < len; ++r) {
      const double* e = &res[r * 6];
      if (!std::all_of(e, e + 6, [](double v) { return std::isfinite(v); }))
        throw Error(fmt::format("the model gives a non-finite error at configuration {} of {} (check the "
                                "machine's error values)",
                                first + r + 1, count));
      const double t = std::hypot(e[0], e[1], e[2]), a = std::hypot(e[3], e[4], e[5]);
      if (t > bt) bt = t, std::copy_n(&q[r * n], n, q_t.begin());
      if (a > br) br = a, std::copy_n(&q[r * n], n, q_r.begin());
      if (collect) collect->add(first + r, &q[r * n], e);
    }
    if (file) {
      buf.clear();
      for (std::size_t r = 0; r < len; ++r) {
        for (std::size_t k = 0; k < n; ++k)
          fmt::format_to(std::back_inserter(buf), "{}{:.12g}", k ? "," : "", to_user_units(m.axes[k], q[r * n + k]));
        if (with_dir)
          for (std::size_t k = 0; k < n; ++k) fmt::format_to(std::back_inserter(buf), ",{}", dir[r * n + k]);
        for (int c = 0; c < 6; ++c) fmt::format_to(std::back_inserter(buf), ",{:.9e}", res[r * 6 + c]);
        buf.push_back('\n');
      }
      file->stream().write(buf.data(), static_cast<std::streamsize>(buf.size()));
    }
    if (progress)
      std::cerr << fmt::format("\r  {} / {} configurations ({:.0f}%)", first + len, count,
                               100.0 * static_cast<double>(first + len) / static_cast<double>(count))
                << std::flush;
  }
  if (progress) std::cerr << "\r" << std::string(60, ' ') << "\r" << std::flush;
  if (file) file->commit();
  if (collect) collect->write(report, command_line(), points, grid, mo.params);

  auto where = [&](const std::vector<double>& qr) { return joint_json(m, qr); };
  auto where_text = [&](const std::vector<double>& qr) { return format_joint_values(m, qr); };
  if (as_json) {
    json j;
    j["configurations"] = count;
    j["seconds"] = seconds;
    j["max_translation"] = {{"value", count ? bt : 0.0}, {"at", count ? where(q_t) : json::object()}};
    j["max_rotation"] = {{"value", count ? br : 0.0}, {"at", count ? where(q_r) : json::object()}};
    if (!out.empty()) j["out"] = out;
    if (!report.empty()) j["report"] = report;
    std::cout << j.dump(2) << "\n";
  } else {
    std::cout << fmt::format("machine      {} ({})\n", m.name, m.topology.chain);
    std::cout << fmt::format("evaluated    {} configurations in {:.3f} s ({:.3g} per second)\n", count,
                             seconds, seconds > 0 ? static_cast<double>(count) / seconds : 0.0);
    if (count) {
      std::cout << fmt::format("largest translational error  {:.6f} mm  at {}\n", bt, where_text(q_t));
      std::cout << fmt::format("largest rotational error     {:.3f} urad  at {}\n", br * 1e6, where_text(q_r));
    }
    if (!out.empty()) std::cout << "wrote        " << out << "\n";
    if (!report.empty()) std::cout << "report       " << report << "\n";
  }
  return 0;
}

int run_errors(const ModelOptions& mo, bool as_json, bool nonzero, const std::string& report) {
  check_outputs(model_inputs(mo), {report});
  const Machine m = load(mo);
  const auto params = m.parameters();
  if (!report.empty()) {
    Report r("Error parameters of " + m.name, command_line());
    r.set_machine(m);
    for (const auto& p : mo.params) r.add_input("parameter file", p);
    std::size_t shown = 0;
    std::vector<std::vector<std::string>> rows;
    nlohmann::json names = nlohmann::json::array(), values = names;
    for (const auto& p : params) {
      if (nonzero && p.value == 0.0) continue;
      ++shown;
      rows.push_back({p.name, std::string(to_string(p.error.kind)), p.unit, fmt::format("{:.9g}", p.value)});
      if (p.error.kind != ErrorKind::Motion && p.value != 0.0) {
        names.push_back(p.name);
        values.push_back(p.value * (is_rotation(p.error.component) ? 1e6 : 1e3));
      }
    }
    r.add_figure("parameters", fmt::format("{} of {}", shown, params.size()), nonzero ? "(non-zero)" : "");
    r.add_section("Location and mounting errors");
    r.add_plot("Location and mounting errors (µm for translations, µrad for rotations)",
               {{"data", {{{"type", "bar"}, {"x", names}, {"y", values}, {"name", "value"}}}},
                {"layout", {{"yaxis", {{"title", {{"text", "µm or µrad"}}}}}}}});
    r.add_section("Every parameter");
    r.add_table("Parameters in internal units (mm, rad); motion-error coefficients per mm^i or rad^i",
                {"name", "kind", "unit", "value"}, rows);
    r.write(report);
  }
  if (as_json) {
    json arr = json::array();
    for (const auto& p : params) {
      if (nonzero && p.value == 0.0) continue;
      arr.push_back({{"name", p.name},
                     {"error", p.error.str()},
                     {"kind", std::string(to_string(p.error.kind))},
                     {"unit", p.unit},
                     {"value", p.value}});
    }
    json j;
    j["machine"] = m.name;
    j["topology"] = m.topology.chain;
    j["parameters"] = arr;
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::cout << fmt::format("{:<10} {:<9} {:<10} {:>16}\n", "name", "kind", "unit", "value");
  for (const auto& p : params) {
    if (nonzero && p.value == 0.0) continue;
    std::cout << fmt::format("{:<10} {:<9} {:<10} {:>16}\n", p.name, to_string(p.error.kind), p.unit,
                             fmt_num(p.value));
  }
  return 0;
}

int run_effects(const ModelOptions& mo, const std::string& at, const std::string& only_errors,
                const std::string& around, bool as_json, bool no_travel_check, const std::string& report) {
  check_outputs(model_inputs(mo), {report});
  Machine m = load(mo);
  // About the nominal machine the effects are the errors' definitions (exact zeros where an
  // error has no effect); about the actual machine they include second-order cross terms.
  if (around == "nominal") m.clear_errors();
  const auto q = parse_joint_values(m, at, "--at");
  check_joints(m, q, "--at", !no_travel_check);
  const std::vector<std::string> wanted = split_list(only_errors);
  for (const auto& w : wanted) {
    auto en = ErrorName::parse(w);
    if (!en || !m.has_error(*en))
      throw InputError({"--errors", 0, w}, "unknown error name '" + w + "' for topology " + m.topology.chain);
  }
  const auto effects = ErrorModel(m).error_sensitivities(q);
  // Per 1 um of a translational error or 1 urad of a rotational one: dx dy dz in um, rx ry rz in urad.
  json arr = json::array();
  std::vector<std::vector<std::string>> rows;
  json bar_names = json::array(), bar_values = json::array();
  std::string text = fmt::format("{:<6} {:<9} {:<5} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10}\n", "error", "kind",
                                 "per", "dx um", "dy um", "dz um", "rx urad", "ry urad", "rz urad");
  for (const auto& e : effects) {
    const std::string name = e.error.str();
    if (!wanted.empty() && std::find(wanted.begin(), wanted.end(), name) == wanted.end()) continue;
    const bool rot = is_rotation(e.error.component);
    // d(out)/d(error) in internal units; 1 um = 1e-3 mm, 1 urad = 1e-6 rad.
    const double per = rot ? 1e-6 : 1e-3;
    double v[6];
    for (int c = 0; c < 6; ++c) v[c] = e.effect[c] * per / (c < 3 ? 1e-3 : 1e-6);
    json j{{"error", name}, {"kind", std::string(to_string(e.error.kind))}, {"per", rot ? "urad" : "um"}};
    for (int c = 0; c < 6; ++c) j[kOutputKeys[c]] = v[c];
    arr.push_back(j);
    text += fmt::format("{:<6} {:<9} {:<5} {:>10.4g} {:>10.4g} {:>10.4g} {:>10.4g} {:>10.4g} {:>10.4g}\n", name,
                        to_string(e.error.kind), rot ? "urad" : "um", v[0], v[1], v[2], v[3], v[4], v[5]);
    rows.push_back({name, std::string(to_string(e.error.kind)), rot ? "1 µrad" : "1 µm", fmt::format("{:.4g}", v[0]),
                    fmt::format("{:.4g}", v[1]), fmt::format("{:.4g}", v[2]), fmt::format("{:.4g}", v[3]),
                    fmt::format("{:.4g}", v[4]), fmt::format("{:.4g}", v[5])});
    bar_names.push_back(name);
    bar_values.push_back(std::hypot(v[0], v[1], v[2]));
  }
  if (!report.empty()) {
    Report r("Single-error effects on " + m.name, command_line());
    r.set_machine(m);
    for (const auto& p : mo.params) r.add_input("parameter file", p);
    r.add_figure("configuration", format_joint_values(m, q, ", "), "mm, deg");
    r.add_figure("tool length", fmt::format("{:g}", m.tool.length), "mm");
    r.add_figure("linearised about", around, "machine");
    r.add_section("Effect of each error on the tool point");
    r.add_plot("Size of the tool-point displacement per 1 µm or 1 µrad of each error (µm)",
               {{"data", {{{"type", "bar"}, {"x", bar_names}, {"y", bar_values}, {"name", "|(dx, dy, dz)|"}}}},
                {"layout", {{"yaxis", {{"title", {{"text", "µm per µm or µrad"}}}}}}}});
    r.add_table("Effect per 1 µm (translational errors) or 1 µrad (rotational errors), workpiece frame",
                {"error", "kind", "per", "dx (µm)", "dy (µm)", "dz (µm)", "rx (µrad)", "ry (µrad)", "rz (µrad)"}, rows);
    r.write(report);
  }
  if (as_json) {
    json j;
    j["machine"] = m.name;
    j["topology"] = m.topology.chain;
    j["at"] = joint_json(m, q);
    j["tool_length"] = m.tool.length;
    j["around"] = around;
    j["effects"] = arr;
    std::cout << j.dump(2) << "\n";
  } else {
    std::cout << text;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  set_command_line(argc, argv);
  CLI::App app{"mtcal - geometric accuracy of CNC machine tools: error models, evaluation, "
               "identification and compensation"};
  app.set_version_flag("--version", std::string("mtcal ") + MTCAL_VERSION);
  app.require_subcommand(1);

  ModelOptions eval_model;
  std::string at, points, grid, out;
  bool eval_json = false, no_travel_check = false;
  int threads = 0;
  auto* eval = app.add_subcommand("eval", "Volumetric error (dx dy dz in mm, rx ry rz in rad) of the tool "
                                          "relative to the workpiece at joint configurations");
  add_model_options(eval, eval_model);
  eval->add_option("--at", at, "One configuration, e.g. \"X=100,Y=50,Z=-20,B=30,C=90\" (mm, deg; "
                               "axes not named are 0)");
  eval->add_option("--points", points, "CSV of configurations: columns named by axis letters (mm, deg), "
                                       "optional dirX ... = +1/-1 directions of motion");
  eval->add_option("--grid", grid, "Full grid, e.g. \"X=-300:300:7,B=-90:90:5\" (lo:hi:count per axis)");
  eval->add_option("--out", out, "Write every configuration with dx,dy,dz,rx,ry,rz to this CSV");
  std::string eval_report;
  eval->add_option("--report", eval_report, "Write an HTML report (error map, distribution, largest errors; "
                                            "self-contained, opens offline) of a --points or --grid run");
  eval->add_flag("--json", eval_json, "Machine-readable output (keys dx dy dz rx ry rz for --at)");
  eval->add_flag("--no-travel-check", no_travel_check, "Evaluate outside the axes' travel too");
  eval->add_option("--threads", threads, "Threads for batches (0: all cores)")->check(CLI::Range(0, 4096));

  ModelOptions err_model;
  bool err_json = false, nonzero = false;
  auto* errors = app.add_subcommand("errors", "List every error parameter of a machine: name, kind, "
                                              "internal unit, value");
  add_model_options(errors, err_model);
  errors->add_flag("--json", err_json, "Machine-readable output");
  errors->add_flag("--nonzero", nonzero, "Only parameters whose value is not zero");
  std::string err_report;
  errors->add_option("--report", err_report, "Write an HTML report of the parameters");

  ModelOptions eff_model;
  std::string eff_at, eff_errors;
  bool eff_json = false, eff_no_travel = false;
  auto* effects = app.add_subcommand(
      "effects", "Effect of each single error on the tool at one configuration: dx dy dz (um) and rx ry rz "
                 "(urad) per 1 um or 1 urad of the error (first-order sensitivity of the exact model)");
  add_model_options(effects, eff_model);
  effects->add_option("--at", eff_at, "The configuration, e.g. \"X=100,B=30\" (mm, deg; axes not named are 0)")
      ->required();
  effects->add_option("--errors", eff_errors, "Only these errors, comma-separated (e.g. EXX,EC0Y,EX0C)");
  std::string eff_around = "nominal";
  effects->add_option("--around", eff_around,
                      "Linearise about the error-free machine (nominal, the errors' definitions) or about the "
                      "machine with its errors (actual)")
      ->check(CLI::IsMember({"nominal", "actual"}))
      ->capture_default_str();
  effects->add_flag("--json", eff_json, "Machine-readable output (keys error kind per dx dy dz rx ry rz)");
  effects->add_flag("--no-travel-check", eff_no_travel, "Allow a configuration outside the travel");
  std::string eff_report;
  effects->add_option("--report", eff_report, "Write an HTML report of the effects");

  std::vector<Command> more = add_probing_commands(app);
  for (auto& c : add_evaluation_commands(app)) more.push_back(std::move(c));
  for (auto& c : add_compare_commands(app)) more.push_back(std::move(c));
  for (auto& c : add_volumetric_commands(app)) more.push_back(std::move(c));
  for (auto& c : add_toolpath_commands(app)) more.push_back(std::move(c));
  for (auto& c : add_prediction_commands(app)) more.push_back(std::move(c));
  for (auto& c : add_identification_commands(app)) more.push_back(std::move(c));

  if (argc > 1 && argv[1][0] != '-') {
    const std::string cmd = argv[1];
    bool known = false;
    for (const auto* sub : app.get_subcommands({})) known = known || sub->get_name() == cmd;
    if (!known) {
      std::string names;
      for (const auto* sub : app.get_subcommands({})) names += (names.empty() ? "" : ", ") + sub->get_name();
      std::cerr << "mtcal: error: unknown command '" << cmd << "' (expected one of " << names << "; see 'mtcal --help')\n";
      return 2;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // Usage errors: one line, exit 2 (help goes to stdout only when asked for).
    std::cerr << "mtcal: error: " << e.what() << " (see 'mtcal --help')\n";
    return 2;
  }
  try {
    const int rc = [&] {
      if (eval->parsed()) return run_eval(eval_model, at, points, grid, out, eval_report, eval_json, no_travel_check, threads);
      if (errors->parsed()) return run_errors(err_model, err_json, nonzero, err_report);
      if (effects->parsed()) return run_effects(eff_model, eff_at, eff_errors, eff_around, eff_json, eff_no_travel, eff_report);
      for (const auto& c : more)
        if (c.app->parsed()) return c.run();
      throw Error("no command");
    }();
    std::cout.flush();
    if (!std::cout) throw Error("cannot write the results to standard output");
    return rc;
  } catch (const std::exception& e) {
    std::string msg = e.what();
    // Every command that checks configurations against the travels can be told not to.
    if (msg.find(" is outside the travel [") != std::string::npos) msg += " (use --no-travel-check to evaluate anyway)";
    for (auto& c : msg)
      if (c == '\n') c = ' ';
    std::cerr << "mtcal: error: " << msg << "\n";
    return 1;
  }
  return 0;
}
