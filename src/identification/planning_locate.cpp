// The first coarse touch: the locating cycle's touches, and the spheres fitted to what it logged.
#include "mtcal/identification/sphere_locate.hpp"

#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "mtcal/fitting/fit.hpp"
#include "mtcal/identification/identification.hpp"
#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/util/errors.hpp"
#include "planning_common.hpp"

namespace mtcal {

using namespace planning_detail;

namespace {

// Unit direction in axis-value space (X, Y, Z values) that moves the tool along machine axis
// `machine_axis` by +1 (as probe_touches takes it).
Vec3 axis_direction(const Machine& m, const std::vector<std::size_t>& lin, int machine_axis) {
  Vec3 u = Vec3::Zero();
  for (std::size_t k = 0; k < lin.size() && k < 3; ++k)
    if (m.axes[lin[k]].direction_axis == machine_axis) u[static_cast<Eigen::Index>(k)] = m.axes[lin[k]].direction_sign;
  return u;
}

double contact_radius(const ProbeCycle& c) { return (c.ball_diameter + c.tip_diameter) / 2; }

}  // namespace

ProbingPlan locate_plan(const Machine& m, const ProbingPlan& artefact, std::span<const double> at) {
  if (at.size() != m.axes.size())
    throw InputError({m.source, 0, ""}, fmt::format("expected a configuration of {} axes where the balls are located, "
                                                    "found {}",
                                                    m.axes.size(), at.size()));
  ProbingPlan p;
  p.features = artefact.features;
  p.source = artefact.source;
  for (std::size_t f = 0; f < artefact.features.size(); ++f) {
    if (artefact.features[f].kind != ProbeFeature::Kind::Ball) continue;
    ProbingRecord r;
    r.indexation = static_cast<int>(p.records.size()) + 1;
    r.q.assign(at.begin(), at.end());
    r.dir.assign(m.axes.size(), 0);
    r.feature = f;
    p.records.push_back(std::move(r));
  }
  if (p.records.empty())
    throw InputError({artefact.source, 0, "kind"}, "expected a ball to locate, found none (facets are not located)");
  return plan_targets(m, p);
}

std::vector<ProbeTouch> locate_touches(const Machine& m, const ProbingPlan& plan, const ProbeCycle& c,
                                       const LocateOptions& o) {
  probe_touches(m, ProbingPlan{}, c);  // the cycle's checks (diameters, approach, overtravel, clearance)
  const double rho = contact_radius(c);
  if (!(o.within > 0) || !(o.within <= rho / 2))
    throw InputError({"locating distance", 0, ""},
                     fmt::format("expected the sphere within (0, {:g}] mm of its rough position (half the contact "
                                 "radius, (ball + tip) / 2 = {:g} mm), found {:g}",
                                 rho / 2, rho, o.within));
  const auto lin = linear_axes(m);
  if (lin.size() != 3) throw InputError({m.source, 0, ""}, "a probing program needs the three linear axes X, Y, Z");
  const int t = m.tool.tool_axis;
  const Vec3 up = axis_direction(m, lin, t), a = axis_direction(m, lin, (t + 1) % 3), b = axis_direction(m, lin, (t + 2) % 3);
  const double u = o.within, h = (rho - u) / 2, s = std::sqrt(0.5);
  struct Way {
    Vec3 dir;
    double height;
  };
  const std::vector<Way> ways{{up, 0.0},          {a, 0.0},          {-a, 0.0},          {b, 0.0},         {-b, 0.0},
                              {s * (a + b), h},   {s * (b - a), h},  {s * (-a - b), h},  {s * (a - b), h}};
  std::vector<ProbeTouch> out;
  for (std::size_t i = 0; i < plan.records.size(); ++i) {
    const ProbingRecord& r = plan.records[i];
    const ProbeFeature& f = plan.features[r.feature];
    if (f.kind != ProbeFeature::Kind::Ball)
      throw InputError({plan.source, r.line, "kind"}, fmt::format("a locating program locates balls, not a {}",
                                                                  feature_kind_name(f.kind)));
    const Vec3 c0(r.q[lin[0]], r.q[lin[1]], r.q[lin[2]]);
    auto at = [&](const Vec3& p) {
      std::vector<double> q = r.q;
      for (std::size_t k = 0; k < 3; ++k) q[lin[k]] = p[static_cast<Eigen::Index>(k)];
      for (std::size_t k = 0; k < 3; ++k) {
        const Axis& ax = m.axes[lin[k]];
        if (ax.travel && (q[lin[k]] < ax.travel->min || q[lin[k]] > ax.travel->max))
          throw InputError({plan.source, r.line, std::string(1, ax.letter)},
                           fmt::format("locating ball {}: a move reaches {} = {:.3f} mm, outside its travel [{:g}, "
                                       "{:g}]; locate it at other rotary values",
                                       f.id, ax.letter, q[lin[k]], ax.travel->min, ax.travel->max));
      }
      return q;
    };
    for (const Way& w : ways) {
      // Along the move p(t) = c0 + height up + t dir the contact with a sphere whose centre is within
      // u of c0 lies between t = -u + sqrt(rho^2 - (height + u)^2) and t = u + rho.
      const Vec3 base = c0 + w.height * up;
      const double nearest = -u + std::sqrt(rho * rho - (w.height + u) * (w.height + u));
      out.push_back({i, at(base + (rho + u + c.approach) * w.dir), at(base + (nearest - c.overtravel) * w.dir),
                     at(base + std::sqrt(rho * rho - w.height * w.height) * w.dir)});
    }
  }
  return out;
}

LocateResult locate_spheres(const Machine& m, const ProbingPlan& plan, const ProbeCycle& c, const LocateOptions& o,
                            const std::vector<LoggedContact>& contacts, const std::string& log_source) {
  const auto touches = locate_touches(m, plan, c, o);
  const auto lin = linear_axes(m);
  const std::string source = contacts.empty() ? log_source : contacts.front().source;
  const std::size_t per_ball = plan.records.empty() ? 0 : touches.size() / plan.records.size();
  auto ball_id = [&](std::size_t k) { return plan.features[plan.records[touches[k].record].feature].id; };
  ContactWording w;
  w.program = "the locating program";
  w.moves = fmt::format("the locating program's probing moves for {} balls", plan.records.size());
  w.touch = [&](std::size_t k) {
    return fmt::format("touch {} of {} locating ball {}", k - touches[k].record * per_ball + 1, per_ball, ball_id(k));
  };
  w.owner = [&](std::size_t k) { return "locating ball " + ball_id(k); };
  if (contacts.size() < touches.size()) {
    const Vec3& rough = plan.features[plan.records[touches[contacts.size()].record].feature].position;
    w.missing_tail = fmt::format("; no sphere found within {:g} mm of the rough position {:g},{:g},{:g}", o.within,
                                 rough.x(), rough.y(), rough.z());
  }
  w.on_move = 0.05;
  const std::vector<Vec3> at = match_contacts(m, plan, touches, contacts, w, log_source);
  const ErrorModel nominal(nominal_of(m));
  const double rho = contact_radius(c);
  LocateResult out;
  out.artefact = plan;
  std::vector<std::vector<Point3>> ball(plan.records.size());
  for (std::size_t i = 0; i < touches.size(); ++i) ball[touches[i].record].push_back(at[i]);
  for (std::size_t i = 0; i < plan.records.size(); ++i) {
    const ProbingRecord& r = plan.records[i];
    ProbeFeature& f = out.artefact.features[r.feature];
    const auto fit = fit_sphere(ball[i]);
    const std::string where = fmt::format("the {} touches of locating ball {}", ball[i].size(), f.id);
    if (!fit) throw InputError({source, 0, ""}, where + " do not define a sphere: no sphere found");
    double ss = 0;
    for (const auto& p : ball[i]) ss += std::pow((p - fit->centre).norm() - fit->radius, 2);
    const double rms = std::sqrt(ss / static_cast<double>(ball[i].size()));
    if (std::abs(fit->radius - rho) > o.radius_tolerance)
      throw InputError({source, 0, ""},
                       fmt::format("{} fit a sphere of diameter {:.4f} mm (tip centres: {:.4f} mm), not the ball's "
                                   "{:g} mm (+ tip {:g} mm = {:g} mm) within {:g} mm: no sphere of the ball's "
                                   "diameter found",
                                   where, 2 * fit->radius - c.tip_diameter, 2 * fit->radius, c.ball_diameter,
                                   c.tip_diameter, 2 * rho, 2 * o.radius_tolerance));
    if (rms > o.fit_tolerance)
      throw InputError({source, 0, ""},
                       fmt::format("{} are not on one sphere: RMS {:.4f} mm about the fitted one, more than {:g} mm "
                                   "(something else touched?)",
                                   where, rms, o.fit_tolerance));
    std::vector<double> q = r.q;
    for (std::size_t k = 0; k < 3; ++k) q[lin[k]] = fit->centre[static_cast<Eigen::Index>(k)];
    LocatedSphere ls;
    ls.id = f.id;
    ls.rough = f.position;
    ls.centre = nominal.nominal_pose(q).t;
    ls.offset = (ls.centre - ls.rough).norm();
    ls.contact_radius = fit->radius;
    ls.ball_diameter = 2 * fit->radius - c.tip_diameter;
    ls.rms = rms;
    ls.contacts = ball[i].size();
    ls.beyond = ls.offset > o.within;
    f.position = ls.centre;
    out.artefact.records[i].q = q;
    out.spheres.push_back(std::move(ls));
  }
  out.artefact.measured = false;
  return out;
}

}  // namespace mtcal
