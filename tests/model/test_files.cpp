// Whole-file reading and atomic output files: complete or absent, never partial.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include <sys/stat.h>

#include "mtcal/io/system/files.hpp"
#include "mtcal/util/errors.hpp"

using namespace mtcal;
namespace fs = std::filesystem;

namespace {
fs::path files_fresh_dir(const char* name) {
  const fs::path d = fs::temp_directory_path() / (std::string("mtcal-test-") + name + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}
}  // namespace

TEST(Files, AtomicFileAppearsOnlyOnCommit) {
  const fs::path d = files_fresh_dir("atomic");
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
  const fs::path d = files_fresh_dir("abandon");
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
  const fs::path d = files_fresh_dir("dirs");
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
  const fs::path d = files_fresh_dir("special");
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
  const fs::path d = files_fresh_dir("umask");
  const mode_t old = ::umask(022);
  write_file_atomically((d / "a.csv").string(), "x");
  ::umask(027);
  write_file_atomically((d / "b.csv").string(), "x");
  ::umask(old);
  EXPECT_EQ(fs::status(d / "a.csv").permissions() & fs::perms::all, static_cast<fs::perms>(0644));
  EXPECT_EQ(fs::status(d / "b.csv").permissions() & fs::perms::all, static_cast<fs::perms>(0640));
  fs::remove_all(d);
}

namespace {
std::string content(const fs::path& p) {
  std::ifstream in(p);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}
}  // namespace

TEST(Files, OutputGroupWritesAllOrNothing) {
  const fs::path d = files_fresh_dir("group");
  const fs::path a = d / "a.csv", b = d / "b.html";
  // Committed files of a group appear only when the group commits.
  {
    OutputGroup g;
    write_file_atomically(a.string(), "A\n");
    write_file_atomically(b.string(), "B\n");
    EXPECT_FALSE(fs::exists(a));
    EXPECT_FALSE(fs::exists(b));
    g.commit();
  }
  EXPECT_EQ(content(a), "A\n");
  EXPECT_EQ(content(b), "B\n");
  // A group abandoned (an error after the first output) leaves the old files and no temporaries.
  {
    OutputGroup g;
    write_file_atomically(a.string(), "A2\n");
  }
  EXPECT_EQ(content(a), "A\n");
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(d)) ++files;
  EXPECT_EQ(files, 2u);
  fs::remove_all(d);
}

TEST(Files, OutputGroupRestoresReplacedTargetsWhenALaterRenameFails) {
  const fs::path d = files_fresh_dir("group-undo"), other = files_fresh_dir("group-undo-b");
  const fs::path a = d / "a.csv", b = other / "b.csv", fresh = d / "new.csv";
  std::ofstream(a) << "old A\n";
  {
    OutputGroup g;
    write_file_atomically(a.string(), "new A\n");
    write_file_atomically(fresh.string(), "new file\n");
    write_file_atomically(b.string(), "new B\n");
    fs::remove_all(other);  // the last rename cannot succeed
    try {
      g.commit();
      ADD_FAILURE() << "commit succeeded without b's folder";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("no output written"), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(content(a), "old A\n");  // restored
  EXPECT_FALSE(fs::exists(fresh));   // a new target of the failed group is gone again
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(d)) ++files;
  EXPECT_EQ(files, 1u);  // no temporaries or backups left
  fs::remove_all(d);
  fs::remove_all(other);
}

// Issue 29, item 4: a folder made for outputs (--report-png DIR) is one of the group's outputs:
// it stays with its files when the group commits and goes with them when it does not, also when
// a rename fails; without a group it stays.
TEST(Files, OutputDirectoryBelongsToTheGroup) {
  const fs::path d = files_fresh_dir("group-dir");
  const fs::path made = d / "png", file = made / "r-plot-1.png";
  {
    OutputGroup g;
    create_output_directory(made.string());
    EXPECT_TRUE(fs::is_directory(made));  // there for the files to be written into
    write_file_atomically(file.string(), "png\n");
  }
  EXPECT_FALSE(fs::exists(made));  // abandoned: files and folder gone
  {
    OutputGroup g;
    create_output_directory(made.string());
    write_file_atomically(file.string(), "png\n");
    g.commit();
  }
  EXPECT_EQ(content(file), "png\n");
  fs::remove_all(made);
  const fs::path other = files_fresh_dir("group-dir-b");
  {
    OutputGroup g;
    create_output_directory(made.string());
    write_file_atomically(file.string(), "png\n");
    write_file_atomically((other / "b.csv").string(), "b\n");
    fs::remove_all(other);  // the last rename fails: the group undoes the first, then the folder
    EXPECT_THROW(g.commit(), Error);
  }
  EXPECT_FALSE(fs::exists(made));
  create_output_directory(made.string());  // no group: it stays
  EXPECT_TRUE(fs::is_directory(made));
  EXPECT_THROW(create_output_directory((d / "no" / "such").string()), Error);  // the parent must exist
  EXPECT_THROW(create_output_directory(made.string()), Error);                 // exists already
  fs::remove_all(d);
  fs::remove_all(other);
}

TEST(Files, InputLimitIsALimitError) {
  const fs::path d = files_fresh_dir("limit");
  const fs::path p = d / "big.csv";
  std::ofstream(p) << std::string(5000, 'x');
  const auto saved = input_limits();
  input_limits().text = 4096;
  try {
    (void)read_text_file(p.string(), "CSV file");
    ADD_FAILURE() << "read a file beyond the limit";
  } catch (const LimitError& e) {
    EXPECT_EQ(e.limit(), Limit::InputSize);
    EXPECT_NE(std::string(e.what()).find("larger than 4 KiB"), std::string::npos) << e.what();
  }
  input_limits() = saved;
  EXPECT_EQ(read_text_file(p.string()).size(), 5000u);
  fs::remove_all(d);
}
