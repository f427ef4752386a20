#include "mtcal/io/files.hpp"

#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <stdlib.h>
#include <unistd.h>

#include "mtcal/util/errors.hpp"

namespace mtcal {

std::string read_text_file(const std::string& path, const std::string& what) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw InputError({path, 0, ""}, "is a directory; expected a " + what);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError({path, 0, ""}, "cannot open " + what);
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw InputError({path, 0, ""}, "cannot read " + what);
  return ss.str();
}

namespace {

// Temporary files being written, removed by the signal handler if the program is interrupted
// (fixed storage: a handler may only call async-signal-safe functions such as unlink).
constexpr int kMaxPending = 8;
char g_pending[kMaxPending][4096];
volatile std::sig_atomic_t g_used[kMaxPending];

extern "C" void remove_pending_and_exit(int sig) {
  for (int i = 0; i < kMaxPending; ++i)
    if (g_used[i]) ::unlink(g_pending[i]);
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

int register_pending(const std::string& path) {
  static const bool installed = [] {
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) std::signal(sig, remove_pending_and_exit);
    return true;
  }();
  (void)installed;
  if (path.size() >= sizeof g_pending[0]) return -1;
  for (int i = 0; i < kMaxPending; ++i) {
    if (g_used[i]) continue;
    std::memcpy(g_pending[i], path.c_str(), path.size() + 1);
    g_used[i] = 1;
    return i;
  }
  return -1;
}

}  // namespace

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)) {
  namespace fs = std::filesystem;
  const fs::path target(path_);
  std::error_code ec;
  if (target.filename().empty() || fs::is_directory(target, ec))
    throw Error("cannot write '" + path_ + "': it is a directory; expected a file name");
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  // A unique name (mkstemp): two outputs of one run, or two runs, never share a temporary file.
  std::string pattern = (dir / ("." + target.filename().string() + ".tmpXXXXXX")).string();
  const int fd = ::mkstemp(pattern.data());
  if (fd < 0) throw Error("cannot write '" + path_ + "': cannot create a file in " + dir.string());
  ::close(fd);
  tmp_ = pattern;
  out_.open(tmp_, std::ios::binary | std::ios::trunc);
  if (!out_) {
    std::remove(tmp_.c_str());
    throw Error("cannot write '" + path_ + "': cannot create a file in " + dir.string());
  }
  slot_ = register_pending(tmp_);
}

AtomicFile::~AtomicFile() {
  if (slot_ >= 0) g_used[slot_] = 0;
  if (committed_) return;
  out_.close();
  std::remove(tmp_.c_str());
}

void AtomicFile::commit() {
  out_.flush();
  if (!out_) throw Error("cannot write '" + path_ + "': write failed");
  out_.close();
  std::error_code ec;
  std::filesystem::rename(tmp_, path_, ec);
  if (ec) throw Error("cannot write '" + path_ + "': " + ec.message());
  committed_ = true;
}

void write_file_atomically(const std::string& path, const std::string& text) {
  AtomicFile f(path);
  f.stream() << text;
  f.commit();
}

}  // namespace mtcal
