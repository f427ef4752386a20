// Whole-file reading and atomic output files: complete or absent, never partial.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <sys/stat.h>

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

// Outputs onto what is not a regular file: /dev/null or a FIFO is refused and left as it is (a
// rename would put a regular file in its place); a symbolic link is followed and stays a link.
TEST(Files, RefusesDevicesAndFifosAndFollowsSymlinks) {
  EXPECT_THROW(AtomicFile("/dev/null"), Error);
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
  const fs::path d = fresh_dir("special");
  const fs::path fifo = d / "pipe";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_THROW(AtomicFile(fifo.string()), Error);
  EXPECT_TRUE(fs::is_fifo(fs::symlink_status(fifo)));

  const fs::path real = d / "real.csv", link = d / "link.csv";
  std::ofstream(real) << "old";
  fs::create_symlink(real, link);
  write_file_atomically(link.string(), "new");
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(link)));
  std::ifstream in(real);
  std::string text;
  std::getline(in, text);
  EXPECT_EQ(text, "new");
  fs::remove_all(d);
}

// A new output gets 0666 & ~umask, as any file the user creates (mkstemp alone gives 0600).
TEST(Files, OutputPermissionsFollowTheUmask) {
  const fs::path d = fresh_dir("umask");
  const mode_t old = ::umask(022);
  write_file_atomically((d / "a.csv").string(), "x");
  ::umask(027);
  write_file_atomically((d / "b.csv").string(), "x");
  ::umask(old);
  EXPECT_EQ(fs::status(d / "a.csv").permissions() & fs::perms::all, static_cast<fs::perms>(0644));
  EXPECT_EQ(fs::status(d / "b.csv").permissions() & fs::perms::all, static_cast<fs::perms>(0640));
  fs::remove_all(d);
}
