#include "mtcal/io/error_csv.hpp"

#include <algorithm>
#include <iterator>

#include <fmt/format.h>

#include "mtcal/io/number_format.hpp"

#include "mtcal/io/csv.hpp"
#include "mtcal/io/files.hpp"
#include "mtcal/model/joints.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {

ConfigurationList read_configurations(const Machine& m, const std::string& path, bool travel_check) {
  const CsvTable table = read_csv(path);
  const std::size_t n = m.axes.size();
  std::vector<int> qcol(n, -1), dcol(n, -1);
  bool with_dir = false;
  for (std::size_t k = 0; k < n; ++k) {
    qcol[k] = table.column(std::string(1, m.axes[k].letter));
    dcol[k] = table.column(std::string("dir") + m.axes[k].letter);
    with_dir = with_dir || dcol[k] >= 0;
  }
  for (const auto& c : table.columns) {
    bool known = false;
    for (const auto& ax : m.axes)
      known = known || c == std::string(1, ax.letter) || c == std::string("dir") + ax.letter;
    for (const char* k : kErrorKeys) known = known || c == k;  // an evaluated file reads back
    if (!known)
      throw InputError({path, 1, c}, "unknown column '" + c + "' (expected axis letters of " + m.topology.chain +
                                         " and optional dir<axis>)");
  }
  if (std::all_of(qcol.begin(), qcol.end(), [](int c) { return c < 0; }))
    throw InputError({path, 1, ""}, "no axis column (expected columns named by the axis letters of " +
                                        m.topology.chain + "; axes without a column are at 0)");
  ConfigurationList out;
  out.axes = n;
  out.q.assign(table.rows.size() * n, 0.0);
  if (with_dir) out.dir.assign(table.rows.size() * n, 0);
  out.lines = table.lines;
  for (std::size_t r = 0; r < table.rows.size(); ++r) {
    std::vector<double> qr(n, 0.0);
    for (std::size_t k = 0; k < n; ++k) {
      if (qcol[k] >= 0) qr[k] = table.rows[r][qcol[k]] * joint_unit_factor(m.axes[k]);
      if (dcol[k] >= 0) {
        const double d = table.rows[r][dcol[k]];
        if (d != 1 && d != -1 && d != 0)
          throw InputError({path, table.lines[r], std::string("dir") + m.axes[k].letter},
                           fmt::format("expected +1, -1 or 0, found {:g}", d));
        out.dir[r * n + k] = static_cast<std::int8_t>(d);
      }
    }
    check_joints(m, qr, fmt::format("{}:{}", path, table.lines[r]), travel_check);
    std::copy(qr.begin(), qr.end(), out.q.begin() + static_cast<std::ptrdiff_t>(r * n));
  }
  return out;
}

ErrorStreamCsv::ErrorStreamCsv(const std::string& path, const Machine& m, bool with_directions)
    : machine_(m), file_(std::make_unique<AtomicFile>(path)) {
  const std::size_t n = m.axes.size();
  std::string header;
  for (std::size_t k = 0; k < n; ++k) header += (k ? "," : "") + std::string(1, m.axes[k].letter);
  if (with_directions)
    for (std::size_t k = 0; k < n; ++k) header += std::string(",dir") + m.axes[k].letter;
  for (const char* k : kErrorKeys) header += std::string(",") + k;
  file_->stream() << header << "\n";
}

ErrorStreamCsv::~ErrorStreamCsv() = default;

void ErrorStreamCsv::write(const ErrorChunk& c) {
  const std::size_t n = c.axes;
  const int position_digits = std::max(12, significant_digits()), error_decimals = significant_digits() - 1;
  fmt::memory_buffer buf;
  for (std::size_t r = 0; r < c.size(); ++r) {
    for (std::size_t k = 0; k < n; ++k)
      fmt::format_to(std::back_inserter(buf), "{}{:.{}g}", k ? "," : "",
                     to_user_units(machine_.axes[k], c.q[r * n + k]), position_digits);
    if (!c.dir.empty())
      for (std::size_t k = 0; k < n; ++k) fmt::format_to(std::back_inserter(buf), ",{}", c.dir[r * n + k]);
    for (int e = 0; e < 6; ++e) fmt::format_to(std::back_inserter(buf), ",{:.{}e}", c.error[r * 6 + e], error_decimals);
    buf.push_back('\n');
  }
  file_->stream().write(buf.data(), static_cast<std::streamsize>(buf.size()));
}

