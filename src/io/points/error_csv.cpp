#include "mtcal/io/points/error_csv.hpp"

#include <bit>
#include <cstdint>

#include <algorithm>
#include <charconv>
#include <iterator>

#include <fmt/format.h>

#include "mtcal/io/text/number_format.hpp"

#include "mtcal/io/text/csv.hpp"
#include "mtcal/io/system/files.hpp"
#include "mtcal/model/joints.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/util/parallel.hpp"

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
      throw InputError({path, 1, c}, "unknown column '" + printable(c) + "' (expected axis letters of " +
                                         m.topology.chain + " and optional dir<axis>)");
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

ErrorStreamCsv::ErrorStreamCsv(const std::string& path, const Machine& m, bool with_directions, int threads,
                               bool translations_only)
    : machine_(m), file_(std::make_unique<AtomicFile>(path)), threads_(threads), errors_(translations_only ? 3 : 6) {
  const std::size_t n = m.axes.size();
  std::string header;
  for (std::size_t k = 0; k < n; ++k) header += (k ? "," : "") + std::string(1, m.axes[k].letter);
  if (with_directions)
    for (std::size_t k = 0; k < n; ++k) header += std::string(",dir") + m.axes[k].letter;
  for (std::size_t k = 0; k < errors_; ++k) header += std::string(",") + kErrorKeys[k];
  file_->stream() << header << "\n";
}

ErrorStreamCsv::~ErrorStreamCsv() = default;

namespace {

// One row's numbers as printf would write them ("%.12g" for axis values in user units, "%d" for
// directions, "%.9e" for errors): std::to_chars is specified as printf in the C locale, without
// a locale or an allocation per number.
char* put(char* p, double v, std::chars_format f, int precision) {
  return std::to_chars(p, p + 64, v, f, precision).ptr;
}

}  // namespace

void ErrorStreamCsv::write(const ErrorChunk& c) {
  const std::size_t n = c.axes, rows = c.size();
  // Axis values with at least 12 digits ("%.12g", as to_user_units rounds them), errors with the
  // chosen significant digits ("%.9e" by default): --precision up to 17 (io/number_format).
  const int position_digits = std::max(12, significant_digits()), error_decimals = significant_digits() - 1;
  std::vector<double> unit(n);
  for (std::size_t k = 0; k < n; ++k) unit[k] = joint_unit_factor(machine_.axes[k]);
  // Rows formatted in parallel slices of up to kSlice rows into per-slice buffers, written in
  // order (the bytes do not depend on the slicing), kSlices slices at a time so that the text
  // held stays small whatever the chunk. A row is at most n * (position_digits + 7 + 1 + 4)
  // + 6 * (error_decimals + 8 + 1) + 1 characters ("%.Pg" is at most P + 7, "%.De" D + 8, a
  // direction 2, and the commas).
  constexpr std::size_t kSlice = 4096, kSlices = 16;
  const std::size_t row_max =
      n * static_cast<std::size_t>(position_digits + 12) + 6 * static_cast<std::size_t>(error_decimals + 9) + 2;
  if (buffers_.size() < kSlices) buffers_.resize(kSlices);
  std::vector<std::size_t> used(kSlices);
  for (std::size_t group = 0; group < rows; group += kSlice * kSlices) {
    const std::size_t slices = std::min(kSlices, (rows - group + kSlice - 1) / kSlice);
    parallel_for(slices, threads_, [&](std::size_t s, std::size_t) {
      const std::size_t b = group + s * kSlice, e = std::min(rows, b + kSlice);
      auto& buf = buffers_[s];
      if (!buf) buf.reset(new char[kSlice * row_max]);  // not zero-filled
      char* p = buf.get();
      for (std::size_t r = b; r < e; ++r) {
        for (std::size_t k = 0; k < n; ++k) {
          if (k) *p++ = ',';
          // The user-unit value as to_user_units gives it (rounded to 12 digits) at the default.
          p = put(p, c.q[r * n + k] / unit[k], std::chars_format::general, position_digits);
        }
        if (!c.dir.empty())
          for (std::size_t k = 0; k < n; ++k) {
            *p++ = ',';
            p = std::to_chars(p, p + 8, static_cast<int>(c.dir[r * n + k])).ptr;
          }
        for (std::size_t x = 0; x < errors_; ++x) {
          *p++ = ',';
          p = put(p, c.error[r * 6 + x], std::chars_format::scientific, error_decimals);
        }
        *p++ = '\n';
      }
      used[s] = static_cast<std::size_t>(p - buf.get());
    });
    for (std::size_t s = 0; s < slices; ++s)
      file_->stream().write(buffers_[s].get(), static_cast<std::streamsize>(used[s]));
    file_->check_stream();
  }
}

