// mtcal compare: two measurement methods compared parameter by parameter over repeated tests.
#include <algorithm>
#include <iostream>
#include <memory>
#include <optional>

#include <fmt/format.h>

#include "acceptance.hpp"
#include "common.hpp"
#include "history.hpp"
#include "mtcal/evaluation/compare.hpp"
#include "mtcal/io/instruments/iso230_files.hpp"
#include "mtcal/io/json/evaluation_json.hpp"
#include "mtcal/io/system/files.hpp"
#include "mtcal/report/evaluation.hpp"
#include "mtcal/report/recorded.hpp"

namespace mtcal::cli {
namespace {

struct CompareOptions {
  std::string data, report;
  bool json_out = false;
};

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
    const auto p =
        std::find_if(c.parameters.begin(), c.parameters.end(), [&](const auto& x) { return x.name == name; });
    t += fmt::format("only {} measured {}\n", c.methods[p->stats[0].n > 0 ? 0 : 1], name);
  }
  return t;
}

void print_comparison(const MethodComparison& c) {
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
}

int run_compare(const CompareOptions& o) {
  check_outputs({o.data}, {o.report});
  if (!o.report.empty()) AtomicFile check(o.report);  // refuse a bad report path before the work
  const MethodComparison c = compare_methods(read_comparison_csv(o.data));
  if (!o.report.empty()) write_comparison_report(o.report, command_line(), c);
  if (recording()) note_report_source(o.data, comparison_invocation(command_line(), o.data, session_metadata()));
  if (o.json_out || recording()) {
    Json j = to_json(c);
    if (!o.report.empty()) j["report"] = o.report;
    if (emit_json(j, o.json_out)) return 0;
  }
  print_comparison(c);
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
  c->add_flag("--json", o->json_out,
              "Machine-readable output: methods, parameters (mean, stdev, n keyed by method; "
              "abs_diff, overlap, pearson_r), summary");
  c->add_option("--report", o->report, "Write an HTML report: bar chart of the means with ±1σ error bars, the table");
  return {{c, [o] { return run_compare(*o); }}};
}

}  // namespace mtcal::cli
