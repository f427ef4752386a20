// Whole-file input, and output files that appear complete or not at all (temporary + rename).
#pragma once

#include <cstddef>
#include <fstream>
#include <string>

namespace mtcal {

// Largest input file read whole (the readers parse text in memory): 256 MiB.
constexpr std::size_t kMaxInputBytes = std::size_t{256} << 20;
// Largest YAML file (machine, parameters, prediction model): 16 MiB, far beyond any real one.
constexpr std::size_t kMaxYamlBytes = std::size_t{16} << 20;

// The whole content of a file; throws InputError ("cannot open <what>", or larger than
// max_bytes) naming the path.
std::string read_text_file(const std::string& path, const std::string& what = "file",
                           std::size_t max_bytes = kMaxInputBytes);

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
  // Flushes and renames the temporary file to path; throws Error if either fails.
  void commit();

 private:
  std::string path_, target_, tmp_;
  std::ofstream out_;
  bool committed_ = false;
  int slot_ = -1;  // entry in the list the signal handler cleans up
};

// Writes text to path through an AtomicFile.
void write_file_atomically(const std::string& path, const std::string& text);

}  // namespace mtcal
