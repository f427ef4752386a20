#include "mtcal/probing/sphere_probing.hpp"

#include <cmath>
#include <random>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {

std::vector<Point3> five_point_approaches() {
  return {Point3::UnitX(), -Point3::UnitX(), Point3::UnitY(), -Point3::UnitY(), -Point3::UnitZ()};
}

SphereCentre sphere_centre(const std::vector<ProbeContact>& contacts, const SphereProbing& probing,
                           const std::string& where) {
  if (!(probing.sphere_diameter > 0) || !(probing.stylus_diameter >= 0))
    throw InputError({where, 0, ""},
                     fmt::format("expected a sphere diameter > 0 and a stylus diameter >= 0, found {} and {}",
                                 probing.sphere_diameter, probing.stylus_diameter));
  if (contacts.size() < 3)
    throw InputError({where, 0, ""},
                     fmt::format("expected at least 3 contacts on the sphere, found {}", contacts.size()));
  const double reach = 0.5 * (probing.sphere_diameter + probing.stylus_diameter);  // tip centre to sphere centre
  std::vector<Point3> pts;
  Point3 hint = Point3::Zero();
  for (const auto& c : contacts) {
    pts.push_back(c.point);
    hint += c.point + reach * c.approach.normalized();
  }
  hint /= static_cast<double>(contacts.size());

  SphereCentre out;
  const auto lsq = fit_sphere_known_radius(pts, reach, hint);
  if (!lsq) {
    // No sphere of that size through the contacts: say so when a free sphere shows their size.
    if (const auto free = contacts.size() >= 4 ? fit_sphere(pts) : std::nullopt)
      throw InputError({where, 0, ""},
                       fmt::format("the contacts are not on a sphere of diameter {} mm probed with a {} mm stylus: "
                                   "their tip centres are {:.4f} mm from a centre, {:.4f} mm expected",
                                   probing.sphere_diameter, probing.stylus_diameter, free->radius, reach));
    throw InputError({where, 0, ""}, "the contacts do not determine a sphere (too few, coincident or on one line)");
  }
  out.least_squares = lsq->centre;
  out.rms = lsq->quality.rms;
  if (out.rms > probing.max_rms)
    throw InputError({where, 0, ""},
                     fmt::format("the contacts are not on a sphere of diameter {} mm probed with a {} mm stylus: "
                                 "rms distance {:.4f} mm (at most {} mm accepted)",
                                 probing.sphere_diameter, probing.stylus_diameter, out.rms, probing.max_rms));
  if (contacts.size() >= 4)
    if (const auto free = fit_sphere(pts)) out.effective_radius = free->radius;

  // The seed's 5-point protocol: one contact per approach +x, -x, +y, -y, -z.
  out.method = "least-squares";
  if (contacts.size() == 5) {
    const auto dirs = five_point_approaches();
    std::array<int, 5> which{-1, -1, -1, -1, -1};
    for (std::size_t c = 0; c < 5; ++c)
      for (std::size_t d = 0; d < 5; ++d)
        if (contacts[c].approach.normalized().dot(dirs[d]) > 0.99) which[d] = static_cast<int>(c);
    if (std::all_of(which.begin(), which.end(), [](int w) { return w >= 0; })) {
      Point3 sum = Point3::Zero();
      for (std::size_t drop = 0; drop < 4; ++drop) {  // keep -z (index 4), drop one of the others
        std::vector<Point3> subset;
        for (std::size_t d = 0; d < 5; ++d)
          if (d != drop) subset.push_back(contacts[static_cast<std::size_t>(which[d])].point);
        const auto f = fit_sphere_known_radius(subset, reach, out.least_squares);
        if (!f) throw InputError({where, 0, ""}, "a 4-point subset of the 5-point protocol is degenerate");
        out.subset_centres.push_back(f->centre);
        sum += f->centre;
      }
      out.five_point = sum / 4.0;
      out.method = "five-point";
    }
  }
  return out;
}

std::vector<ProbedIndexation> simulate_probing(const Machine& m, const ProbingSimulation& sim) {
  const auto k_rot = m.axis_index(sim.axis);
  if (!k_rot || m.axes[*k_rot].kind != AxisKind::Rotary || !m.axes[*k_rot].moves_workpiece)
    throw ModelError(std::string("probing simulation turns a rotary axis that carries the workpiece; '") + sim.axis +
                     "' is not one in " + m.topology.chain);
  int linear = 0;
  for (const auto& ax : m.axes) linear += ax.kind == AxisKind::Linear ? 1 : 0;
  if (linear != 3)
    throw ModelError("probing simulation needs three linear axes, " + m.topology.chain + " has " +
                     std::to_string(linear));
  const std::size_t n = m.axes.size();
  std::vector<double> base = sim.held.empty() ? std::vector<double>(n, 0.0) : sim.held;
  if (base.size() != n) throw ModelError(fmt::format("expected {} held joint values, found {}", n, base.size()));
  std::vector<std::size_t> lin;
  for (std::size_t k = 0; k < n; ++k)
    if (m.axes[k].kind == AxisKind::Linear) lin.push_back(k);

  const ErrorModel model(m);
  const double reach = 0.5 * (sim.probing.sphere_diameter + sim.probing.stylus_diameter);
  const Point3 sphere_w = sim.sphere - m.workpiece.origin;  // the sphere is fixed to the table
  std::mt19937_64 rng(sim.seed);
  std::normal_distribution<double> noise(0.0, 1.0);

  std::vector<ProbedIndexation> out;
  for (double angle : sim.angles) {
    std::vector<double> q = base;
    q[*k_rot] = angle;
    const Mat3 Rn = model.nominal_pose(q).R;  // tool (machine) directions in the workpiece frame
    ProbedIndexation ix{angle, {}};
    for (const Point3& a : five_point_approaches()) {
      const Point3 target = sphere_w - reach * (Rn * a);  // the tip touches the sphere
      // Newton on the linear joints: the actual tip reaches the target (nearly affine map).
      for (int it = 0; it < 30; ++it) {
        const Point3 f = model.actual_pose(q).t - target;
        if (f.norm() < 1e-12) break;
        Eigen::Matrix3d J;
        for (int c = 0; c < 3; ++c) {
          std::vector<double> qh = q;
          qh[lin[static_cast<std::size_t>(c)]] += 1e-3;
          J.col(c) = (model.actual_pose(qh).t - model.actual_pose(q).t) / 1e-3;
        }
        const Point3 step = J.fullPivLu().solve(f);
        for (int c = 0; c < 3; ++c) q[lin[static_cast<std::size_t>(c)]] -= step[c];
        if (it == 29) throw InputError({"simulation", 0, ""}, "the probe could not reach the sphere (no convergence)");
      }
      // What the controller shows: the nominal tool point with the rotary axes at zero, in
      // machine coordinates.
      std::vector<double> shown = q;
      for (std::size_t k = 0; k < n; ++k)
        if (m.axes[k].kind == AxisKind::Rotary) shown[k] = 0.0;
      Point3 p = model.nominal_pose(shown).t + m.workpiece.origin + sim.trigger_bias * a;
      if (sim.noise > 0)
        for (int c = 0; c < 3; ++c) p[c] += sim.noise * noise(rng);
      ix.contacts.push_back({p, a});
    }
    out.push_back(std::move(ix));
  }
  return out;
}

}  // namespace mtcal
