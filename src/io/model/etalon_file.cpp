#include "mtcal/io/model/etalon_file.hpp"
#include "mtcal/util/parse.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <optional>

#include <fmt/format.h>

#include "mtcal/model/joints.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {

namespace {

// Without any leading and trailing white space (std::isspace: line feeds and form feeds too).
std::string_view trim_space(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

// A strict decimal number (the whole word), finite.
std::optional<double> number(std::string_view word) {
  if (word.empty() || word.size() > 64) return std::nullopt;
  const std::string w(word);
  if (w.find_first_not_of("0123456789+-.eE") != std::string::npos) return std::nullopt;
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(w.c_str(), &end);
  if (end != w.c_str() + w.size() || errno == ERANGE || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::vector<std::string_view> words(std::string_view s) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
    const std::size_t start = i;
    while (i < s.size() && !std::isspace(static_cast<unsigned char>(s[i]))) ++i;
    if (i > start) out.push_back(s.substr(start, i - start));
  }
  return out;
}

[[noreturn]] void fail_at(const std::string& source, int line, const std::string& field, const std::string& what) {
  throw InputError({source, line, field}, what);
}

// Files from Windows programs may start with a UTF-8 byte order mark.
std::string_view without_bom(std::string_view text) {
  return text.rfind("\xEF\xBB\xBF", 0) == 0 ? text.substr(3) : text;
}

}  // namespace

bool looks_like_etalon(std::string_view text) {
  text = without_bom(text);
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view line = trim_space(text.substr(pos, end - pos));
    pos = end + 1;
    if (line.empty() || line.rfind("//", 0) == 0) continue;
    return line.front() == '[';
  }
  return false;
}

