// Sphere centres from touch-probe contacts, and simulated probing of a sphere on a machine model.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "mtcal/fitting/fit.hpp"
#include "mtcal/model/machine.hpp"

namespace mtcal {

// One trigger: the stylus-tip centre the machine recorded (machine coordinates, mm) and the unit
// direction in which the probe was moving. The tip centre lies (sphere + stylus diameter)/2 from
// the sphere centre, against the approach direction.
struct ProbeContact {
  Point3 point = Point3::Zero();
  Point3 approach = -Point3::UnitZ();
};

struct SphereProbing {
  double sphere_diameter = 0.0;  // mm
  double stylus_diameter = 0.0;  // mm
  double max_rms = 0.01;         // mm: contacts farther than this from a sphere are refused
};

// Centre of one probed sphere, two ways: the least-squares fit of all contacts with the known
// radius, and (with exactly the 5-point protocol of Cubas & Yeh 2022: approaches +x, -x, +y, -y
// and -z) the mean of the four 4-point subsets that keep the -z contact, each fitted with the
// known radius. effective_radius is the free-radius fit's tip-centre distance (>= 4 contacts
// not on one plane): smaller than nominal by the probe's pre-travel.
struct SphereCentre {
  Point3 least_squares = Point3::Zero();
  std::optional<Point3> five_point;        // the seed's protocol, when the contacts follow it
  std::vector<Point3> subset_centres;      // the four 4-point solutions
  double rms = 0.0;                        // of the least-squares fit, mm
  std::optional<double> effective_radius;  // tip-centre distance of the free-radius fit
  std::string method;                      // "five-point" or "least-squares" (what centre() gives)
  Point3 centre() const { return five_point ? *five_point : least_squares; }
};
// Throws InputError (field = where) with fewer than 3 contacts, degenerate contacts, or contacts
// that are not on a sphere of the given size (rms above max_rms).
SphereCentre sphere_centre(const std::vector<ProbeContact>& contacts, const SphereProbing& probing,
                           const std::string& where);

// Simulated sphere probing at indexations of one rotary axis (the others held), on a machine
// model with errors: for each indexation and each approach of the 5-point protocol, the linear
// axes are driven until the actual stylus tip touches the sphere, and the nominal tool position
// the controller shows is recorded (machine coordinates), with Gaussian noise and a trigger
// bias (pre-travel along the approach).
struct ProbingSimulation {
  char axis = 'C';
  std::vector<double> angles;          // indexations of that axis, rad
  std::vector<double> held;            // all joint values (internal units, chain order); the
                                       // tested axis's entry is replaced by each angle; empty: 0
  Point3 sphere = Point3(150, 0, 50);  // sphere centre at zero indexation, machine coordinates
  SphereProbing probing{30.0, 6.0, 0.01};
  double noise = 0.0;         // standard deviation per coordinate, mm
  double trigger_bias = 0.0;  // pre-travel, mm (the tip goes this far past contact)
  std::uint64_t seed = 1;
};
struct ProbedIndexation {
  double angle = 0.0;  // rad
  std::vector<ProbeContact> contacts;
};
// Throws ModelError if the axis is not a rotary axis carrying the workpiece or the machine lacks
// three linear axes carrying the tool or workpiece, InputError if a contact cannot be reached.
std::vector<ProbedIndexation> simulate_probing(const Machine& m, const ProbingSimulation& sim);

// The five approach directions of the protocol: +x, -x, +y, -y, -z.
std::vector<Point3> five_point_approaches();

}  // namespace mtcal
