// Probing files: contacts written by simulation read back into the same centres, centres and parameter files, bad input
// located.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/io/instruments/probing_files.hpp"
#include "mtcal/io/json/probing_json.hpp"
#include "mtcal/probing/rotary_probing.hpp"
#include "mtcal/util/errors.hpp"

#include "input_errors.hpp"
#include "examples.hpp"

using namespace mtcal;
using mtcal::testing::error_at;

namespace {

using mtcal::testing::kDeg;

std::string temp(const std::string& name) { return (std::filesystem::temp_directory_path() / name).string(); }

std::string probing_files_write_temp(const std::string& name, const std::string& text) {
  const auto p = temp(name);
  std::ofstream(p) << text;
  return p;
}

// A perfect C axis: a sphere of 30 mm probed with a 6 mm stylus at 8 indexations about z.
std::vector<ProbedIndexation> ideal_probing() {
  std::vector<ProbedIndexation> out;
  for (int k = 0; k < 8; ++k) {
    ProbedIndexation ix;
    ix.angle = 45.0 * k * kDeg;
    const Point3 centre(150 * std::cos(ix.angle), 150 * std::sin(ix.angle), 50);
    for (const Point3& a : five_point_approaches()) ix.contacts.push_back({centre - 18.0 * a, a});
    out.push_back(ix);
  }
  return out;
}

}  // namespace

TEST(ProbingFiles, ContactsRoundTripGiveTheCentres) {
  Axis c;
  c.letter = 'C';
  c.kind = AxisKind::Rotary;
  c.direction_axis = 2;
  const auto probed = ideal_probing();
  const std::string path = temp("mtcal-contacts-roundtrip.csv");
  write_contacts_csv(path, c, probed);
  const ContactSet set = read_contacts_csv(path, 'C');
  EXPECT_EQ(set.source, path);
  EXPECT_EQ(set.axis, 'C');
  ASSERT_EQ(set.contacts.size(), 40u);
  EXPECT_EQ(set.contacts.front().line, 2);
  EXPECT_NEAR(set.contacts[5].angle_deg, 45.0, 1e-9);
  const IndexedCentres centres = centres_from_contacts(set, SphereProbing{30, 6, 0.01});
  EXPECT_EQ(centres.method, "five-point");
  ASSERT_EQ(centres.centres.size(), 8u);
  ASSERT_EQ(centres.fits.size(), 8u);
  for (std::size_t k = 0; k < 8; ++k) {
    EXPECT_NEAR(centres.centres[k].angle, probed[k].angle, 1e-12);
    EXPECT_NEAR((centres.centres[k].centre -
                 Point3(150 * std::cos(probed[k].angle), 150 * std::sin(probed[k].angle), 50))
                    .norm(),
                0.0, 1e-6);
  }
  const RotaryAxisResult r = locate_rotary_axis(NominalRotaryAxis::by_letter('C'), centres, {});
  EXPECT_NEAR(r.tilt(), 0.0, 1e-8);
  const Json j = to_json(r);
  EXPECT_EQ(j["centre_method"], "five-point");
  EXPECT_EQ(j["indexations"], 8);
  EXPECT_TRUE(j.contains("triples") && j.contains("least_squares"));
}

TEST(ProbingFiles, RotaryParametersReadBackAsAParameterFile) {
  IndexedCentres centres;
  centres.source = "centres.csv";
  for (int k = 0; k < 6; ++k) {
    const double a = 60.0 * k * kDeg;
    centres.centres.push_back({a, Point3(0.01 + 100 * std::cos(a), -0.02 + 100 * std::sin(a), 10)});
  }
  const RotaryAxisResult r = locate_rotary_axis(NominalRotaryAxis::by_letter('C'), centres, {false, true, {}});
  const std::string yaml = rotary_parameters_yaml(r);
  EXPECT_EQ(
      yaml.rfind("# Location errors of axis C from mtcal rotary-axis (least squares), 6 indexations of centres.csv\n",
                 0),
      0u);
  const std::string path = temp("mtcal-c-axis.yaml");
  write_rotary_parameters(path, r);
  Machine m = load_machine(MTCAL_EXAMPLES_DIR "/hu40t-wCBXfYZt.yaml");
  load_parameters(m, path);  // must be a valid parameter file for a machine with a C axis
  SUCCEED();
}

TEST(ProbingFiles, BadContactsAndCentresAreLocated) {
  const auto unk = probing_files_write_temp("mtcal-contacts-unk.csv", "C,x,y,z,q\n0,1,2,3,4\n");
  auto w = error_at([&] { read_contacts_csv(unk, 'C'); });
  EXPECT_EQ(w.file, unk);
  EXPECT_EQ(w.line, 1);
  EXPECT_EQ(w.field, "q");
  const auto zero = probing_files_write_temp("mtcal-contacts-zero.csv",
                               "C,x,y,z,approach_x,approach_y,approach_z\n0,1,2,3,0,0,-1\n0,1,2,3,0,0,0\n");
  w = error_at([&] { read_contacts_csv(zero, 'C'); });
  EXPECT_EQ(w.line, 3);
  EXPECT_EQ(w.field, "approach_x");
  // An angle given twice (or a turn apart) is one position measured twice: read as given, then
  // averaged into one centre with a note.
  const auto dup = probing_files_write_temp("mtcal-centres-dup.csv", "A,x,y,z\n0,1,2,3\n5,1,2,3\n0,1,2,5\n360,1,2,4\n");
  IndexedCentres c = read_centres_csv(dup, 'A');
  ASSERT_EQ(c.centres.size(), 4u);
  const auto notes = merge_wrapped_centres(c);
  ASSERT_EQ(c.centres.size(), 2u);
  EXPECT_NEAR(c.centres[0].centre.z(), 4.0, 1e-12);  // (3 + 5 + 4) / 3
  EXPECT_NEAR(c.centres[0].angle, 0.0, 1e-15);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("0, 0, 360 deg"), std::string::npos) << notes[0];
  const auto good = read_centres_csv(probing_files_write_temp("mtcal-centres.csv", "A,x,y,z\n90,1,2,3\n"), 'A');
  EXPECT_EQ(good.method, "given");
  ASSERT_EQ(good.centres.size(), 1u);
  EXPECT_NEAR(good.centres[0].angle, 90 * kDeg, 1e-15);
}
