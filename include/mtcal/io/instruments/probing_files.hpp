// Probing files: contacts and sphere centres per indexation of a rotary axis, simulated contacts, the rotary axis's
// parameter file.
#pragma once

#include <string>
#include <vector>

#include "mtcal/model/machine.hpp"
#include "mtcal/probing/rotary_probing.hpp"
#include "mtcal/probing/sphere_probing.hpp"

namespace mtcal {

// Reads the contacts CSV: the axis's angle (deg, the column named by its letter), the recorded
// stylus-tip centre x,y,z (mm) and optionally approach_x,approach_y,approach_z (the direction of
// probe motion, normalised; all three or none; default -z). Other machine-axis columns (X Y Z A
// B C) are allowed and ignored. Throws InputError naming file, line and column.
ContactSet read_contacts_csv(const std::string& path, char axis);
// The same from the file's text (a file kept in the history store), path naming it.
ContactSet parse_contacts_csv(const std::string& text, const std::string& path, char axis);

// Reads the centres CSV: the axis's angle (deg, the column named by its letter), the sphere
// centre x,y,z (mm); method "given". An angle given twice (or a turn apart) is one position
// measured twice: locate_rotary_axis averages the centres.
IndexedCentres read_centres_csv(const std::string& path, char axis);
IndexedCentres parse_centres_csv(const std::string& text, const std::string& path, char axis);

// The contacts CSV of simulated probing (read back by read_contacts_csv): header
// "<letter>,x,y,z,approach_x,approach_y,approach_z", the angle in the axis's user unit.
std::string contacts_csv(const Axis& axis, const std::vector<ProbedIndexation>& probed);
void write_contacts_csv(const std::string& path, const Axis& axis, const std::vector<ProbedIndexation>& probed);

// The four location errors of result.best() as an mtcal parameter file (YAML, mtcal_parameters: 1),
// with their standard uncertainties as comments.
std::string rotary_parameters_yaml(const RotaryAxisResult& result);
void write_rotary_parameters(const std::string& path, const RotaryAxisResult& result);

}  // namespace mtcal