void ErrorStreamCsv::commit() { file_->commit(); }

void write_error_map_csv(const std::string& path, const Machine& m, const ErrorMap& map) {
  AtomicFile out(path);
  const int position_digits = std::max(12, significant_digits()), error_decimals = significant_digits() - 1;
  const std::size_t n = m.axes.size();
  std::string header;
  for (std::size_t k = 0; k < n; ++k) header += (k ? "," : "") + std::string(1, m.axes[k].letter);
  if (!map.dir.empty())
    for (std::size_t k = 0; k < n; ++k) header += std::string(",dir") + m.axes[k].letter;
  out.stream() << header << ",dx,dy,dz\n";
  fmt::memory_buffer buf;
  for (std::size_t i = 0; i < map.size(); ++i) {
    for (std::size_t k = 0; k < n; ++k)
      fmt::format_to(std::back_inserter(buf), "{}{:.{}g}", k ? "," : "", to_user_units(m.axes[k], map.q[i * n + k]),
                     position_digits);
    for (const std::int8_t d : map.direction(i)) fmt::format_to(std::back_inserter(buf), ",{}", d);
    fmt::format_to(std::back_inserter(buf), ",{:.{}e},{:.{}e},{:.{}e}\n", map.error[i].x(), error_decimals,
                   map.error[i].y(), error_decimals, map.error[i].z(), error_decimals);
    if (buf.size() > (1u << 20)) out.stream().write(buf.data(), static_cast<std::streamsize>(buf.size())), buf.clear();
  }
  out.stream().write(buf.data(), static_cast<std::streamsize>(buf.size()));
  out.commit();
}

void write_diagonals_csv(const std::string& path, const std::vector<DiagonalProfile>& diagonals) {
  AtomicFile out(path);
  out.stream() << "diagonal,position,deviation\n";
  for (const auto& d : diagonals)
    for (std::size_t i = 0; i < d.position.size(); ++i)
      out.stream() << fmt::format("{},{:.{}g},{:.{}e}\n", d.name, d.position[i], std::max(9, significant_digits()),
                                  d.deviation[i], significant_digits() - 1);
  out.commit();
}

ToolpathCsv::ToolpathCsv(const std::string& path, const Machine& m) : file_(std::make_unique<AtomicFile>(path)) {
  std::string header = "line,n,motion,s";
  for (const auto& ax : m.axes) header += std::string(",") + ax.letter;
  for (const char* k : kErrorKeys) header += std::string(",") + k;
  file_->stream() << header << "\n";
  for (const auto& ax : m.axes) inv_.push_back(1.0 / joint_unit_factor(ax));
}

ToolpathCsv::~ToolpathCsv() = default;

void ToolpathCsv::write(const ToolpathChunk& c) {
  const std::size_t n = inv_.size();
  const int position_digits = std::max(12, significant_digits()), error_decimals = significant_digits() - 1;
  fmt::memory_buffer buf;
  auto out = std::back_inserter(buf);
  for (std::size_t i = 0; i < c.size(); ++i) {
    fmt::format_to(out, "{},", c.line[i]);
    if (c.n[i] >= 0) fmt::format_to(out, "{}", c.n[i]);
    fmt::format_to(out, ",{},{:.6f}", to_string(c.motion[i]), c.s[i]);
    for (std::size_t k = 0; k < n; ++k) fmt::format_to(out, ",{:.{}g}", c.q[i * n + k] * inv_[k], position_digits);
    for (std::size_t e = 0; e < 6; ++e) fmt::format_to(out, ",{:.{}e}", c.error[i * 6 + e], error_decimals);
    buf.push_back('\n');
  }
  file_->stream().write(buf.data(), static_cast<std::streamsize>(buf.size()));
}

void ToolpathCsv::commit() { file_->commit(); }

}  // namespace mtcal
