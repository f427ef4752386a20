#include "budget.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <mutex>

#include <fmt/format.h>

#include "mtcal/io/system/files.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/util/parse.hpp"

namespace mtcal::cli {

RunLimits& run_limits() {
  static RunLimits l;
  return l;
}

namespace {

// "4G", "512M", "1e9", "2 GiB" -> bytes (binary prefixes: K = 1024).
std::string parse_size(std::string& text) {
  std::string s;
  for (char c : text)
    if (c != ' ') s += c;
  double f = 1;
  auto strip = [&](const char* suffix, double factor) {
    const std::string x = suffix;
    if (s.size() > x.size() && (s.compare(s.size() - x.size(), x.size(), x) == 0)) {
      s.resize(s.size() - x.size());
      f = factor;
      return true;
    }
    return false;
  };
  for (const auto& [suffix, factor] : {std::pair{"KiB", 1024.0},
                                       {"MiB", 1048576.0},
                                       {"GiB", 1073741824.0},
                                       {"TiB", 1099511627776.0},
                                       {"K", 1024.0},
                                       {"M", 1048576.0},
                                       {"G", 1073741824.0},
                                       {"T", 1099511627776.0}})
    if (strip(suffix, factor)) break;
  const auto v = parse_number(s);
  if (!v || *v * f < 1 || *v * f > 1e18)
    return "expected a size such as 512M, 8G or 1e9 (bytes), found '" + printable(text) + "'";
  text = fmt::format("{:.0f}", *v * f);
  return {};
}

}  // namespace

void add_limit_options(CLI::App& app) {
  const CLI::Validator size(parse_size, "SIZE");
  auto& l = run_limits();
  app.add_option("--max-memory", l.memory,
                 "Refuse a computation estimated to need more memory than this (bytes; K M G T suffixes)")
      ->transform(size)
      ->default_str("4G");
  app.add_option("--max-time", l.seconds, "Refuse a computation estimated to run longer than this (seconds)")
      ->check(CLI::Range(1.0, 1e9))
      ->default_str("3600");
  app.add_option("--max-output-size", l.output, "Refuse a streamed output file estimated to be larger than this")
      ->transform(size)
      ->default_str("16G");
  app.add_option_function<double>(
         "--max-input-size",
         [](double bytes) {
           const auto b = static_cast<std::size_t>(bytes);
           input_limits().text = b;
           input_limits().yaml = b;
         },
         "Largest input file read (bytes; default 256M, YAML files 16M; this sets both)")
      ->transform(size);
}

const char* limit_option(int limit) {
  switch (static_cast<Limit>(limit)) {
    case Limit::InputSize: return "--max-input-size";
    case Limit::Memory: return "--max-memory";
    case Limit::Time: return "--max-time";
    case Limit::OutputSize: return "--max-output-size";
  }
  return "";
}

void check_estimate(const Estimate& e) {
  const auto& l = run_limits();
  if (e.bytes > l.memory)
    throw LimitError(Limit::Memory, {e.what, 0, ""},
                     fmt::format("needs about {} of memory, beyond the limit of {}", format_bytes(e.bytes),
                                 format_bytes(l.memory)));
  if (e.output_bytes > l.output)
    throw LimitError(Limit::OutputSize, {e.what, 0, ""},
                     fmt::format("would write about {}, beyond the limit of {}", format_bytes(e.output_bytes),
                                 format_bytes(l.output)));
  if (e.seconds > l.seconds)
    throw LimitError(Limit::Time, {e.what, 0, ""},
                     fmt::format("would take about {}, beyond the limit of {}", format_seconds(e.seconds),
                                 format_seconds(l.seconds)));
}

namespace {
std::mutex g_progress_mutex;
}

Progress::Progress(std::string label, std::size_t total)
    : label_(std::move(label)),
      total_(total),
      active_(total > 0 && ::isatty(STDERR_FILENO)),
      start_(std::chrono::steady_clock::now()),
      last_(start_) {}

Progress::~Progress() {
  if (!active_) return;
  const std::lock_guard lock(g_progress_mutex);
  std::cerr << "\r" << std::string(72, ' ') << "\r" << std::flush;
}

void Progress::update(std::size_t done, std::size_t total) {
  if (!active_) return;
  const auto now = std::chrono::steady_clock::now();
  const std::lock_guard lock(g_progress_mutex);
  if (total) total_ = total;
  // At most 5 lines a second, and only for work that has lasted half a second.
  if (now - last_ < std::chrono::milliseconds(200) || now - start_ < std::chrono::milliseconds(500)) return;
  last_ = now;
  std::cerr << fmt::format("\r  {}: {} / {} ({:.0f}%)", label_, done, total_,
                           100.0 * static_cast<double>(done) / static_cast<double>(std::max<std::size_t>(total_, 1)))
            << std::flush;
}

}  // namespace mtcal::cli