std::vector<EtalonBlock> parse_etalon(std::string_view text, const std::string& source) {
  text = without_bom(text);  // line endings: "\r\n" is trimmed with the other white space
  std::vector<EtalonBlock> blocks;
  bool in_grid = false;  // between "Gridpoints = {" and "}"
  bool has_key = false;  // the current block has its VALUE or Gridpoints
  int grid_line = 0;
  auto fail = [&](int line, const std::string& field, const std::string& what) { fail_at(source, line, field, what); };
  auto close_block = [&](int line) {
    if (!blocks.empty() && !has_key)
      fail(blocks.back().line, blocks.back().name,
           fmt::format("expected 'VALUE = number' or 'Gridpoints = {{' in block [{}], found {}", blocks.back().name,
                       line ? "the next block" : "the end of the file"));
  };
  // A row "argument value" of the current table.
  auto row = [&](std::string_view s, int line) {
    const auto w = words(s);
    if (w.empty()) return;
    EtalonBlock& b = blocks.back();
    const std::string field = fmt::format("{} row {}", b.name, b.argument.size() + 1);
    if (w.size() != 2)
      fail(line, field,
           fmt::format("expected two numbers 'argument value' in Gridpoints, found {} word(s): '{}'", w.size(),
                       printable(s)));
    const auto a = number(w[0]), v = number(w[1]);
    if (!a) fail(line, field, fmt::format("expected a number (argument), found '{}'", printable(w[0])));
    if (!v) fail(line, field, fmt::format("expected a number (error value), found '{}'", printable(w[1])));
    if (!b.argument.empty() && *a <= b.argument.back())
      fail(line, field,
           fmt::format("expected arguments strictly increasing, found {:g} after {:g}", *a, b.argument.back()));
    b.argument.push_back(*a);
    b.error.push_back(*v);
  };
  std::size_t pos = 0;
  int line_no = 0;
  while (pos <= text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(pos, end - pos);
    pos = end + 1;
    ++line_no;
    if (const auto c = line.find("//"); c != std::string_view::npos) line = line.substr(0, c);
    line = trim_space(line);
    if (line.empty()) {
      if (end == text.size()) break;
      continue;
    }
    if (in_grid) {
      const auto close = line.find('}');
      row(line.substr(0, close), line_no);
      if (close != std::string_view::npos) {
        if (!trim_space(line.substr(close + 1)).empty())
          fail(line_no, blocks.back().name,
               fmt::format("expected nothing after '}}', found '{}'", printable(line.substr(close + 1))));
        if (blocks.back().argument.size() < 2)
          fail(line_no, blocks.back().name,
               fmt::format("expected at least two Gridpoints rows, found {}", blocks.back().argument.size()));
        in_grid = false;
      }
    } else if (line.front() == '[') {
      if (line.back() != ']' || line.size() < 3)
        fail(line_no, "", fmt::format("expected a block name in square brackets, found '{}'", printable(line)));
      close_block(line_no);
      EtalonBlock b;
      b.name = std::string(trim_space(line.substr(1, line.size() - 2)));
      b.line = line_no;
      for (const auto& other : blocks)
        if (other.name == b.name)
          fail(line_no, b.name, fmt::format("block [{}] given twice (first at line {})", b.name, other.line));
      blocks.push_back(std::move(b));
      has_key = false;
    } else {
      const auto eq = line.find('=');
      if (blocks.empty())
        fail(line_no, "", fmt::format("expected a block name in square brackets first, found '{}'", printable(line)));
      EtalonBlock& b = blocks.back();
      if (eq == std::string_view::npos)
        fail(line_no, b.name, fmt::format("expected 'KEY = ...' in block [{}], found '{}'", b.name, printable(line)));
      const std::string key = to_upper(trim_space(line.substr(0, eq)));
      const std::string_view rest = trim_space(line.substr(eq + 1));
      if (has_key)
        fail(line_no, b.name,
             fmt::format("expected one VALUE or Gridpoints in block [{}], found a second key '{}'", b.name,
                         printable(key)));
      if (key == "VALUE") {
        const auto v = number(rest);
        if (!v) fail(line_no, b.name, fmt::format("expected a number after VALUE =, found '{}'", printable(rest)));
        b.value = *v;
      } else if (key == "GRIDPOINTS") {
        if (rest.empty() || rest.front() != '{')
          fail(line_no, b.name, fmt::format("expected '{{' after Gridpoints =, found '{}'", printable(rest)));
        b.table = true;
        in_grid = true;
        grid_line = line_no;
        const std::string_view after = rest.substr(1);
        const auto close = after.find('}');
        row(after.substr(0, close), line_no);
        if (close != std::string_view::npos) {
          if (b.argument.size() < 2)
            fail(line_no, b.name, fmt::format("expected at least two Gridpoints rows, found {}", b.argument.size()));
          in_grid = false;
        }
      } else {
        fail(line_no, b.name,
             fmt::format("expected the key VALUE or Gridpoints in block [{}], found '{}'", b.name, printable(key)));
      }
      has_key = true;
    }
    if (end == text.size()) break;
  }
  if (in_grid)
    fail(grid_line, blocks.back().name,
         fmt::format("expected '}}' closing the Gridpoints of [{}], found the end of the file", blocks.back().name));
  close_block(0);
  if (blocks.empty()) fail(0, "", "expected at least one block [NAME], found none");
  return blocks;
}

void apply_etalon(Machine& m, std::string_view text, const std::string& source) {
  const auto blocks = parse_etalon(text, source);
  Machine updated = m;  // all or nothing
  for (const auto& b : blocks) {
    const std::string expect = fmt::format(
        "expected an ISO 230-1 error of {} (a position error such as [C0B] with VALUE, a component error such as "
        "[EXY] with Gridpoints)",
        m.topology.chain);
    std::optional<ErrorName> name;
    if (b.table) {
      name = ErrorName::parse(b.name);
      if (!name || name->kind != ErrorKind::Motion || !m.has_error(*name))
        throw InputError({source, b.line, b.name}, fmt::format("unknown component error [{}]: {}", b.name, expect));
      const std::size_t a = *m.axis_index(name->body);
      Axis& ax = updated.axes[a];
      Table t;
      for (const double p : b.argument) t.positions.push_back(p * joint_unit_factor(ax));
      t.forward = b.error;
      ax.motion[static_cast<std::size_t>(index_of(name->component))] = MotionFunction(std::move(t));
      ax.motion_given[static_cast<std::size_t>(index_of(name->component))] = true;
    } else {
      name = ErrorName::parse("E" + b.name);
      if (!name || name->kind != ErrorKind::Location || !m.has_error(*name))
        throw InputError({source, b.line, b.name}, fmt::format("unknown position error [{}]: {}", b.name, expect));
      updated.set_parameter("E" + b.name, b.value);
    }
  }
  m = std::move(updated);
}

}  // namespace mtcal
