// The first coarse touch: a sphere located from a rough position before a plan is made (docs/planning.md, "Locating the sphere").
#pragma once

#include <span>
#include <string>
#include <vector>

#include "mtcal/identification/planning.hpp"

namespace mtcal {

// The locating cycle beyond the plan's ProbeCycle (ball and tip diameters, approach, overtravel,
// clearance): how far the sphere may be from its rough position, and what a located sphere must be.
struct LocateOptions {
  // The sphere's centre lies within this distance (mm, any direction) of the rough position the
  // artefact gives; at most half the contact radius (ball + tip) / 2, where every probing move of
  // locate_touches still meets the sphere.
  double within = 3.0;
  // A located sphere: its contact radius (the tip centre's) within radius_tolerance of
  // (ball + tip) / 2, and the contacts' RMS about the fitted sphere at most fit_tolerance (mm).
  double radius_tolerance = 0.05;
  double fit_tolerance = 0.01;
};

// The locating plan: one record per ball of the artefact (its facets and rows are not used), at the
// configuration `at` (chain order, internal units: the rotary axes' values; the linear ones are
// computed: the ball's rough centre by the nominal chain, plan_targets). Throws InputError for an
// artefact without a ball or an `at` of another size.
ProbingPlan locate_plan(const Machine& m, const ProbingPlan& artefact, std::span<const double> at);

// The touches of the locating cycle, per record in this order: the pole (from above along the tool
// axis), four on the rough centre's equator (along the other two machine axes, both ways) and four
// on a ring h = (rho - within) / 2 above it, between those (rho = (ball + tip) / 2). Every probing
// move is along the tool axis or across it; it starts rho + within + approach from the rough centre
// (outside the sphere wherever it lies) and ends overtravel past the nearest contact a sphere within
// `within` can give, so that each move meets it. `expected` is the contact of a sphere at the rough
// centre. Throws InputError for a cycle probe_touches refuses, a `within` not in (0, rho / 2], or a
// move outside a linear axis's travel (the ball and the axis named).
std::vector<ProbeTouch> locate_touches(const Machine& m, const ProbingPlan& plan, const ProbeCycle& cycle,
                                       const LocateOptions& options);

// One located sphere.
struct LocatedSphere {
  std::string id;
  Vec3 rough = Vec3::Zero();   // the artefact's position (mm, workpiece frame)
  Vec3 centre = Vec3::Zero();  // located: the fitted centre through the nominal chain (mm, workpiece frame)
  double offset = 0.0;         // |centre - rough|, mm
  double contact_radius = 0.0;  // the fitted sphere of the tip centre's contacts, mm
  double ball_diameter = 0.0;   // 2 contact_radius - tip diameter, mm
  double rms = 0.0;             // the contacts about the fitted sphere, mm
  std::size_t contacts = 0;
  bool beyond = false;  // offset > within: found, but farther than the cycle was laid out for
};
struct LocateResult {
  // The artefact with its located balls at their centres (facets as they were), one record per
  // ball at the locating configuration: what plan --artefact takes.
  ProbingPlan artefact;
  std::vector<LocatedSphere> spheres;
};

// The spheres from the contacts the locating program logged (axis values, chain order, internal
// units; contacts_from_tool_points first for a program in tool-point coordinates): per record the
// sphere fitted to its touches (radius free; fit_sphere). Throws InputError located at the log's line
// for a count other than the touches' (a short log names the first contact missing: the probe did
// not trip, the sphere is not within `within` of its rough position), a contact at other rotary
// values than its record's or off its probing move, and per ball when no sphere of the cycle's
// diameters is found (the fitted diameter or the RMS said).
LocateResult locate_spheres(const Machine& m, const ProbingPlan& plan, const ProbeCycle& cycle,
                            const LocateOptions& options, const std::vector<LoggedContact>& contacts,
                            const std::string& log_source = "probe log");

}  // namespace mtcal
