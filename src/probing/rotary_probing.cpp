// Rotary-axis location test from sphere probing (probing/rotary_probing.hpp).
#include "mtcal/probing/rotary_probing.hpp"
#include "mtcal/util/units.hpp"

#include <cmath>

#include <Eigen/Geometry>
#include <numbers>
#include <utility>

#include <fmt/format.h>

#include "mtcal/fitting/fit.hpp"
#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {
namespace {


}  // namespace

IndexedCentres centres_from_contacts(const ContactSet& set, const SphereProbing& probing) {
  // Consecutive contacts with the same angle form one indexation. An angle met again later is a
  // second probing of that position: fitted on its own (never merged into the first fit), its
  // centre then averaged with the first by merge_wrapped_centres.
  struct Group {
    double angle;
    int line;
    std::vector<ProbeContact> contacts;
  };
  std::vector<Group> groups;
  const std::string axis(1, set.axis);
  for (const auto& c : set.contacts) {
    if (groups.empty() || groups.back().angle != c.angle_deg) groups.push_back({c.angle_deg, c.line, {}});
    groups.back().contacts.push_back(c.contact);
  }
  IndexedCentres out;
  out.source = set.source;
  out.method.clear();
  for (const auto& g : groups) {
    const double a = g.angle;
    const auto sc = sphere_centre(g.contacts, probing, fmt::format("{}:{} ({}={:g})", set.source, g.line, axis, a));
    if (out.method.empty()) out.method = sc.method;
    if (out.method != sc.method) out.method = "mixed";
    out.centres.push_back({a * kRadPerDeg, sc.centre()});
    out.fits.push_back(sc);
  }
  return out;
}

ContactSet contacts_from_log(const Machine& m, char axis, const std::vector<LoggedAxisValues>& log,
                             const std::string& source) {
  const auto k = m.axis_index(axis);
  if (!k || m.axes[*k].kind != AxisKind::Rotary)
    throw ModelError(fmt::format("a rotary-axis test turns a rotary axis; '{}' is not one in {}", axis, m.topology.chain));
  if (log.empty()) throw InputError({source, 0, ""}, fmt::format("expected contacts at indexations of {}, found none", axis));
  const ErrorModel model(m);
  ContactSet set;
  set.source = source;
  set.axis = axis;
  for (const auto& c : log) {
    if (c.q.size() != m.axes.size())
      throw ModelError(fmt::format("expected {} axis values a contact, found {}", m.axes.size(), c.q.size()));
    if (!std::isfinite(c.q[*k]))
      throw InputError({source, c.line, std::string(1, axis)}, fmt::format("expected the value of {}, found none", axis));
    std::vector<double> q = c.q;
    for (std::size_t a = 0; a < q.size(); ++a) {
      if (m.axes[a].kind == AxisKind::Rotary) {
        // The test turns one axis with the others held: a log that turns another is a different test.
        if (a != *k && std::isfinite(q[a]) && std::isfinite(log.front().q[a]) &&
            std::abs(q[a] - log.front().q[a]) > 1e-9)
          throw InputError({source, c.line, std::string(1, m.axes[a].letter)},
                           fmt::format("expected {} held at {:g} deg (line {}) while {} turns, found {:g} deg",
                                       m.axes[a].letter, log.front().q[a] / kRadPerDeg, log.front().line, axis, q[a] / kRadPerDeg));
        q[a] = 0.0;
      } else if (!std::isfinite(q[a])) {
        throw InputError({source, c.line, std::string(1, m.axes[a].letter)},
                         fmt::format("expected the value of {}, found none", m.axes[a].letter));
      }
    }
    IndexedContact ic;
    ic.angle_deg = c.q[*k] / kRadPerDeg;
    ic.line = c.line;
    ic.contact.point = model.nominal_pose(q).t + m.workpiece.origin;
    set.contacts.push_back(ic);
  }
  // Approach directions per indexation (consecutive contacts at one angle, as centres_from_contacts
  // groups them): towards the centre of the free sphere through them.
  for (std::size_t i = 0; i < set.contacts.size();) {
    std::size_t j = i;
    std::vector<Point3> pts;
    while (j < set.contacts.size() && set.contacts[j].angle_deg == set.contacts[i].angle_deg)
      pts.push_back(set.contacts[j++].contact.point);
    if (const auto free = pts.size() >= 4 ? fit_sphere(pts) : std::nullopt)
      for (std::size_t c = i; c < j; ++c) {
        const Point3 d = free->centre - set.contacts[c].contact.point;
        if (d.norm() > 0) set.contacts[c].contact.approach = d.normalized();
      }
    i = j;
  }
  return set;
}

