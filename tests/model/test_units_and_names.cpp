// Units, ISO 230 error names and topology strings.
#include <gtest/gtest.h>

#include <numbers>

#include "mtcal/model/error_name.hpp"
#include "mtcal/model/machine.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/util/units.hpp"

using namespace mtcal;

TEST(Units, FactorsToInternalUnits) {
  EXPECT_DOUBLE_EQ(find_unit("um")->to_internal, 1e-3);
  EXPECT_DOUBLE_EQ(find_unit("\xC2\xB5m")->to_internal, 1e-3);
  EXPECT_DOUBLE_EQ(find_unit("m")->to_internal, 1e3);
  EXPECT_DOUBLE_EQ(find_unit("deg")->to_internal, std::numbers::pi / 180);
  EXPECT_DOUBLE_EQ(find_unit("arcsec")->to_internal, std::numbers::pi / 180 / 3600);
  EXPECT_DOUBLE_EQ(find_unit("um/m")->to_internal, 1e-6);
  EXPECT_EQ(find_unit("um/m")->dimension, Dimension::Angle);
  EXPECT_EQ(find_unit("urad")->name, "urad");
  EXPECT_FALSE(find_unit("furlong"));
  EXPECT_FALSE(find_unit("MM"));
}

TEST(ErrorName, ParsesIsoNames) {
  auto exx = ErrorName::parse("EXX");
  ASSERT_TRUE(exx);
  EXPECT_EQ(exx->kind, ErrorKind::Motion);
  EXPECT_EQ(exx->component, Component::X);
  EXPECT_EQ(exx->body, 'X');
  auto ec0y = ErrorName::parse("EC0Y");
  ASSERT_TRUE(ec0y);
  EXPECT_EQ(ec0y->kind, ErrorKind::Location);
  EXPECT_EQ(ec0y->component, Component::C);
  EXPECT_EQ(ec0y->body, 'Y');
  auto ebt = ErrorName::parse("EBt");
  ASSERT_TRUE(ebt);
  EXPECT_EQ(ebt->kind, ErrorKind::Mounting);
  for (const char* s : {"EXX", "EAC", "EX0C", "EC0C", "EB0Z", "EXt", "ECw"}) EXPECT_EQ(ErrorName::parse(s)->str(), s);
  for (const char* s : {"", "E", "EX", "XXX", "EQX", "EXQ", "EX1C", "EX0Q", "EXXX", "EXT", "eXX"})
    EXPECT_FALSE(ErrorName::parse(s)) << s;
}

TEST(Topology, ParsesChains) {
  auto t = Topology::parse("wCBXfYZt");
  EXPECT_EQ(t.axes, (std::vector<char>{'C', 'B', 'X', 'Y', 'Z'}));
  EXPECT_EQ(t.frame_index, 3u);
  EXPECT_EQ(Topology::parse("wfXYZt").frame_index, 0u);
  EXPECT_EQ(Topology::parse("wXYZft").frame_index, 3u);
  EXPECT_EQ(Topology::parse("wCAYXfZt").axes.size(), 5u);
}

TEST(Topology, RejectsMalformedChains) {
  for (const char* s : {"", "wt", "XfYZt", "wXfYZ", "wXYZt", "wXffYZt", "wXfXZt", "wXfYQt", "wft"}) {
    EXPECT_THROW(Topology::parse(s), ModelError) << s;
  }
  try {
    Topology::parse("wXfYQt");
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("'Q'"), std::string::npos) << e.what();
  }
}

TEST(Axis, LocationErrorsAllowedByIso230) {
  Axis lin;
  lin.kind = AxisKind::Linear;
  lin.direction_axis = 1;                          // Y
  EXPECT_TRUE(lin.allows_location(Component::Y));  // EY0Y zero position
  EXPECT_TRUE(lin.allows_location(Component::A));  // EA0Y
  EXPECT_TRUE(lin.allows_location(Component::C));  // EC0Y
  EXPECT_FALSE(lin.allows_location(Component::X));
  EXPECT_FALSE(lin.allows_location(Component::B));  // roll of the line: meaningless
  Axis rot;
  rot.kind = AxisKind::Rotary;
  rot.direction_axis = 2;                           // C
  EXPECT_TRUE(rot.allows_location(Component::X));   // EX0C
  EXPECT_TRUE(rot.allows_location(Component::Y));   // EY0C
  EXPECT_FALSE(rot.allows_location(Component::Z));  // along the line: no effect
  EXPECT_TRUE(rot.allows_location(Component::A));
  EXPECT_TRUE(rot.allows_location(Component::B));
  EXPECT_TRUE(rot.allows_location(Component::C));  // EC0C zero position
}