void ErrorStreamCsv::commit() { file_->commit(); }

namespace {

// NumPy .npy version 1.0 (numpy.lib.format): the magic string, the version, a little-endian
// uint16 header length, then an ASCII Python dict literal padded with spaces and ended by a
// newline so that the data starts at a multiple of 64 bytes. Reserved at a fixed 128 bytes so
// that the shape can be written at commit without moving the data.
constexpr std::size_t kNpyHeader = 128;

std::string npy_header(std::size_t rows, std::size_t columns) {
  std::string dict = fmt::format("{{'descr': '<f8', 'fortran_order': False, 'shape': ({}, {}), }}", rows, columns);
  dict.resize(kNpyHeader - 10 - 1, ' ');
  dict += '\n';
  const auto len = static_cast<std::uint16_t>(dict.size());
  std::string h("\x93NUMPY\x01\x00", 8);
  h += static_cast<char>(len & 0xff);
  h += static_cast<char>(len >> 8);
  return h + dict;
}

}  // namespace

ErrorStreamNpy::ErrorStreamNpy(const std::string& path, const Machine& m, bool with_directions)
    : file_(std::make_unique<AtomicFile>(path)) {
  static_assert(std::endian::native == std::endian::little, "the .npy writer writes the doubles as they are ('<f8')");
  for (const auto& ax : m.axes) {
    inv_.push_back(1.0 / joint_unit_factor(ax));
    columns_.emplace_back(1, ax.letter);
  }
  if (with_directions)
    for (const auto& ax : m.axes) columns_.push_back(std::string("dir") + ax.letter);
  for (const char* k : kErrorKeys) columns_.emplace_back(k);
  file_->stream() << npy_header(0, columns_.size());
}

ErrorStreamNpy::~ErrorStreamNpy() = default;

void ErrorStreamNpy::write(const ErrorChunk& c) {
  const std::size_t n = c.axes, rows = c.size(), cols = columns_.size();
  buffer_.resize(rows * cols);
  double* p = buffer_.data();
  for (std::size_t r = 0; r < rows; ++r) {
    // The user-unit value as the CSV's (q / factor) before its rounding to 12 digits.
    for (std::size_t k = 0; k < n; ++k) *p++ = c.q[r * n + k] * inv_[k];
    if (!c.dir.empty())
      for (std::size_t k = 0; k < n; ++k) *p++ = c.dir[r * n + k];
    for (std::size_t x = 0; x < 6; ++x) *p++ = c.error[r * 6 + x];
  }
  file_->stream().write(reinterpret_cast<const char*>(buffer_.data()),
                        static_cast<std::streamsize>(buffer_.size() * sizeof(double)));
  file_->check_stream();
  rows_ += rows;
}

void ErrorStreamNpy::commit() {
  file_->stream().seekp(0);
  file_->stream() << npy_header(rows_, columns_.size());
  file_->check_stream();
  file_->commit();
}

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
    if (buf.size() > (1u << 20)) {
      out.stream().write(buf.data(), static_cast<std::streamsize>(buf.size()));
      out.check_stream();
      buf.clear();
    }
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
  file_->check_stream();
}

void ToolpathCsv::commit() { file_->commit(); }

}  // namespace mtcal
