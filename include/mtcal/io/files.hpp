// Whole-file input, and output files that appear complete or not at all (temporary + rename).
#pragma once

#include <fstream>
#include <string>

namespace mtcal {

// The whole content of a file; throws InputError ("cannot open <what>") naming the path.
std::string read_text_file(const std::string& path, const std::string& what = "file");

class AtomicFile {
 public:
  // Opens a temporary file beside path; throws Error if it cannot.
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
  std::string path_, tmp_;
  std::ofstream out_;
  bool committed_ = false;
  int slot_ = -1;  // entry in the list the signal handler cleans up
};

// Writes text to path through an AtomicFile.
void write_file_atomically(const std::string& path, const std::string& text);

}  // namespace mtcal
