// mtcal compare: two measurement methods compared parameter by parameter over repeated tests.
#include <algorithm>
#include <iostream>
#include <memory>
#include <optional>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "common.hpp"
#include "mtcal/evaluation/compare.hpp"
#include "mtcal/io/files.hpp"
#include "mtcal/report/report.hpp"

namespace mtcal::cli {
namespace {

using json = nlohmann::ordered_json;

struct CompareOptions {
  std::string data, report;
  bool json_out = false;
};

template <class T>
json or_null(const std::optional<T>& v) {
  return v ? json(*v) : json(nullptr);
}

// Numbers for people: 5 significant digits whatever the input's unit; "-" where there is none.
std::string num(const std::optional<double>& v) { return v ? fmt::format("{:.5g}", *v) : std::string("-"); }
std::string yes_no(const std::optional<bool>& v) { return v ? (*v ? "yes" : "no") : "-"; }
std::string r_text(const std::optional<double>& v) { return v ? fmt::format("{:.3f}", *v) : std::string("-"); }

std::string summary_text(const MethodComparison& c) {
  const auto& s = c.summary;
  std::string t = fmt::format(
      "{} parameters, {} measured by both methods; mean +- 1 stdev bands overlap for {} of {}; Pearson r for {} "
      "(>= 3 paired tests, both varying): |r| >= {:g} for {} ({} positive, {} negative)\n",
      s.parameters, s.both_methods, s.overlap, s.overlap + s.no_overlap, s.with_correlation, kStrongCorrelation,
      s.strong_correlation, s.strong_positive, s.strong_negative);
  for (const auto& name : s.one_method_only) {
    const auto p = std::find_if(c.parameters.begin(), c.parameters.end(), [&](const auto& x) { return x.name == name; });
    t += fmt::format("only {} measured {}\n", c.methods[p->stats[0].n > 0 ? 0 : 1], name);
  }
  return t;
}

void write_report(const CompareOptions& o, const MethodComparison& c) {
  const auto& s = c.summary;
  Report r(fmt::format("Method comparison: {} and {}", c.methods[0], c.methods[1]), command_line());
  r.add_input("data", o.data);
  r.add_figure("parameters", fmt::format("{}", s.parameters), fmt::format("({} measured by both methods)", s.both_methods));
  r.add_figure("mean ± 1σ bands overlap", fmt::format("{} of {}", s.overlap, s.overlap + s.no_overlap), "parameters");
  r.add_figure(fmt::format("|Pearson r| ≥ {:g}", kStrongCorrelation), fmt::format("{} of {}", s.strong_correlation, s.with_correlation),
               fmt::format("parameters ({} positive, {} negative)", s.strong_positive, s.strong_negative));
  for (const auto& p : c.parameters) {
    if (p.stats[0].n == 0 || p.stats[1].n == 0)
      r.add_warning(fmt::format("{} was measured by {} only: no difference, overlap or correlation.", p.name,
                                c.methods[p.stats[0].n > 0 ? 0 : 1]));
    else if (p.stats[0].n < 2 || p.stats[1].n < 2)
      r.add_warning(fmt::format("{} has fewer than two tests for one method: no standard deviation, no overlap.", p.name));
  }

  r.add_section("Means of both methods");
  nlohmann::json data = nlohmann::json::array();
  for (std::size_t k = 0; k < 2; ++k) {
    nlohmann::json x = nlohmann::json::array(), y = x, e = x;
    for (const auto& p : c.parameters) {
      x.push_back(p.name);
      y.push_back(p.stats[k].mean ? nlohmann::json(*p.stats[k].mean) : nlohmann::json(nullptr));
      e.push_back(p.stats[k].stdev.value_or(0.0));
    }
    data.push_back({{"type", "bar"}, {"name", c.methods[k]}, {"x", x}, {"y", y},
                    {"error_y", {{"type", "data"}, {"array", e}, {"visible", true}}}});
  }
  r.add_plot("Mean of each parameter per method, with ±1 sample standard deviation as error bars (in the data's units)",
             {{"data", data},
              {"layout", {{"barmode", "group"}, {"yaxis", {{"title", {{"text", "mean (data's units)"}}}}}}}});

  r.add_section("Every parameter");
  r.add_paragraph("Standard deviations are sample standard deviations (n − 1). The ±1σ bands overlap when "
                  "|difference of means| ≤ σ₁ + σ₂. Pearson r pairs the tests of the same name and needs at least "
                  "three pairs in which both methods vary.");
  std::vector<std::vector<std::string>> rows;
  for (const auto& p : c.parameters)
    rows.push_back({p.name, fmt::format("{}", p.stats[0].n), num(p.stats[0].mean), num(p.stats[0].stdev),
                    fmt::format("{}", p.stats[1].n), num(p.stats[1].mean), num(p.stats[1].stdev), num(p.abs_diff),
                    yes_no(p.overlap), r_text(p.pearson_r), fmt::format("{}", p.paired)});
  const std::string& a = c.methods[0];
  const std::string& b = c.methods[1];
  r.add_table("Statistics per parameter (values in the data's units)",
              {"parameter", "n " + a, "mean " + a, "stdev " + a, "n " + b, "mean " + b, "stdev " + b,
               "|difference|", "±1σ overlap", "Pearson r", "paired tests"},
              rows);
  r.write(o.report);
}

int run_compare(const CompareOptions& o) {
  check_outputs({o.data}, {o.report});
  if (!o.report.empty()) AtomicFile check(o.report);  // refuse a bad report path before the work
  const MethodComparison c = compare_methods(read_comparison_csv(o.data));
  if (!o.report.empty()) write_report(o, c);

  if (o.json_out) {
    json j;
    j["file"] = o.data;
    j["methods"] = {c.methods[0], c.methods[1]};
    json params = json::object();
    for (const auto& p : c.parameters) {
      json mean, stdev, n;
      for (std::size_t k = 0; k < 2; ++k) {
        mean[c.methods[k]] = or_null(p.stats[k].mean);
        stdev[c.methods[k]] = or_null(p.stats[k].stdev);
        n[c.methods[k]] = p.stats[k].n;
      }
      params[p.name] = {{"mean", mean},         {"stdev", stdev},
                        {"abs_diff", or_null(p.abs_diff)}, {"overlap", or_null(p.overlap)},
                        {"pearson_r", or_null(p.pearson_r)}, {"n", n},
                        {"paired", p.paired}};
    }
    j["parameters"] = params;
    const auto& s = c.summary;
    j["summary"] = {{"parameters", s.parameters},
                    {"both_methods", s.both_methods},
                    {"one_method_only", s.one_method_only},
                    {"overlap", s.overlap},
                    {"no_overlap", s.no_overlap},
                    {"with_correlation", s.with_correlation},
                    {"strong_correlation", s.strong_correlation},
                    {"strong_positive", s.strong_positive},
                    {"strong_negative", s.strong_negative},
                    {"strong_threshold", kStrongCorrelation}};
    if (!o.report.empty()) j["report"] = o.report;
    std::cout << j.dump(2) << "\n";
    return 0;
  }

  std::size_t w = 9;
  for (const auto& p : c.parameters) w = std::max(w, p.name.size());
  std::cout << fmt::format("method A: {}\nmethod B: {}\n", c.methods[0], c.methods[1]);
  std::cout << fmt::format("{:<{}} {:>3} {:>11} {:>10} {:>3} {:>11} {:>10} {:>10} {:>7} {:>9}\n", "parameter", w, "nA",
                           "mean A", "stdev A", "nB", "mean B", "stdev B", "|A - B|", "overlap", "pearson r");
  for (const auto& p : c.parameters)
    std::cout << fmt::format("{:<{}} {:>3} {:>11} {:>10} {:>3} {:>11} {:>10} {:>10} {:>7} {:>9}\n", p.name, w,
                             p.stats[0].n, num(p.stats[0].mean), num(p.stats[0].stdev), p.stats[1].n,
                             num(p.stats[1].mean), num(p.stats[1].stdev), num(p.abs_diff), yes_no(p.overlap),
                             r_text(p.pearson_r));
  std::cout << summary_text(c);
  if (!o.report.empty()) std::cout << "report " << o.report << "\n";
  return 0;
}

}  // namespace

std::vector<Command> add_compare_commands(CLI::App& app) {
  auto o = std::make_shared<CompareOptions>();
  auto* c = app.add_subcommand(
      "compare",
      "Compare two measurement methods (e.g. ballbar and SAMBA) over repeated tests: per parameter the mean and "
      "sample standard deviation of each method, |difference of means|, whether the mean +- 1 stdev bands overlap, "
      "Pearson r over paired tests");
  c->add_option("DATA", o->data,
                "Long CSV with the header method,test,parameter,value: exactly two methods, one row per value")
      ->required();
  c->add_flag("--json", o->json_out, "Machine-readable output: methods, parameters (mean, stdev, n keyed by method; "
                                     "abs_diff, overlap, pearson_r), summary");
  c->add_option("--report", o->report, "Write an HTML report: bar chart of the means with ±1σ error bars, the table");
  return {{c, [o] { return run_compare(*o); }}};
}

}  // namespace mtcal::cli
