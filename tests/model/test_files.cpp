// Whole-file reading and atomic output files: complete or absent, never partial.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "mtcal/io/files.hpp"
#include "mtcal/util/errors.hpp"

using namespace mtcal;
namespace fs = std::filesystem;

namespace {
fs::path fresh_dir(const char* name) {
  const fs::path d = fs::temp_directory_path() / (std::string("mtcal-test-") + name + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}
}  // namespace

TEST(Files, AtomicFileAppearsOnlyOnCommit) {
  const fs::path d = fresh_dir("atomic");
  const std::string target = (d / "out.csv").string();
  {
    AtomicFile f(target);
    f.stream() << "a,b\n1,2\n";
    EXPECT_FALSE(fs::exists(target));  // nothing at the target while writing
    f.commit();
  }
  EXPECT_EQ(read_text_file(target), "a,b\n1,2\n");
  EXPECT_EQ(std::distance(fs::directory_iterator(d), fs::directory_iterator()), 1);
  fs::remove_all(d);
}

TEST(Files, AbandonedAtomicFileLeavesNothingAndKeepsTheOldFile) {
  const fs::path d = fresh_dir("abandon");
  const std::string target = (d / "out.csv").string();
  std::ofstream(target) << "old\n";
  {
    AtomicFile f(target);
    f.stream() << "partial";
    // destroyed without commit, as when an error is thrown mid-way
  }
  EXPECT_EQ(read_text_file(target), "old\n");
  EXPECT_EQ(std::distance(fs::directory_iterator(d), fs::directory_iterator()), 1);  // no temporary left
  fs::remove_all(d);
}

TEST(Files, RefusesDirectoriesAndMissingFolders) {
  const fs::path d = fresh_dir("dirs");
  EXPECT_THROW(AtomicFile(d.string()), Error);
  EXPECT_THROW(AtomicFile((d / "").string()), Error);
  EXPECT_THROW(AtomicFile((d / "no" / "such" / "x.csv").string()), Error);
  EXPECT_THROW(read_text_file(d.string()), InputError);
  EXPECT_THROW(read_text_file((d / "missing.yaml").string()), InputError);
  fs::remove_all(d);
}
