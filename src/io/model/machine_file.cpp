#include "mtcal/io/model/machine_file.hpp"

#include "mtcal/io/model/etalon_file.hpp"
#include "mtcal/io/system/files.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/yaml.h>

#include "mtcal/model/machine_builder.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/util/parse.hpp"
#include "mtcal/util/units.hpp"
#include "../text/yaml_reader.hpp"

namespace mtcal {
namespace {

constexpr int kFormatVersion = 1;

using namespace detail::yaml;

Vec3 vec3(const YAML::Node& n, const Ctx& ctx, double scale) {
  auto v = numbers(n, ctx);
  if (v.size() != 3) ctx.fail(n, fmt::format("expected 3 numbers [x, y, z], found {}", v.size()));
  return Vec3(v[0], v[1], v[2]) * scale;
}

// The location of a node for the builder: file, line and the dotted key path.
SourceLocation at(const YAML::Node& n, const Ctx& ctx) {
  return {ctx.file, n.IsDefined() ? n.Mark().line + 1 : 0, ctx.path};
}

const char* an(Dimension d) { return d == Dimension::Length ? "a length" : "an angle"; }

// A unit of the expected dimension; ratios (um/m ...) only where with_ratios (error values).
Unit checked_unit(const std::string& name, const YAML::Node& n, const Ctx& ctx, Dimension expected, bool with_ratios) {
  auto u = find_unit(name);
  if (!u)
    ctx.fail(n, fmt::format("unknown unit '{}' (expected {} unit: {})", name, an(expected),
                            accepted_units(expected, with_ratios)));
  if (u->dimension != expected || (u->ratio && !with_ratios))
    ctx.fail(n, fmt::format("'{}' is {} unit here; expected {} unit: {}", name,
                            u->ratio && u->dimension == expected ? "a slope, not a position" : an(u->dimension),
                            an(expected), accepted_units(expected, with_ratios)));
  return *u;
}

Unit unit(const YAML::Node& n, const Ctx& ctx, Dimension expected, bool with_ratios) {
  return checked_unit(text(n, ctx), n, ctx, expected, with_ratios);
}

// "12.5 um" or {value: 12.5, unit: um}.
double quantity(const YAML::Node& n, const Ctx& ctx, Dimension expected) {
  if (n.IsMap()) {
    auto e = entries(n, ctx, {"value", "unit", "description"});
    if (!e.count("value")) ctx.fail(n, "missing key 'value'");
    if (!e.count("unit")) ctx.fail(n, fmt::format("missing key 'unit' ({} unit)", an(expected)));
    (void)number(e["value"], ctx.child("value"));  // refuses what is no number
    const auto v = convert_number(e["value"].Scalar(), unit(e["unit"], ctx.child("unit"), expected, true).to_internal);
    if (!v) ctx.child("value").fail(e["value"], "'" + printable(e["value"].Scalar()) + "' is beyond the range of a number");
    return *v;
  }
  const char* example = expected == Dimension::Length ? "12 um" : "25 urad";
  if (!n.IsScalar())
    ctx.fail(n, fmt::format("expected '<number> <unit>' such as '{}', found {}", example, describe(n)));
  std::istringstream in(n.Scalar());
  std::string num, u, extra;
  in >> num >> u >> extra;
  if (u.empty() || !extra.empty())
    ctx.fail(n, fmt::format("expected '<number> <unit>' such as '{}', found '{}'", example, n.Scalar()));
  if (!parse_number(num)) ctx.fail(n, "expected a number before the unit, found '" + printable(num) + "'");
  const auto v = convert_number(num, checked_unit(u, n, ctx, expected, true).to_internal);
  if (!v) ctx.fail(n, "'" + printable(n.Scalar()) + "' is beyond the range of a number");
  return *v;
}

struct Direction {
  int axis = 0;  // 0 x, 1 y, 2 z
  double sign = 1.0;
};

Direction parse_direction(const YAML::Node& n, const Ctx& ctx) {
  std::string s = text(n, ctx);
  if (s.size() == 2 && (s[0] == '+' || s[0] == '-')) {
    char c = static_cast<char>(std::tolower(static_cast<unsigned char>(s[1])));
    if (c >= 'x' && c <= 'z') return {c - 'x', s[0] == '+' ? 1.0 : -1.0};
  }
  ctx.fail(n, "expected a direction '+x', '-x', '+y', '-y', '+z' or '-z', found '" + printable(s) + "'");
}

MotionFunction parse_motion(const YAML::Node& n, const Ctx& ctx, const Axis& ax, Component comp, double length_scale,
                            double angle_scale) {
  auto e = entries(n, ctx, {"unit", "argument_unit", "polynomial", "reversal", "table", "fourier", "description"});
  const Dimension value_dim = is_rotation(comp) ? Dimension::Angle : Dimension::Length;
  if (!e.count("unit"))
    ctx.fail(n, fmt::format("missing key 'unit' (the unit of the error values, {} unit)", an(value_dim)));
  const double vs = unit(e["unit"], ctx.child("unit"), value_dim, true).to_internal;
  const Dimension arg_dim = ax.kind == AxisKind::Linear ? Dimension::Length : Dimension::Angle;
  double as = ax.kind == AxisKind::Linear ? length_scale : angle_scale;
  if (e.count("argument_unit")) {
    if (e.count("fourier"))
      ctx.child("argument_unit")
          .fail(e["argument_unit"], "a Fourier series takes the angle itself; 'argument_unit' has no meaning there");
    as = unit(e["argument_unit"], ctx.child("argument_unit"), arg_dim, false).to_internal;
  }

  const int forms = static_cast<int>(e.count("polynomial") + e.count("table") + e.count("fourier"));
  if (forms != 1) ctx.fail(n, fmt::format("expected exactly one of 'polynomial', 'table', 'fourier', found {}", forms));
  const double reversal = e.count("reversal") ? number(e["reversal"], ctx.child("reversal")) * vs : 0.0;

  if (e.count("polynomial")) {
    Ctx pc = ctx.child("polynomial");
    auto c = numbers(e["polynomial"], pc);
    if (c.empty() || c.size() > 4)
      pc.fail(e["polynomial"], fmt::format("expected 1 to 4 coefficients [E0, E1, E2, E3], found {}", c.size()));
    Polynomial p;
    for (std::size_t i = 0; i < c.size(); ++i) p.coefficients[i] = c[i] * vs / std::pow(as, static_cast<double>(i));
    p.reversal = reversal;
    return MotionFunction(p);
  }
  if (e.count("table")) {
    if (e.count("reversal"))
      ctx.child("reversal").fail(e["reversal"], "a table gives direction dependence by 'backward', not 'reversal'");
    Ctx tc = ctx.child("table");
    auto t = entries(e["table"], tc, {"positions", "forward", "backward"});
    if (!t.count("positions")) tc.fail(e["table"], "missing key 'positions'");
    if (!t.count("forward")) tc.fail(e["table"], "missing key 'forward'");
    Table tab;
    tab.positions = numbers(t["positions"], tc.child("positions"));
    if (tab.positions.size() < 2)
      tc.child("positions")
          .fail(t["positions"], fmt::format("expected at least 2 positions, found {}", tab.positions.size()));
    for (std::size_t i = 1; i < tab.positions.size(); ++i)
      if (!(tab.positions[i] > tab.positions[i - 1]))
        tc.child("positions")
            .fail(t["positions"], fmt::format("positions must increase strictly; position {} ({}) follows {}", i,
                                              tab.positions[i], tab.positions[i - 1]));
    for (auto& x : tab.positions) x *= as;
    auto read_values = [&](const char* key, std::vector<double>& out) {
      out = numbers(t[key], tc.child(key));
      if (out.size() != tab.positions.size())
        tc.child(key).fail(t[key], fmt::format("expected {} values (one per position), found {}", tab.positions.size(),
                                               out.size()));
      for (auto& v : out) v *= vs;
    };
    read_values("forward", tab.forward);
    if (t.count("backward")) read_values("backward", tab.backward);
    return MotionFunction(tab);
  }
  if (ax.kind != AxisKind::Rotary)
    ctx.child("fourier").fail(e["fourier"],
                              "a Fourier series is for rotary axes; axis " + std::string(1, ax.letter) + " is linear");
  Ctx fc = ctx.child("fourier");
  auto f = entries(e["fourier"], fc, {"constant", "cos", "sin"});
  Fourier four;
  four.constant = f.count("constant") ? number(f["constant"], fc.child("constant")) * vs : 0.0;
  if (f.count("cos")) four.cos_terms = numbers(f["cos"], fc.child("cos"));
  if (f.count("sin")) four.sin_terms = numbers(f["sin"], fc.child("sin"));
  for (auto& v : four.cos_terms) v *= vs;
  for (auto& v : four.sin_terms) v *= vs;
  four.reversal = reversal;
  return MotionFunction(four);
}

// The errors section (machine files and parameter files): each error replaces what b had.
void read_errors(MachineBuilder& b, const YAML::Node& node, const Ctx& ec, double ls, double as) {
  auto errs = entries(node, ec, {});
  for (auto& [key, value] : errs) {
    const YAML::Node& n = value;
    Ctx kc = ec.child(key);
    const ErrorName en = b.error_name(key, at(n, kc));
    const Dimension dim = is_rotation(en.component) ? Dimension::Angle : Dimension::Length;
    if (en.kind == ErrorKind::Motion)
      b.motion(key, parse_motion(n, kc, b.current().axis(en.body), en.component, ls, as), at(n, kc));
    else
      b.error_value(key, quantity(n, kc, dim), at(n, kc));
  }
}

Machine build(const YAML::Node& root, const std::string& file) {
  Ctx ctx{file, ""};
  auto top =
      entries(root, ctx,
              {"mtcal_machine", "name", "description", "topology", "units", "axes", "tool", "workpiece", "errors"});
  if (!top.count("mtcal_machine"))
    ctx.fail(root, fmt::format("missing key 'mtcal_machine' (the format version, {})", kFormatVersion));
  {
    Ctx vc = ctx.child("mtcal_machine");
    double v = number(top["mtcal_machine"], vc);
    if (v != kFormatVersion)
      vc.fail(top["mtcal_machine"],
              fmt::format("unsupported format version {} (this mtcal reads {})", v, kFormatVersion));
  }
  MachineBuilder b;
  b.source(file);
  if (top.count("name")) b.name(text(top["name"], ctx.child("name")));
  if (top.count("description")) b.description(text(top["description"], ctx.child("description")));
  if (!top.count("topology")) ctx.fail(root, "missing key 'topology' (e.g. wCBXfYZt)");
  b.topology(text(top["topology"], ctx.child("topology")), at(top["topology"], ctx.child("topology")));
  const Topology& topology = b.current().topology;

  double ls = 1.0, as = std::numbers::pi / 180.0;  // defaults: mm and deg
  if (top.count("units")) {
    Ctx uc = ctx.child("units");
    auto u = entries(top["units"], uc, {"length", "angle"});
    if (u.count("length")) ls = unit(u["length"], uc.child("length"), Dimension::Length, false).to_internal;
    if (u.count("angle")) as = unit(u["angle"], uc.child("angle"), Dimension::Angle, false).to_internal;
  }

  if (!top.count("axes")) ctx.fail(root, "missing key 'axes'");
  Ctx ac = ctx.child("axes");
  auto axes = entries(top["axes"], ac, {});
  for (auto& [key, node] : axes) {
    Ctx kc = ac.child(key);
    if (key.size() != 1 || !b.current().axis_index(key[0]))
      kc.fail(node, "axis '" + printable(key) + "' is not in topology " + topology.chain);
    const char letter = key[0];
    if (node.IsNull()) continue;
    auto e = entries(node, kc, {"travel", "direction", "point", "description"});
    const double s = b.current().axis(letter).kind == AxisKind::Linear ? ls : as;
    if (e.count("travel") && !e["travel"].IsNull()) {
      auto t = numbers(e["travel"], kc.child("travel"));
      if (t.size() != 2) kc.child("travel").fail(e["travel"], "expected [min, max] with min < max");
      b.axis_travel(letter, t[0] * s, t[1] * s, at(e["travel"], kc.child("travel")));
    }
    if (e.count("direction")) {
      const Direction d = parse_direction(e["direction"], kc.child("direction"));
      b.axis_direction(letter, d.axis, d.sign, at(e["direction"], kc.child("direction")));
    }
    if (e.count("point"))
      b.axis_point(letter, vec3(e["point"], kc.child("point"), ls), at(e["point"], kc.child("point")));
  }
  for (char letter : topology.axes)
    if (!axes.count(std::string(1, letter)))
      ac.fail(top["axes"], std::string("axis '") + letter + "' of topology " + topology.chain +
                               " is missing (list it, even as '" + letter + ": {}')");

  if (top.count("tool")) {
    Ctx tc = ctx.child("tool");
    auto t = entries(top["tool"], tc, {"length", "spindle_point", "axis"});
    if (t.count("length"))
      b.tool_length(number(t["length"], tc.child("length")) * ls, at(t["length"], tc.child("length")));
    if (t.count("spindle_point"))
      b.tool_spindle_point(vec3(t["spindle_point"], tc.child("spindle_point"), ls),
                           at(t["spindle_point"], tc.child("spindle_point")));
    if (t.count("axis")) {
      const Direction d = parse_direction(t["axis"], tc.child("axis"));
      if (d.sign < 0) tc.child("axis").fail(t["axis"], "the tool axis is given as +x, +y or +z");
      b.tool_axis(d.axis, at(t["axis"], tc.child("axis")));
    }
  }
  if (top.count("workpiece")) {
    Ctx wc = ctx.child("workpiece");
    auto w = entries(top["workpiece"], wc, {"origin"});
    if (w.count("origin"))
      b.workpiece_origin(vec3(w["origin"], wc.child("origin"), ls), at(w["origin"], wc.child("origin")));
  }

  // Every motion error starts as a zero cubic with reversal (the builder's default), so that
  // every coefficient is a parameter (identification, --set) whether or not the file gives it.
  if (top.count("errors")) read_errors(b, top["errors"], ctx.child("errors"), ls, as);
  try {
    return b.build();
  } catch (const ModelError& e) {
    throw InputError({file, 0, ""}, e.what());
  }
}

}  // namespace

namespace {
// Counts the documents of a YAML stream and notices when the parser stops advancing: yaml-cpp
// 0.7 (Debian 12) restarts an empty document forever at a ',' outside a flow collection (its
// LoadAll never returns on a file holding just ","; upstream issue 1040, fixed after 0.7.0).
struct DocumentScan : YAML::EventHandler {
  std::vector<YAML::Mark> starts;  // where each document starts ('---' or its first node)
  std::vector<YAML::Mark> nodes;   // each document's first node, for messages
  void OnDocumentStart(const YAML::Mark& m) override {
    starts.push_back(m);
    nodes.push_back(m);
    first = true;
  }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark& m, YAML::anchor_t) override { node(m); }
  void OnAlias(const YAML::Mark& m, YAML::anchor_t) override { node(m); }
  void OnScalar(const YAML::Mark& m, const std::string&, YAML::anchor_t, const std::string&) override { node(m); }
  void OnSequenceStart(const YAML::Mark& m, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {
    node(m);
  }
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark& m, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {
    node(m);
  }
  void OnMapEnd() override {}

 private:
  bool first = false;
  void node(const YAML::Mark& m) {
    if (first) nodes.back() = m;
    first = false;
  }
};

YAML::Node load_one_document(std::string_view yaml_text, const std::string& source) {
  try {
    std::istringstream in{std::string(yaml_text)};
    YAML::Parser parser(in);
    DocumentScan scan;
    // Four documents at most: enough to see the parser stuck (two starts at one position) or a
    // second document, never an endless loop.
    while (scan.starts.size() < 4 && parser.HandleNextDocument(scan)) {
    }
    for (std::size_t k = 1; k < scan.starts.size(); ++k)
      if (scan.starts[k].pos == scan.starts[k - 1].pos)
        throw InputError({source, scan.starts[k].line + 1, ""},
                         "not valid YAML: expected a key, a value or '-', found a ',' outside [ ] or { }");
    if (scan.starts.size() > 1)
      throw InputError({source, scan.nodes[1].line + 1, ""},
                       fmt::format("expected one YAML document, found {}{} (one per file)", scan.starts.size(),
                                   scan.starts.size() == 4 ? " or more" : ""));
    return YAML::Load(std::string(yaml_text));
  } catch (const YAML::Exception& e) {
    throw InputError({source, e.mark.line + 1, ""}, "not valid YAML: " + e.msg);
  }
}
}  // namespace

Machine parse_machine(std::string_view yaml_text, const std::string& source) {
  const YAML::Node root = load_one_document(yaml_text, source);
  try {
    return build(root, source);
  } catch (const YAML::Exception& e) {
    throw InputError({source, e.mark.line + 1, ""}, e.msg);
  }
}

void apply_parameters(Machine& m, std::string_view yaml_text, const std::string& source) {
  const YAML::Node root = load_one_document(yaml_text, source);
  Ctx ctx{source, ""};
  try {
    auto top = entries(root, ctx, {"mtcal_parameters", "description", "units", "errors"});
    if (!top.count("mtcal_parameters"))
      ctx.fail(root, fmt::format("missing key 'mtcal_parameters' (the format version, {})", kFormatVersion));
    Ctx vc = ctx.child("mtcal_parameters");
    const double version = number(top["mtcal_parameters"], vc);
    if (version != kFormatVersion)
      vc.fail(top["mtcal_parameters"],
              fmt::format("unsupported format version {} (this mtcal reads {})", version, kFormatVersion));
    if (top.count("description")) text(top["description"], ctx.child("description"));
    double ls = 1.0, as = std::numbers::pi / 180.0;
    if (top.count("units")) {
      Ctx uc = ctx.child("units");
      auto u = entries(top["units"], uc, {"length", "angle"});
      if (u.count("length")) ls = unit(u["length"], uc.child("length"), Dimension::Length, false).to_internal;
      if (u.count("angle")) as = unit(u["angle"], uc.child("angle"), Dimension::Angle, false).to_internal;
    }
    MachineBuilder updated(m);  // all or nothing
    if (top.count("errors")) read_errors(updated, top["errors"], ctx.child("errors"), ls, as);
    m = updated.build();
  } catch (const YAML::Exception& e) {
    throw InputError({source, e.mark.line + 1, ""}, e.msg);
  }
}

void load_parameters(Machine& m, const std::string& path) {
  apply_parameter_file(m, read_text_file(path, "parameter file", input_limits().yaml), path);
}

void apply_parameter_file(Machine& m, std::string_view text, const std::string& source) {
  // An Etalon exchange file (what --format etalon writes) is a parameter file too (docs/compensation.md).
  if (looks_like_etalon(text)) return apply_etalon(m, text, source);
  apply_parameters(m, text, source);
}

Machine load_machine(const std::string& path) {
  return parse_machine(read_text_file(path, "machine file", input_limits().yaml), path);
}

namespace {
// The files are read back strictly (finite numbers only): a non-finite value is never written.
std::string num(double v) {
  if (!std::isfinite(v))
    throw Error(fmt::format("cannot write the non-finite value {} to a machine or parameter file", v));
  return fmt::format("{:.17g}", v);
}
std::string list(const std::vector<double>& v) {
  std::string s = "[";
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + num(v[i]);
  return s + "]";
}
std::string vec(const Vec3& v) { return list({v.x(), v.y(), v.z()}); }
std::string quote(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}
}  // namespace

// One error's line of an `errors:` section, internal units (mm, rad), full precision.
std::string error_yaml(const Machine& m, const ErrorName& en) {
  const int c = index_of(en.component);
  const char* u = c >= 3 ? "rad" : "mm";
  if (en.kind == ErrorKind::Mounting) {
    const auto& arr = en.body == 't' ? m.tool_mounting : m.workpiece_mounting;
    return fmt::format("  {}: {{value: {}, unit: {}}}\n", en.str(), num(arr[static_cast<std::size_t>(c)]), u);
  }
  const Axis& ax = m.axis(en.body);
  if (en.kind == ErrorKind::Location)
    return fmt::format("  {}: {{value: {}, unit: {}}}\n", en.str(), num(ax.location[static_cast<std::size_t>(c)]), u);
  const auto& f = ax.motion[static_cast<std::size_t>(c)];
  const char* au = ax.kind == AxisKind::Linear ? "mm" : "rad";
  std::string y = fmt::format("  {}: {{unit: {}, ", en.str(), u);
  if (const auto* p = std::get_if<Polynomial>(&f.form())) {
    y += fmt::format("argument_unit: {}, polynomial: {}, reversal: {}}}\n", au,
                     list({p->coefficients.begin(), p->coefficients.end()}), num(p->reversal));
  } else if (const auto* t = std::get_if<Table>(&f.form())) {
    y += fmt::format("argument_unit: {}, ", au);
    y += "table: {positions: " + list(t->positions) + ", forward: " + list(t->forward);
    if (!t->backward.empty()) y += ", backward: " + list(t->backward);
    y += "}}\n";
  } else {
    const auto& fo = std::get<Fourier>(f.form());
    y += fmt::format("fourier: {{constant: {}, cos: {}, sin: {}}}, reversal: {}}}\n", num(fo.constant),
                     list(fo.cos_terms), list(fo.sin_terms), num(fo.reversal));
  }
  return y;
}

std::string parameters_yaml(const Machine& m, const std::vector<ErrorName>& errors, const std::string& comment) {
  std::string y;
  std::size_t start = 0;
  while (start < comment.size()) {
    const auto end = comment.find('\n', start);
    y += "# " + comment.substr(start, end == std::string::npos ? std::string::npos : end - start) + "\n";
    if (end == std::string::npos) break;
    start = end + 1;
  }
  for (const auto& p : m.parameters())
    if (!std::isfinite(p.value) && std::find(errors.begin(), errors.end(), p.error) != errors.end())
      throw Error(fmt::format("parameter {} is {}; a parameter file holds finite values only", p.name, p.value));
  y += "mtcal_parameters: 1\nunits: {length: mm, angle: rad}\nerrors:\n";
  for (const auto& e : errors) y += error_yaml(m, e);
  return y;
}

std::string to_yaml(const Machine& m) {
  std::string y;
  y += fmt::format("mtcal_machine: {}\n", kFormatVersion);
  y += "name: " + quote(m.name) + "\n";
  if (!m.description.empty()) y += "description: " + quote(m.description) + "\n";
  y += "topology: " + m.topology.chain + "\n";
  y += "units: {length: mm, angle: rad}\n";
  y += "axes:\n";
  for (const auto& ax : m.axes) {
    y += fmt::format("  {}: {{direction: {}{}, point: {}", ax.letter, ax.direction_sign > 0 ? '+' : '-',
                     static_cast<char>('x' + ax.direction_axis), vec(ax.point));
    if (ax.travel) y += ", travel: " + list({ax.travel->min, ax.travel->max});
    y += "}\n";
  }
  y += fmt::format("tool: {{length: {}, spindle_point: {}, axis: +{}}}\n", num(m.tool.length),
                   vec(m.tool.spindle_point), static_cast<char>('x' + m.tool.tool_axis));
  y += "workpiece: {origin: " + vec(m.workpiece.origin) + "}\n";
  y += "errors:\n";
  for (const auto& ax : m.axes) {
    for (int c = 0; c < 6; ++c)
      if (ax.motion_given[c] || !ax.motion[c].is_zero())
        y += error_yaml(m, {ErrorKind::Motion, static_cast<Component>(c), ax.letter});
    for (int c = 0; c < 6; ++c)
      if (ax.allows_location(static_cast<Component>(c)) && ax.location[c] != 0.0)
        y += error_yaml(m, {ErrorKind::Location, static_cast<Component>(c), ax.letter});
  }
  for (char body : {'t', 'w'})
    for (int c = 0; c < 6; ++c)
      if ((body == 't' ? m.tool_mounting : m.workpiece_mounting)[c] != 0.0)
        y += error_yaml(m, {ErrorKind::Mounting, static_cast<Component>(c), body});
  return y;
}

}  // namespace mtcal
