// Planning a probing measurement: candidates within reach, the subset to estimate, prediction, VA sensitivity.
#include "mtcal/identification/planning.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <set>
#include <tuple>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <fmt/format.h>

#include "mtcal/evaluation/volumetric.hpp"
#include "mtcal/fitting/least_squares.hpp"
#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/util/errors.hpp"
#include "probing_model.hpp"
#include "planning_common.hpp"


namespace mtcal {

namespace {

using namespace planning_detail;  // the shared helpers of the planning units


std::string violation(const ErrorModel& nominal, const ProbingPlan& plan, const ProbingRecord& r,
                      const ProbeReach& reach) {
  const Machine& m = nominal.machine();
  for (std::size_t k = 0; k < m.axes.size(); ++k) {
    const auto& t = m.axes[k].travel;
    if (t && (r.q[k] < t->min - 1e-9 || r.q[k] > t->max + 1e-9)) return "travel";
  }
  const ProbeFeature& f = plan.features[r.feature];
  if (f.kind == ProbeFeature::Kind::Ballbar || f.kind == ProbeFeature::Kind::Laser) return "";  // no probe
  const Vec3 a = tool_axis(nominal, r);
  if (f.kind == ProbeFeature::Kind::Ball) {
    const double tilt = std::acos(std::clamp(a.dot(-reach.stem.normalized()), -1.0, 1.0)) * 180.0 / std::numbers::pi;
    if (tilt > reach.max_tilt_deg + 1e-9) return "stem";
  } else if (a.dot(f.normal) < -1e-9) {
    return "facet side";
  }
  // The holder: a disc of holder_radius centred stylus_length along a from the tip, at right angles
  // to a; its lowest point is sin(angle to z) * radius below its centre. Balls only: they stand
  // on the table, whose plane the rule takes as unbounded; facets are faces of the artefact or
  // the pallet, whose edges the probe reaches over.
  if (f.kind != ProbeFeature::Kind::Ball) return "";
  const double lowest = f.position.z() + reach.stylus_length * a.z() -
                        reach.holder_radius * std::sqrt(std::max(0.0, 1.0 - a.z() * a.z()));
  if (lowest < reach.table_z - 1e-9) return "table";
  return "";
}

bool is_instrument(ProbeFeature::Kind k) { return k == ProbeFeature::Kind::Ballbar || k == ProbeFeature::Kind::Laser; }

// The rotary axes' values of the instruments' records: each axis at the value nearest 0 within
// its travel.
std::vector<double> instrument_rotary(const Machine& m) {
  std::vector<double> q(m.axes.size(), 0.0);
  for (std::size_t k : rotary_axes(m))
    if (const auto& t = m.axes[k].travel) q[k] = std::clamp(0.0, t->min, t->max);
  return q;
}

// The box of the nominal tool point (workpiece frame) over the linear axes' travels at the rotary
// values of q: the corners' extremes (the linear axes move the tool point along straight lines).
std::pair<Vec3, Vec3> tool_point_box(const Machine& m, const ErrorModel& nominal, std::vector<double> q,
                                     const std::string& where) {
  const auto lin = linear_axes(m);
  for (std::size_t k : lin)
    if (!m.axes[k].travel)
      throw InputError({where, 0, std::string(1, m.axes[k].letter)},
                       fmt::format("ballbar circles and laser lines are laid out in the travels; axis {} has none",
                                   m.axes[k].letter));
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (std::size_t c = 0; c < (std::size_t{1} << lin.size()); ++c) {
    for (std::size_t j = 0; j < lin.size(); ++j)
      q[lin[j]] = (c >> j) & 1 ? m.axes[lin[j]].travel->max : m.axes[lin[j]].travel->min;
    const Vec3 p = nominal.nominal_pose(q).t;
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  return {lo, hi};
}

constexpr const char* kPlaneNames[3] = {"YZ", "ZX", "XY"};  // by the index of the normal's axis

// The instruments' candidate features and records (nominal targets), removing circles and lines
// with a reading outside the travel; `removed` counts those.
ProbingPlan instrument_candidates(const Machine& m, const ErrorModel& nominal, const std::vector<ProbeFeature>& taken,
                                  const InstrumentCandidates& o, int indexation, std::size_t& considered,
                                  std::size_t& removed) {
  ProbingPlan out;
  out.source = "the candidate configurations";
  if (o.ballbar_radii.empty() && o.laser_axes.empty()) return out;
  const std::vector<double> q0 = instrument_rotary(m);
  const auto lin = linear_axes(m);
  if (!o.ballbar_radii.empty() && o.ballbar_points < 4)
    throw InputError({o.ballbar_source, 0, ""}, fmt::format("expected at least 4 readings a circle, found {}", o.ballbar_points));
  if (!o.laser_axes.empty() && o.laser_points < 2)
    throw InputError({o.laser_source, 0, ""}, fmt::format("expected at least 2 targets a line, found {}", o.laser_points));
  if (!o.ballbar_radii.empty() && o.pivots_per_axis < 1)
    throw InputError({o.ballbar_source, 0, ""}, "expected at least one pivot per axis of a plane");
  const auto box = tool_point_box(m, nominal, q0, o.ballbar_radii.empty() ? o.laser_source : o.ballbar_source);
  const Vec3 lo = box.first, hi = box.second;
  const Vec3 mid = (lo + hi) / 2, size = hi - lo;
  auto add = [&](const ProbeFeature& f, const std::vector<double>& at) {
    if (std::any_of(taken.begin(), taken.end(), [&](const ProbeFeature& t) { return t.id == f.id; }))
      throw InputError({f.kind == ProbeFeature::Kind::Laser ? o.laser_source : o.ballbar_source, 0, f.id},
                       fmt::format("the candidate {} id '{}' is already a feature of the artefact",
                                   feature_kind_name(f.kind), f.id));
    out.features.push_back(f);
    for (double a : at) {
      ProbingRecord r;
      r.indexation = indexation;
      r.q = q0;
      r.dir.assign(m.axes.size(), 0);
      r.feature = out.features.size() - 1;
      r.at = a;
      out.records.push_back(r);
    }
  };
  for (double R : o.ballbar_radii) {
    const std::string value = fmt::format("{:g}", R);
    if (!(R > 0) || !std::isfinite(R))
      throw InputError({o.ballbar_source, 0, value}, fmt::format("expected a radius > 0 mm, found {}", value));
    std::vector<double> at;
    for (std::size_t i = 0; i < o.ballbar_points; ++i)
      at.push_back(2 * std::numbers::pi * static_cast<double>(i) / static_cast<double>(o.ballbar_points));
    bool fits = false;
    for (int k : {2, 0, 1}) {  // XY, YZ, ZX
      const int a = (k + 1) % 3, b = (k + 2) % 3;
      if (size[a] < 2 * R - 1e-9 || size[b] < 2 * R - 1e-9) continue;
      fits = true;
      auto values = [&](int axis) {
        std::vector<double> v;
        const double first = lo[axis] + R, last = hi[axis] - R;
        const std::size_t n = last - first < 1e-9 ? 1 : o.pivots_per_axis;
        if (n == 1) return std::vector<double>{mid[axis]};
        for (std::size_t i = 0; i < n; ++i)
          v.push_back(first + (last - first) * static_cast<double>(i) / static_cast<double>(n - 1));
        return v;
      };
      std::size_t n = 0;
      for (double vb : values(b))
        for (double va : values(a)) {
          ProbeFeature f;
          f.kind = ProbeFeature::Kind::Ballbar;
          f.id = fmt::format("BB{:g}{}{}", R, kPlaneNames[k], ++n);
          f.position = mid;
          f.position[a] = va;
          f.position[b] = vb;
          f.normal = Vec3::Unit(k);
          f.radius = R;
          add(f, at);
          ++considered;
        }
    }
    if (!fits)
      throw InputError({o.ballbar_source, 0, value},
                       fmt::format("a circle of radius {} mm needs 2 x {} mm of the tool point's travel along both "
                                   "axes of its plane; the travel is {:.6g} mm along x, {:.6g} along y, {:.6g} along z: "
                                   "no plane XY, YZ or ZX holds it",
                                   value, value, size.x(), size.y(), size.z()));
  }
  for (const auto& name : o.laser_axes) {
    std::size_t k = m.axes.size();
    for (std::size_t j : lin)
      if (name.size() == 1 && std::toupper(static_cast<unsigned char>(name[0])) == m.axes[j].letter) k = j;
    if (k == m.axes.size()) {
      std::string letters;
      for (std::size_t j : lin) letters += fmt::format("{}{}", letters.empty() ? "" : ", ", m.axes[j].letter);
      throw InputError({o.laser_source, 0, name},
                       fmt::format("expected a linear axis of the machine ({}), found '{}'", letters, printable(name)));
    }
    // The beam along the axis' motion of the tool point (workpiece frame), through the box's middle.
    std::vector<double> qa = q0, qb = q0;
    for (std::size_t j : lin) qa[j] = qb[j] = (m.axes[j].travel->min + m.axes[j].travel->max) / 2;
    qa[k] = m.axes[k].travel->min;
    qb[k] = m.axes[k].travel->max;
    const Vec3 pa = nominal.nominal_pose(qa).t, pb = nominal.nominal_pose(qb).t;
    const double length = (pb - pa).norm();
    ProbeFeature f;
    f.kind = ProbeFeature::Kind::Laser;
    f.id = fmt::format("L{}", m.axes[k].letter);
    f.normal = (pb - pa) / length;
    f.position = pa;
    std::vector<double> at;
    for (std::size_t i = 0; i < o.laser_points; ++i)
      at.push_back(length * static_cast<double>(i) / static_cast<double>(o.laser_points - 1));
    add(f, at);
    ++considered;
  }
  out = plan_targets(m, out);
  // A circle or line with a reading outside the travel: removed whole.
  std::vector<bool> outside(out.features.size(), false);
  for (const auto& r : out.records)
    for (std::size_t k = 0; k < m.axes.size(); ++k) {
      const auto& t = m.axes[k].travel;
      if (t && (r.q[k] < t->min - 1e-6 || r.q[k] > t->max + 1e-6)) outside[r.feature] = true;
    }
  removed += static_cast<std::size_t>(std::count(outside.begin(), outside.end(), true));
  std::erase_if(out.records, [&](const ProbingRecord& r) { return outside[r.feature]; });
  return out;
}

}  // namespace

std::size_t plan_poses(const ProbingPlan& plan) {
  std::size_t n = 0;
  std::set<std::size_t> seen;
  for (const auto& r : plan.records)
    if (!is_instrument(plan.features[r.feature].kind) || seen.insert(r.feature).second) ++n;
  return n;
}

ProbingPlan probing_part(const ProbingPlan& plan) {
  ProbingPlan out = plan;
  std::erase_if(out.records, [&](const ProbingRecord& r) { return is_instrument(plan.features[r.feature].kind); });
  return out;
}

std::vector<InstrumentSetup> instrument_setups(const Machine& m, const ProbingPlan& plan) {
  std::vector<InstrumentSetup> out;
  std::map<std::size_t, std::size_t> index;  // feature -> setup
  for (const auto& r : plan.records) {
    const ProbeFeature& f = plan.features[r.feature];
    if (!is_instrument(f.kind)) continue;
    auto [it, fresh] = index.emplace(r.feature, out.size());
    if (fresh) {
      InstrumentSetup s;
      s.id = f.id;
      s.kind = f.kind;
      s.position = f.position;
      if (f.kind == ProbeFeature::Kind::Ballbar) {
        s.plane = kPlaneNames[ballbar_plane(f)];
        s.radius = f.radius;
      } else {
        s.direction = f.normal;
        s.from = s.to = r.at;
      }
      for (std::size_t k : rotary_axes(m)) s.rotary.push_back(r.q.empty() ? 0.0 : r.q[k]);
      out.push_back(s);
    }
    InstrumentSetup& s = out[it->second];
    ++s.readings;
    s.from = std::min(s.from, r.at);
    s.to = std::max(s.to, r.at);
  }
  return out;
}

std::string describe_setup(const InstrumentSetup& s) {
  if (s.kind == ProbeFeature::Kind::Ballbar)
    return fmt::format("ballbar {}: {} plane, pivot {:.6g} {:.6g} {:.6g} mm, radius {:g} mm, {} readings", s.id,
                       s.plane, s.position.x(), s.position.y(), s.position.z(), s.radius, s.readings);
  return fmt::format("laser {}: beam {:.6g} {:.6g} {:.6g} from {:.6g} {:.6g} {:.6g} mm, {:.6g} to {:.6g} mm, {} targets",
                     s.id, s.direction.x(), s.direction.y(), s.direction.z(), s.position.x(), s.position.y(),
                     s.position.z(), s.from, s.to, s.readings);
}

CandidateGrid rotary_grid(const Machine& m, double step) {
  if (!(step > 0) || !std::isfinite(step))
    throw InputError({"rotary step", 0, ""}, fmt::format("expected a step > 0, found {:g}", step));
  CandidateGrid g;
  for (std::size_t k : rotary_axes(m)) {
    const auto& t = m.axes[k].travel;
    double lo = t ? t->min : -std::numbers::pi, hi = t ? t->max : std::numbers::pi;
    bool turn = hi - lo >= 2 * std::numbers::pi - 1e-12;
    if (turn) {  // one turn, centred on zero when the travel allows
      lo = std::max(lo, -std::numbers::pi);
      hi = lo + 2 * std::numbers::pi;
    }
    std::vector<double> v;
    const auto n = static_cast<long>(std::floor((hi - lo) / step + 1e-9));
    for (long i = 0; i <= n; ++i) {
      const double x = lo + static_cast<double>(i) * step;
      if (turn && x >= hi - 1e-9) break;
      v.push_back(x);
    }
    g.rotary.push_back(std::move(v));
  }
  return g;
}

std::string reach_violation(const Machine& m, const ProbingPlan& plan, const ProbingRecord& r,
                            const ProbeReach& reach) {
  const ErrorModel nominal(nominal_of(m));
  return violation(nominal, plan, r, reach);
}

CandidateSet candidate_configurations(const Machine& m, const std::vector<ProbeFeature>& features,
                                      const CandidateGrid& grid, const ProbeReach& reach,
                                      const InstrumentCandidates& instruments) {
  const auto rot = rotary_axes(m);
  const auto lin = linear_axes(m);
  for (const auto& f : features)
    if (f.kind != ProbeFeature::Kind::Ball && f.kind != ProbeFeature::Kind::Facet)
      throw InputError({"artefact", 0, f.id},
                       fmt::format("the design proposes probings of balls and facets; the {} '{}' is not one (its "
                                   "records are not proposed as candidates)",
                                   feature_kind_name(f.kind), f.id));
  if (grid.rotary.size() != rot.size())
    throw InputError({"candidate grid", 0, ""}, fmt::format("expected values for the {} rotary axes, found {}",
                                                            rot.size(), grid.rotary.size()));
  const bool more = !instruments.ballbar_radii.empty() || !instruments.laser_axes.empty();
  if (features.empty() && !more)
    throw InputError({"artefact", 0, ""}, "expected at least one ball or facet, found none");
  ProbingPlan all;
  all.features = features;
  all.source = "the candidate configurations";
  std::size_t count = 1;
  for (const auto& v : grid.rotary) count *= v.size();
  if (count == 0) throw InputError({"candidate grid", 0, ""}, "a rotary axis has no values");
  for (std::size_t idx = 0; idx < count && !features.empty(); ++idx) {
    ProbingRecord base;
    base.indexation = static_cast<int>(idx + 1);
    base.q.assign(m.axes.size(), 0.0);
    base.dir.assign(m.axes.size(), 0);
    std::size_t rest = idx;
    for (std::size_t j = rot.size(); j-- > 0;) {  // the last rotary axis fastest
      base.q[rot[j]] = grid.rotary[j][rest % grid.rotary[j].size()];
      rest /= grid.rotary[j].size();
    }
    for (std::size_t f = 0; f < features.size(); ++f) {
      base.feature = f;
      if (features[f].kind == ProbeFeature::Kind::Ball) {
        all.records.push_back(base);
        continue;
      }
      // Facets: every pre-move pattern of the linear axes; plan_targets sets the probing axis'
      // own direction (the approach), which makes half of the patterns duplicates, dropped below.
      for (int p = 0; p < (1 << lin.size()); ++p) {
        ProbingRecord r = base;
        for (std::size_t k = 0; k < lin.size(); ++k) r.dir[lin[k]] = (p >> k) & 1 ? 1 : -1;
        all.records.push_back(r);
      }
    }
  }
  all = plan_targets(m, all);
  // Duplicates (facet patterns that differ only in the probing axis).
  {
    std::set<std::tuple<int, std::size_t, std::vector<std::int8_t>>> seen;
    std::vector<ProbingRecord> unique;
    for (auto& r : all.records)
      if (seen.insert({r.indexation, r.feature, r.dir}).second) unique.push_back(std::move(r));
    all.records = std::move(unique);
  }
  CandidateSet out;
  out.considered = all.records.size();
  const std::vector<std::string> order{"travel", "stem", "facet side", "table"};
  std::map<std::string, std::size_t> removed;
  const ErrorModel nominal(nominal_of(m));
  std::vector<ProbingRecord> kept;
  for (auto& r : all.records) {
    const std::string why = violation(nominal, all, r, reach);
    if (why.empty())
      kept.push_back(std::move(r));
    else
      ++removed[why];
  }
  // The instruments' circles and lines: one candidate each, at one further indexation.
  {
    ProbingPlan more_plan = instrument_candidates(m, nominal, features, instruments, static_cast<int>(count + 1),
                                                  out.considered, removed["travel"]);
    const std::size_t shift = all.features.size();
    all.features.insert(all.features.end(), more_plan.features.begin(), more_plan.features.end());
    for (auto& r : more_plan.records) {
      r.feature += shift;
      kept.push_back(std::move(r));
    }
  }
  for (const auto& name : order) out.removed.emplace_back(name, removed[name]);
  if (kept.empty()) {
    std::string list;
    for (const auto& [name, n] : out.removed) list += fmt::format("{}{} by {}", list.empty() ? "" : ", ", n, name);
    throw InputError({"candidate configurations", 0, ""},
                     fmt::format("no candidate configuration is left: of {} ({} indexations x the features{}), {}",
                                 out.considered, count, more ? ", and the circles and lines" : "", list));
  }
  all.records = std::move(kept);
  out.plan = std::move(all);
  return out;
}

// ---------------------------------------------------------------------------------------------

std::vector<ProbeFeature> region_balls(const BallRegion& r, const std::vector<ProbeFeature>& taken) {
  for (const auto& [name, v] : {std::pair{"x_min", r.x_min}, std::pair{"x_max", r.x_max}, std::pair{"y_min", r.y_min},
                                std::pair{"y_max", r.y_max}, std::pair{"z", r.z}})
    if (!std::isfinite(v)) throw InputError({"ball region", 0, name}, fmt::format("expected a finite value, found {:g}", v));
  if (!(r.spacing > 0) || !std::isfinite(r.spacing))
    throw InputError({"ball region", 0, "spacing"}, fmt::format("expected a spacing > 0 mm, found {:g}", r.spacing));
  if (r.x_min > r.x_max || r.y_min > r.y_max)
    throw InputError({"ball region", 0, ""}, fmt::format("expected min <= max, found x {:g} to {:g}, y {:g} to {:g}",
                                                         r.x_min, r.x_max, r.y_min, r.y_max));
  const double nx = std::floor((r.x_max - r.x_min) / r.spacing + 1e-9) + 1,
               ny = std::floor((r.y_max - r.y_min) / r.spacing + 1e-9) + 1;
  if (nx * ny > 10000)
    throw InputError({"ball region", 0, "spacing"},
                     fmt::format("expected at most 10,000 positions, found {:g} x {:g}: a larger spacing", nx, ny));
  std::vector<ProbeFeature> out;
  for (long j = 0; j < static_cast<long>(ny); ++j)
    for (long i = 0; i < static_cast<long>(nx); ++i) {
      ProbeFeature f;
      f.id = r.id_prefix + std::to_string(out.size() + 1);
      if (std::any_of(taken.begin(), taken.end(), [&](const ProbeFeature& t) { return t.id == f.id; }))
        throw InputError({"ball region", 0, f.id},
                         fmt::format("the region's ball id '{}' is already a feature of the artefact", f.id));
      f.kind = ProbeFeature::Kind::Ball;
      f.position = Vec3(r.x_min + static_cast<double>(i) * r.spacing, r.y_min + static_cast<double>(j) * r.spacing, r.z);
      out.push_back(f);
    }
  return out;
}

// ---------------------------------------------------------------------------------------------

ParameterChoice choose_parameters(const Machine& m, const ProbingPlan& candidates, const SubsetOptions& so,
                                  const IdentificationOptions& model) {
  const SubsetAnalysis a = full_rank_subsets(m, candidates, so, model);
  ParameterChoice out;
  out.examined = a.examined;
  out.full_rank = a.full_rank;
  if (a.subsets.empty()) {
    IdentificationOptions all = model;
    all.estimate = so.always;
    all.estimate.insert(all.estimate.end(), so.candidates.begin(), so.candidates.end());
    all.estimate_source = so.candidates_source;
    const Identifiability id = identifiability(m, candidates, all);
    std::string why;
    for (const auto& d : id.null_directions) why += (why.empty() ? "" : "; ") + d;
    throw InputError({so.choose_source, 0, std::to_string(so.choose)},
                     fmt::format("none of the {} subsets of {} among the {} candidates is identifiable at all {} "
                                 "candidate poses{}{}",
                                 a.examined, so.choose, a.candidates.size(), candidates.records.size(),
                                 id.unidentifiable.empty() ? "" : fmt::format(" ({} {} not identifiable whatever the poses: {})",
                                                                              fmt::join(id.unidentifiable, ", "),
                                                                              id.unidentifiable.size() == 1 ? "is" : "are", why),
                                 so.always.empty() ? "" : fmt::format(", with {}", fmt::join(so.always, ","))));
  }
  const ParameterSubset& best = a.subsets.front();
  out.condition = best.condition;
  out.estimate = so.always;
  for (std::size_t i : best.members) {
    out.chosen.push_back(a.candidates[i]);
    out.estimate.push_back(a.candidates[i]);
  }
  return out;
}

// ---------------------------------------------------------------------------------------------

PlanPrediction predict_plan(const Machine& m, const ProbingPlan& plan, const IdentificationOptions& o) {
  const Machine nominal = nominal_of(m);
  const ProbingPlan targets = plan_targets(nominal, plan);
  const Identifiability id = identifiability(m, plan, o);
  if (!id.unidentifiable.empty()) {
    std::string why;
    for (const auto& d : id.null_directions) why += (why.empty() ? "" : "; ") + d;
    throw InputError({plan.source, 0, id.unidentifiable.front()},
                     fmt::format("{} {} not identifiable from the {} poses ({})",
                                 fmt::join(id.unidentifiable, ", "), id.unidentifiable.size() == 1 ? "is" : "are",
                                 plan_poses(plan), why));
  }
  const auto params = detail::parameter_indices(m, o.estimate, o.estimate_source);
  const detail::ProbingModel pm(nominal, targets, params, o.scale_bars, false, o.sigma_ball, o.sigma_facet,
                                o.sigma_scale_bar, o.sigma_ballbar, o.sigma_laser);
  Eigen::VectorXd r;
  Eigen::MatrixXd J;
  pm.evaluate(pm.initial(), r, &J);
  // The rows are divided by the readings' sigma: sigma^2 (J^T J)^-1 of the unweighted Jacobian.
  const JacobianAnalysis a = analyse_jacobian(J, 1.0, JacobianOptions{o.rank_tolerance, true});
  PlanPrediction out;
  out.poses = plan_poses(plan);
  out.residuals = pm.residuals();
  out.unknowns = pm.unknowns();
  out.rank = a.rank;
  out.condition = a.condition;
  if (!a.full_rank())
    throw InputError({plan.source, 0, ""}, fmt::format("the {} poses leave {} of the {} unknowns undetermined",
                                                       plan_poses(plan), pm.unknowns() - a.rank, pm.unknowns()));
  const auto k = static_cast<Eigen::Index>(params.size());
  out.covariance = a.covariance.topLeftCorner(k, k);
  const auto all = m.parameters();
  for (std::size_t i = 0; i < params.size(); ++i)
    out.parameters.push_back(
        {all[params[i]].name, all[params[i]].unit, a.uncertainty[static_cast<Eigen::Index>(i)], 0.0});
  return out;
}

// ---------------------------------------------------------------------------------------------

std::vector<std::vector<double>> travel_grid(const Machine& m, std::size_t per_axis) {
  if (per_axis < 2)
    throw InputError({"workspace", 0, ""}, fmt::format("expected at least 2 values per axis, found {}", per_axis));
  std::vector<std::vector<double>> g;
  const auto n = static_cast<double>(per_axis);
  for (const auto& axis : m.axes) {
    const auto& t = axis.travel;
    std::vector<double> v;
    const bool rotary = axis.kind == AxisKind::Rotary;
    if (rotary && (!t || t->max - t->min >= 2 * std::numbers::pi - 1e-12)) {
      for (std::size_t i = 0; i < per_axis; ++i)  // one turn, the end left out (it is the start)
        v.push_back(-std::numbers::pi + 2 * std::numbers::pi * static_cast<double>(i) / n);
    } else if (!t) {
      throw InputError({m.source, 0, std::string(1, axis.letter)},
                       "a workspace over the travels needs the travel of every linear axis; axis has none");
    } else {
      for (std::size_t i = 0; i < per_axis; ++i)
        v.push_back(t->min + (t->max - t->min) * static_cast<double>(i) / (n - 1));
    }
    g.push_back(std::move(v));
  }
  return g;
}

VaSensitivity va_sensitivity(const Machine& m, const std::vector<std::vector<double>>& workspace,
                             const IdentificationOptions& o, const VaOptions& vo) {
  const auto params = detail::parameter_indices(m, o.estimate, o.estimate_source);
  const ErrorModel model(m);
  const ErrorMap map = grid_error_map(model, workspace);
  const VolumetricAccuracy va = volumetric_accuracy(map.error);
  VaSensitivity out;
  out.va = va.va.value;
  if (!(out.va > 1e-12))
    throw InputError({"workspace", 0, ""},
                     fmt::format("the machine's VA over the workspace ({} configurations) is {:g} mm: its uncertainty "
                                 "is linearised about the machine's errors, which must not all vanish there (give "
                                 "the expected errors, e.g. a prior identification's parameters)",
                                 map.size(), out.va));
  // The pairs within the tolerance of the maximum: a point can be in one only if its distance from
  // the centroid plus the map's radius about it reaches VA - tolerance (triangle inequality).
  const double floor = out.va - std::max(0.0, vo.tie_tolerance);
  Vec3 centre = Vec3::Zero();
  for (const Vec3& e : map.error) centre += e;
  centre /= static_cast<double>(map.size());
  double radius = 0.0;
  for (const Vec3& e : map.error) radius = std::max(radius, (e - centre).norm());
  std::vector<std::size_t> far;
  for (std::size_t i = 0; i < map.size(); ++i)
    if ((map.error[i] - centre).norm() + radius >= floor) far.push_back(i);
  std::vector<std::tuple<double, std::size_t, std::size_t>> pairs{{out.va, va.va.i, va.va.j}};
  for (std::size_t a = 0; a < far.size(); ++a)
    for (std::size_t b = a + 1; b < far.size(); ++b) {
      const std::size_t i = far[a], j = far[b];
      if ((i == va.va.i && j == va.va.j) || (i == va.va.j && j == va.va.i)) continue;
      const double l = (map.error[j] - map.error[i]).norm();
      if (l >= floor) pairs.emplace_back(l, i, j);
    }
  std::sort(pairs.begin() + 1, pairs.end(), [](const auto& x, const auto& y) { return std::get<0>(x) > std::get<0>(y); });
  out.tie_tolerance = std::max(0.0, vo.tie_tolerance);
  if (pairs.size() > std::max<std::size_t>(1, vo.max_pairs)) {
    pairs.resize(std::max<std::size_t>(1, vo.max_pairs));
    out.pairs_capped = true;
  }
  const auto ci = map.configuration(va.va.i), cj = map.configuration(va.va.j);
  out.from.assign(ci.begin(), ci.end());
  out.to.assign(cj.begin(), cj.end());
  const auto all = m.parameters();
  for (std::size_t k : params) out.parameters.push_back(all[k].name);
  out.gradients.resize(static_cast<Eigen::Index>(params.size()), static_cast<Eigen::Index>(pairs.size()));
  for (std::size_t n = 0; n < pairs.size(); ++n) {
    const auto [l, i, j] = pairs[n];
    const Vec3 d = (map.error[j] - map.error[i]).normalized();
    const Eigen::Matrix<double, 6, Eigen::Dynamic> Ji = model.jacobian(map.configuration(i)),
                                                   Jj = model.jacobian(map.configuration(j));
    for (std::size_t k = 0; k < params.size(); ++k) {
      const auto c = static_cast<Eigen::Index>(params[k]);
      out.gradients(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(n)) =
          d.dot(Jj.block<3, 1>(0, c) - Ji.block<3, 1>(0, c));
    }
    out.pair_lengths.push_back(l);
  }
  out.gradient = out.gradients.col(0);
  return out;
}

double va_uncertainty(const VaSensitivity& s, const Eigen::MatrixXd& covariance) {
  if (covariance.rows() != s.gradients.rows() || covariance.cols() != s.gradients.rows())
    throw Error(fmt::format("va_uncertainty: a covariance of {} x {} for {} parameters", covariance.rows(),
                            covariance.cols(), s.gradients.rows()));
  return std::sqrt(std::max(0.0, (s.gradients.transpose() * covariance * s.gradients).diagonal().maxCoeff()));
}

// ---------------------------------------------------------------------------------------------
}  // namespace mtcal