InstrumentFrame frame_from_angles(double rx, double ry, double rz, const Point3& translation) {
  InstrumentFrame f;
  f.rotation = (Eigen::AngleAxisd(rz, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(ry, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(rx, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  f.translation = translation;
  return f;
}

void apply_frame(IndexedCentres& centres, const InstrumentFrame& frame) {
  for (auto& c : centres.centres) c.centre = frame.rotation * c.centre + frame.translation;
  for (auto& f : centres.fits) {
    f.least_squares = frame.rotation * f.least_squares + frame.translation;
    if (f.five_point) f.five_point = frame.rotation * *f.five_point + frame.translation;
    for (auto& c : f.subset_centres) c = frame.rotation * c + frame.translation;
  }
}

std::vector<std::string> merge_wrapped_centres(IndexedCentres& in) {
  constexpr double turn = 2 * std::numbers::pi;
  auto reduce = [&](double a) {
    double r = std::fmod(a, turn);
    if (r < 0) r += turn;
    return r > turn - 1e-9 ? 0.0 : r;
  };
  std::vector<std::string> notes;
  std::vector<std::vector<std::size_t>> groups;
  std::vector<double> reduced;
  for (std::size_t i = 0; i < in.centres.size(); ++i) {
    const double r = reduce(in.centres[i].angle);
    std::size_t g = 0;
    while (g < reduced.size() && std::abs(reduced[g] - r) > 1e-9) ++g;
    if (g == reduced.size()) reduced.push_back(r), groups.emplace_back();
    groups[g].push_back(i);
  }
  if (groups.size() == in.centres.size()) return notes;
  IndexedCentres out;
  out.source = in.source;
  out.method = in.method;
  for (const auto& g : groups) {
    std::size_t rep = g[0];
    Point3 sum = Point3::Zero();
    std::string angles;
    for (std::size_t i : g) {
      sum += in.centres[i].centre;
      if (std::abs(in.centres[i].angle) < std::abs(in.centres[rep].angle)) rep = i;
      angles += fmt::format("{}{:g}", angles.empty() ? "" : ", ", in.centres[i].angle / kRadPerDeg);
    }
    out.centres.push_back({in.centres[rep].angle, sum / static_cast<double>(g.size())});
    if (!in.fits.empty()) out.fits.push_back(in.fits[rep]);
    if (g.size() > 1)
      notes.push_back(
          fmt::format("indexations at {} deg are one position of the axis: their centres are averaged "
                      "(spread {:.3g} mm)",
                      angles, [&] {
                        double d = 0;
                        for (std::size_t i : g)
                          d = std::max(d, (in.centres[i].centre - sum / static_cast<double>(g.size())).norm());
                        return d;
                      }()));
  }
  in = std::move(out);
  return notes;
}

MeasuredAxisLine measure_axis_line(const NominalRotaryAxis& axis, const std::vector<MeasuredCentre>& centres) {
  std::vector<Point3> pts;
  for (const auto& c : centres) pts.push_back(c.centre);
  const auto fit = pts.size() >= 3 ? fit_circle(pts) : std::nullopt;
  if (!fit)
    throw InputError({"centres", 0, ""}, "the sphere centres lie on one line (or coincide): no circle, no axis");
  MeasuredAxisLine l;
  const int k = axis.direction_axis;
  Point3 n = fit->normal.normalized();
  if (std::abs(n[k]) > 1e-12) {
    if (n[k] < 0) n = -n;
  } else {
    int m = 0;
    n.cwiseAbs().maxCoeff(&m);
    if (n[m] < 0) n = -n;
  }
  l.direction = n;
  // The line's point nearest the nominal point.
  l.point = fit->centre + (axis.point - fit->centre).dot(n) * n;
  l.radius = fit->radius;
  l.tilt = std::atan2(std::hypot(n[(k + 1) % 3], n[(k + 2) % 3]), std::abs(n[k]));
  l.rms = fit->quality.sigma;
  return l;
}

const RotaryEstimate& RotaryAxisResult::best() const {
  if (least_squares) return *least_squares;
  if (triples) return *triples;
  throw Error("no estimate of the rotary axis");
}

RotaryAxisResult locate_rotary_axis(const NominalRotaryAxis& axis, IndexedCentres centres,
                                    const RotaryAxisOptions& options) {
  if (!options.triples && !options.least_squares) throw Error("expected at least one estimator of the rotary axis");
  if (options.triples && centres.centres.size() > kMaxTriplesCentres)
    throw InputError({centres.source, 0, ""},
                     fmt::format("{} indexations are more than the triples estimator takes (at most {})",
                                 centres.centres.size(), kMaxTriplesCentres));
  RotaryAxisResult r;
  r.axis = axis;
  r.centres = std::move(centres);
  r.notes = merge_wrapped_centres(r.centres);
  r.reject_sigma = options.triples_options.reject_sigma;
  if (r.centres.centres.size() < 3)
    throw InputError({r.centres.source, 0, ""},
                     fmt::format("expected at least 3 positions of the axis, found {}{}", r.centres.centres.size(),
                                 r.notes.empty() ? "" : " (after merging angles a turn apart)"));
  r.line = measure_axis_line(axis, r.centres.centres);
  if (r.line.tilt > options.max_tilt) {
    r.located = false;
    r.notes.push_back(fmt::format(
        "the measured axis is {:.2f} deg from the nominal direction of {}: ISO 230-7 location errors are small "
        "angles about the nominal line, so only the measured line is given (give the instrument's frame if its "
        "axes are not the machine's, or check the axis letter)",
        r.line.tilt / kRadPerDeg, axis.letter));
    return r;
  }
  if (options.least_squares) r.least_squares = estimate_by_least_squares(axis, r.centres.centres);
  if (options.triples) r.triples = estimate_by_triples(axis, r.centres.centres, options.triples_options);
  const auto names = rotary_quantity_names(axis.letter);
  for (const RotaryEstimate* e : {r.least_squares ? static_cast<const RotaryEstimate*>(&*r.least_squares) : nullptr,
                                  r.triples ? static_cast<const RotaryEstimate*>(&*r.triples) : nullptr}) {
    if (!e) continue;
    for (std::size_t q = 0; q < kRotaryQuantities; ++q)
      if (!std::isfinite(e->value[q]))
        throw InputError({"centres", 0, names[q]},
                         std::string("the estimate is not finite: are the centres of axis ") + axis.letter + "?");
  }
  return r;
}

}  // namespace mtcal
