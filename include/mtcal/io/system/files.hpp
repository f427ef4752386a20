// Whole-file input, and output files that appear complete or not at all (temporary + rename).
#pragma once

#include <cstddef>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

namespace mtcal {

// Largest input file read whole (the readers parse text in memory): 256 MiB.
constexpr std::size_t kMaxInputBytes = std::size_t{256} << 20;
// Largest YAML file (machine, parameters, prediction model): 16 MiB, far beyond any real one.
constexpr std::size_t kMaxYamlBytes = std::size_t{16} << 20;

// The limits in force (a program may raise them, e.g. mtcal --max-input-size; docs/reliability.md).
struct InputLimits {
  std::size_t text = kMaxInputBytes;  // CSV, .dat, G-code
  std::size_t yaml = kMaxYamlBytes;   // machine, parameter and prediction model files
};
InputLimits& input_limits();

// The whole content of a file; throws InputError ("cannot open <what>") or LimitError (larger
// than max_bytes; 0: input_limits().text) naming the path.
std::string read_text_file(const std::string& path, const std::string& what = "file", std::size_t max_bytes = 0);

// The permissions a new file of this process gets: wanted & ~umask.
unsigned permissions_from_umask(unsigned wanted);

class AtomicFile {
 public:
  // Opens a temporary file beside path; throws Error if it cannot, or if path is a directory or
  // exists and is not a regular file (a device such as /dev/null, a FIFO, a socket). A symbolic
  // link is followed: its target is replaced and the link kept. The file gets 0666 & ~umask.
  explicit AtomicFile(std::string path);
  // Removes the temporary file unless commit() succeeded. The temporary file is also removed if
  // the program is stopped by SIGINT, SIGTERM or SIGHUP while it is being written.
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  std::ostream& stream() { return out_; }
  // Throws Error (file-size limit, disk full ...) if a write to the stream has failed: long
  // streamed outputs call it per block instead of running on to the end after a failure.
  void check_stream();
  // Flushes and renames the temporary file to path; throws Error if either fails.
  void commit();

 private:
  std::string path_, target_, tmp_;
  std::ofstream out_;
  bool committed_ = false;
  int slot_ = -1;  // entry in the list the signal handler cleans up
};

// The outputs of one command appear together or not at all. While a group is open (one at a
// time, on the main thread), AtomicFile::commit() only completes its temporary file and hands it
// to the group; OutputGroup::commit() then renames every temporary file onto its target, with
// SIGINT/SIGTERM/SIGHUP held back meanwhile; if one rename fails, the targets already replaced
// are restored (hard-linked copies of the old files) and the rest removed. A group destroyed
// without commit() removes its temporary files: an exception or a failed write leaves no output.
class OutputGroup {
 public:
  OutputGroup();
  ~OutputGroup();
  OutputGroup(const OutputGroup&) = delete;
  OutputGroup& operator=(const OutputGroup&) = delete;
  // Renames every completed output; throws Error (nothing replaced) if one cannot be.
  void commit();
  // The group AtomicFile::commit() hands its file to, or null.
  static OutputGroup* current();
  struct Pending {
    std::string path, target, tmp;
    int slot = -1;
  };
  void add(Pending p);
  // A directory made for this group's files (create_output_directory): removed, once its files
  // are, unless the group commits.
  void add_directory(std::string path, int slot);

 private:
  void remove_directories();

  std::vector<Pending> files_;
  std::vector<std::pair<std::string, int>> dirs_;
  bool done_ = false;
};

// Makes the directory path (its parent must exist; mode 0777 & ~umask) for outputs to be written
// into, as `mkdir` does. While an output group is open, the directory is one of its outputs: it
// is removed again (with the group's files in it) if the group is destroyed without commit() or
// the program is stopped by SIGINT, SIGTERM or SIGHUP before then. Throws Error if it cannot.
void create_output_directory(const std::string& path);

// Writes text to path through an AtomicFile.
void write_file_atomically(const std::string& path, const std::string& text);

}  // namespace mtcal
