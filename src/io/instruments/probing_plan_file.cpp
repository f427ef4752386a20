// Probing plan and measurement CSV files (docs/identification.md): read into and written from the domain's ProbingPlan.
#include "mtcal/io/instruments/probing_plan_file.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "mtcal/io/text/csv.hpp"
#include "mtcal/io/system/files.hpp"
#include "mtcal/model/joints.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/util/parse.hpp"

namespace mtcal {

ProbingPlan parse_probing_csv(const Machine& m, const std::string& text, const std::string& source) {
  const TextTable t = parse_text_csv(text, source);
  for (char c : {'X', 'Y', 'Z'})
    if (!m.axis_index(c))
      throw InputError({source, 0, ""},
                       fmt::format("probing plans need linear axes X, Y and Z; {} has no {}", m.topology.chain, c));
  std::vector<std::string> allowed{"indexation", "feature", "kind", "x", "y",      "z",     "nx",    "ny",      "nz",
                                   "dirX",       "dirY",    "dirZ", "X", "Y",      "Z",     "radius", "angle", "along", "reading"};
  for (const auto& ax : m.axes)
    if (ax.kind == AxisKind::Rotary) allowed.push_back(std::string(1, ax.letter));
  for (const auto& c : t.columns)
    if (std::find(allowed.begin(), allowed.end(), c) == allowed.end())
      throw InputError(
          {source, t.header_line, c},
          fmt::format("unknown column '{}' (expected indexation, the rotary axes of {}, feature, kind, x, y, z, "
                      "nx, ny, nz, dirX, dirY, dirZ, for ballbars radius and angle, for lasers along and, in a "
                      "measurement, X, Y, Z and the ballbars' and lasers' reading)",
                      c, m.topology.chain));
  for (const char* c : {"indexation", "feature", "kind", "x", "y", "z"})
    if (t.column(c) < 0) throw InputError({source, t.header_line, ""}, fmt::format("missing column '{}'", c));
  const int readings = (t.column("X") >= 0) + (t.column("Y") >= 0) + (t.column("Z") >= 0);
  if (readings != 0 && readings != 3)
    throw InputError({source, t.header_line, ""}, "expected all of the readings X, Y, Z or none of them");
  if (t.rows.empty()) throw InputError({source, 0, ""}, "expected at least one probing, found none");

  ProbingPlan plan;
  plan.measured = readings == 3;
  plan.source = source;
  const std::size_t n = m.axes.size();
  for (std::size_t r = 0; r < t.rows.size(); ++r) {
    const int line = t.lines[r];
    auto cell = [&](const char* name) -> std::string {
      const int c = t.column(name);
      return c < 0 ? std::string() : t.rows[r][static_cast<std::size_t>(c)];
    };
    auto number = [&](const std::string& name, bool optional) {
      const int c = t.column(name);
      const std::string s = c < 0 ? std::string() : trim(t.rows[r][static_cast<std::size_t>(c)]);
      if (s.empty()) {
        if (optional) return 0.0;
        throw InputError({source, line, name}, "expected a number, found an empty cell");
      }
      const auto v = parse_number(s);
      if (!v) throw InputError({source, line, name}, "expected a finite number, found '" + printable(s) + "'");
      return *v;
    };
    ProbeFeature f;
    f.id = trim(cell("feature"));
    if (f.id.empty()) throw InputError({source, line, "feature"}, "expected a feature id, found an empty cell");
    const std::string kind = trim(cell("kind"));
    if (kind == "ball") {
      f.kind = ProbeFeature::Kind::Ball;
    } else if (kind == "facet") {
      f.kind = ProbeFeature::Kind::Facet;
    } else if (kind == "ballbar") {
      f.kind = ProbeFeature::Kind::Ballbar;
    } else if (kind == "laser") {
      f.kind = ProbeFeature::Kind::Laser;
    } else {
      throw InputError({source, line, "kind"},
                       "expected ball, facet, ballbar or laser, found '" + printable(kind) + "'");
    }
    const bool instrument = f.kind == ProbeFeature::Kind::Ballbar || f.kind == ProbeFeature::Kind::Laser;
    f.position = Vec3(number("x", false), number("y", false), number("z", false));
    const Vec3 nrm(number("nx", true), number("ny", true), number("nz", true));
    if (f.kind == ProbeFeature::Kind::Facet || f.kind == ProbeFeature::Kind::Laser) {
      if (std::abs(nrm.norm() - 1.0) > 1e-6)
        throw InputError({source, line, "nx"},
                         fmt::format("expected a {}'s unit {}, found length {:g}", kind,
                                     f.kind == ProbeFeature::Kind::Laser ? "beam direction" : "normal", nrm.norm()));
      f.normal = nrm.normalized();  // accepted within 1e-6 of unit length; used exactly unit
    } else if (f.kind == ProbeFeature::Kind::Ballbar) {
      f.normal = nrm;
      try {
        ballbar_plane(f);
      } catch (const InputError&) {
        throw InputError({source, line, "nx"},
                         fmt::format("expected a ballbar's plane normal 0,0,1 (XY), 1,0,0 (YZ) or 0,1,0 (ZX), found "
                                     "{:g},{:g},{:g}",
                                     nrm.x(), nrm.y(), nrm.z()));
      }
      f.radius = number("radius", false);
      if (!(f.radius > 0)) throw InputError({source, line, "radius"}, fmt::format("expected a bar length > 0 mm, found {:g}", f.radius));
    } else if (!nrm.isZero(0.0)) {
      throw InputError({source, line, "nx"}, "a ball has no normal: leave nx, ny, nz empty or 0");
    }
    std::size_t fi = 0;
    if (const auto known = plan.feature_index(f.id)) {
      const auto& g = plan.features[*known];
      if (g.kind != f.kind || g.position != f.position || g.normal != f.normal || g.radius != f.radius)
        throw InputError({source, line, "feature"},
                         "feature '" + printable(f.id) + "' has a different kind or geometry than on an earlier row");
      fi = *known;
    } else {
      fi = plan.features.size();
      plan.features.push_back(f);
    }
    ProbingRecord rec;
    rec.line = line;
    rec.feature = fi;
    const double idx = number("indexation", false);
    if (idx != std::floor(idx) || std::abs(idx) > 1e9)
      throw InputError({source, line, "indexation"}, fmt::format("expected a whole number, found {:g}", idx));
    rec.indexation = static_cast<int>(idx);
    rec.q.assign(n, 0.0);
    rec.dir.assign(n, 0);
    if (f.kind == ProbeFeature::Kind::Ballbar) rec.at = number("angle", false) * std::numbers::pi / 180;
    if (f.kind == ProbeFeature::Kind::Laser) rec.at = number("along", false);
    if (instrument && plan.measured) rec.reading = number("reading", false);
    for (std::size_t k = 0; k < n; ++k) {
      const Axis& ax = m.axes[k];
      const std::string letter(1, ax.letter);
      if (ax.kind == AxisKind::Rotary) {
        rec.q[k] = number(letter, true) * joint_unit_factor(ax);
        continue;
      }
      if (plan.measured) rec.q[k] = number(letter, false);
      const double d = number("dir" + letter, true);
      if (d != 0 && d != 1 && d != -1)
        throw InputError({source, line, "dir" + letter}, fmt::format("expected -1, 0 or +1, found {:g}", d));
      if (f.kind == ProbeFeature::Kind::Ball && d != 0)
        throw InputError({source, line, "dir" + letter},
                         "a ball centre has no direction of motion: leave dir empty or 0");
      rec.dir[k] = static_cast<std::int8_t>(d);
    }
    check_joints(m, rec.q, fmt::format("{}:{}", source, line), false);
    plan.records.push_back(std::move(rec));
  }
  return plan;
}

ProbingPlan read_probing_csv(const Machine& m, const std::string& path) {
  return parse_probing_csv(m, read_text_file(path, "probing file"), path);
}

std::string probing_csv(const Machine& m, const ProbingPlan& plan, const std::string& comment) {
  std::string out;
  if (!comment.empty()) out += "# " + comment + "\n";
  out += "indexation";
  for (const auto& ax : m.axes)
    if (ax.kind == AxisKind::Rotary) out += fmt::format(",{}", ax.letter);
  out += ",feature,kind,x,y,z,nx,ny,nz,dirX,dirY,dirZ";
  if (plan.measured) out += ",X,Y,Z";
  // The instruments' columns only where the plan has ballbars or lasers: ball and facet files as before.
  const bool instruments = std::any_of(plan.features.begin(), plan.features.end(), [](const ProbeFeature& f) {
    return f.kind == ProbeFeature::Kind::Ballbar || f.kind == ProbeFeature::Kind::Laser;
  });
  if (instruments) out += plan.measured ? ",radius,angle,along,reading" : ",radius,angle,along";
  out += "\n";
  const std::size_t ix = *m.axis_index('X'), iy = *m.axis_index('Y'), iz = *m.axis_index('Z');
  for (const auto& r : plan.records) {
    const auto& f = plan.features[r.feature];
    out += fmt::format("{}", r.indexation);
    for (std::size_t k = 0; k < m.axes.size(); ++k)
      if (m.axes[k].kind == AxisKind::Rotary) out += fmt::format(",{:.12g}", to_user_units(m.axes[k], r.q[k]));
    out += fmt::format(",{},{},{:.12g},{:.12g},{:.12g}", f.id, feature_kind_name(f.kind), f.position.x(),
                       f.position.y(), f.position.z());
    if (f.kind != ProbeFeature::Kind::Ball)
      out += fmt::format(",{:.12g},{:.12g},{:.12g}", f.normal.x(), f.normal.y(), f.normal.z());
    else
      out += ",,,";
    out += fmt::format(",{},{},{}", r.dir[ix], r.dir[iy], r.dir[iz]);
    // Shortest round-trip form: a written simulation reads back bit for bit.
    if (plan.measured) out += fmt::format(",{},{},{}", r.q[ix], r.q[iy], r.q[iz]);
    if (instruments) {
      if (f.kind == ProbeFeature::Kind::Ballbar)
        out += fmt::format(",{:.12g},{},", f.radius, r.at * 180 / std::numbers::pi);
      else if (f.kind == ProbeFeature::Kind::Laser)
        out += fmt::format(",,,{}", r.at);
      else
        out += ",,,";
      if (plan.measured) out += f.kind == ProbeFeature::Kind::Ballbar || f.kind == ProbeFeature::Kind::Laser
                                    ? fmt::format(",{}", r.reading)
                                    : ",";
    }
    out += "\n";
  }
  return out;
}

void write_probing_csv(const std::string& path, const Machine& m, const ProbingPlan& plan, const std::string& comment) {
  write_file_atomically(path, probing_csv(m, plan, comment));
}

ScaleBar parse_scale_bar(const std::string& spec, const std::string& where) {
  const auto c1 = spec.find(':'), c2 = c1 == std::string::npos ? c1 : spec.find(':', c1 + 1);
  if (c2 == std::string::npos || spec.find(':', c2 + 1) != std::string::npos)
    throw InputError({where, 0, spec},
                     "expected BALL:BALL:LENGTH (mm), e.g. 1:2:304.8, found '" + printable(spec) + "'");
  ScaleBar s{trim(spec.substr(0, c1)), trim(spec.substr(c1 + 1, c2 - c1 - 1)), 0.0, where};
  const auto len = parse_number(spec.substr(c2 + 1));
  if (!len || *len <= 0)
    throw InputError({where, 0, spec}, "expected a length > 0 mm, found '" + spec.substr(c2 + 1) + "'");
  s.length = *len;
  return s;
}

}  // namespace mtcal
