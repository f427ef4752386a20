#include "mtcal/io/system/files.hpp"

#include <cerrno>
#include <csignal>
#include <pthread.h>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fmt/format.h>

#include "mtcal/util/errors.hpp"

namespace mtcal {

InputLimits& input_limits() {
  static InputLimits limits;
  return limits;
}

std::string read_text_file(const std::string& path, const std::string& what, std::size_t max_bytes) {
  if (max_bytes == 0) max_bytes = input_limits().text;
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw InputError({path, 0, ""}, "is a directory; expected a " + what);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError({path, 0, ""}, "cannot open " + what);
  // Read in blocks and stop past the limit: /dev/zero or a runaway file must not fill the memory.
  std::string text;
  std::string block(1 << 16, '\0');
  while (in) {
    in.read(block.data(), static_cast<std::streamsize>(block.size()));
    text.append(block.data(), static_cast<std::size_t>(in.gcount()));
    if (text.size() > max_bytes)
      throw LimitError(Limit::InputSize, {path, 0, ""},
                       fmt::format("{} larger than {}: expected at most that much (a limit against runaway inputs)",
                                   what, format_bytes(static_cast<double>(max_bytes))));
  }
  if (in.bad()) throw InputError({path, 0, ""}, "cannot read " + what);
  return text;
}

namespace {

// Temporary files being written, removed by the signal handler if the program is interrupted
// (fixed storage: a handler may only call async-signal-safe functions such as unlink).
constexpr int kMaxPending = 64;
char g_pending[kMaxPending][4096];
volatile std::sig_atomic_t g_used[kMaxPending];

extern "C" void remove_pending_and_exit(int sig) {
  for (int i = 0; i < kMaxPending; ++i)
    if (g_used[i]) ::unlink(g_pending[i]);
  // Directories made for outputs, once the files in them are gone (rmdir leaves a full one).
  for (int i = kMaxPending - 1; i >= 0; --i)
    if (g_used[i]) ::rmdir(g_pending[i]);
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

unsigned permissions_from_umask(unsigned wanted) {
  // umask() can only be read by setting it; set it straight back (outputs are opened before any
  // worker thread creates files).
  const mode_t mask = ::umask(0);
  ::umask(mask);
  return wanted & ~static_cast<unsigned>(mask);
}

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)) {
  namespace fs = std::filesystem;
  fs::path target(path_);
  std::error_code ec;
  if (target.filename().empty() || fs::is_directory(target, ec))
    throw Error("cannot write '" + path_ + "': it is a directory; expected a file name");
  // A symbolic link is followed: the file it points to is replaced and the link stays (what an
  // editor does); renaming onto the link itself would turn it into a regular file.
  if (fs::is_symlink(fs::symlink_status(target, ec))) {
    target = fs::weakly_canonical(target, ec);
    if (ec) throw Error("cannot write '" + path_ + "': cannot resolve the symbolic link: " + ec.message());
    if (fs::is_directory(target, ec))
      throw Error("cannot write '" + path_ + "': it links to a directory; expected a file name");
  }
  // Only a regular file is replaced: renaming onto /dev/null, a FIFO or a socket would put a
  // regular file in the place of the device.
  const fs::file_status st = fs::status(target, ec);
  if (fs::exists(st) && !fs::is_regular_file(st))
    throw Error("cannot write '" + path_ +
                "': it is not a regular file (a device, FIFO or socket); expected a "
                "regular file or a new file name");
  target_ = target.string();
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  // A unique name (mkstemp): two outputs of one run, or two runs, never share a temporary file.
  std::string pattern = (dir / ("." + target.filename().string() + ".tmpXXXXXX")).string();
  const int fd = ::mkstemp(pattern.data());
  if (fd < 0) throw Error("cannot write '" + path_ + "': cannot create a file in " + dir.string());
  // mkstemp creates 0600; an output gets what any new file of the user gets (0666 & ~umask).
  (void)::fchmod(fd, static_cast<mode_t>(permissions_from_umask(0666)));
  ::close(fd);
  tmp_ = pattern;
  out_.open(tmp_, std::ios::binary | std::ios::trunc);
  if (!out_) {
    std::remove(tmp_.c_str());
    throw Error("cannot write '" + path_ + "': cannot create a file in " + dir.string());
  }
  slot_ = register_pending(tmp_);
}

namespace {
// Why a write failed: the file-size limit (EFBIG, with SIGXFSZ ignored), a full disk ...
std::string write_failure() {
  const int e = errno;
  if (e == EFBIG) return "the file is larger than the file-size limit (ulimit -f)";
  if (e == ENOSPC) return "no space left on the device";
  if (e == EDQUOT) return "disk quota exceeded";
  return e ? std::string("write failed: ") + std::strerror(e) : std::string("write failed");
}
}  // namespace

AtomicFile::~AtomicFile() {
  if (slot_ >= 0) g_used[slot_] = 0;
  if (committed_) return;
  out_.close();
  std::remove(tmp_.c_str());
}

void AtomicFile::check_stream() {
  if (!out_) throw Error("cannot write '" + path_ + "': " + write_failure());
}

void AtomicFile::commit() {
  out_.flush();
  if (!out_) throw Error("cannot write '" + path_ + "': " + write_failure());
  out_.close();
  if (!out_) throw Error("cannot write '" + path_ + "': " + write_failure());
  if (OutputGroup* g = OutputGroup::current()) {
    // The group renames it with the command's other outputs, or removes it.
    g->add({path_, target_, tmp_, slot_});
    slot_ = -1;
    committed_ = true;
    return;
  }
  std::error_code ec;
  std::filesystem::rename(tmp_, target_, ec);
  if (ec) throw Error("cannot write '" + path_ + "': " + ec.message());
  committed_ = true;
}

namespace {
OutputGroup* g_group = nullptr;

// Signals that would stop the program between two renames, held back while a group commits.
struct HoldSignals {
  sigset_t old{};
  HoldSignals() {
    sigset_t set;
    sigemptyset(&set);
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&set, sig);
    ::pthread_sigmask(SIG_BLOCK, &set, &old);
  }
  ~HoldSignals() { ::pthread_sigmask(SIG_SETMASK, &old, nullptr); }
};
}  // namespace

OutputGroup::OutputGroup() {
  if (g_group) throw Error("internal: an output group is already open");
  g_group = this;
}

OutputGroup::~OutputGroup() {
  g_group = nullptr;
  if (done_) return;
  for (const auto& f : files_) {
    std::remove(f.tmp.c_str());
    if (f.slot >= 0) g_used[f.slot] = 0;
  }
  remove_directories();
}

void OutputGroup::remove_directories() {
  // Newest first: a directory made inside another goes before it.
  for (auto it = dirs_.rbegin(); it != dirs_.rend(); ++it) {
    ::rmdir(it->first.c_str());
    if (it->second >= 0) g_used[it->second] = 0;
  }
  dirs_.clear();
}

void OutputGroup::add_directory(std::string path, int slot) { dirs_.emplace_back(std::move(path), slot); }

void create_output_directory(const std::string& path) {
  if (::mkdir(path.c_str(), 0777) != 0)  // the umask applies, as to any new directory
    throw Error("cannot create the directory '" + path + "': " + std::strerror(errno));
  OutputGroup* g = OutputGroup::current();
  if (!g) return;
  g->add_directory(path, register_pending(path));
}

OutputGroup* OutputGroup::current() { return g_group; }

void OutputGroup::add(Pending p) { files_.push_back(std::move(p)); }

void OutputGroup::commit() {
  g_group = nullptr;
  const HoldSignals hold;
  // Old versions of the targets, kept (hard links, same directory) until every rename is done.
  std::vector<std::string> backup(files_.size());
  for (std::size_t i = 0; i < files_.size(); ++i) {
    struct stat st {};
    if (::stat(files_[i].target.c_str(), &st) != 0) continue;
    std::string b = files_[i].tmp + ".old";
    if (::link(files_[i].target.c_str(), b.c_str()) == 0) backup[i] = b;
  }
  for (std::size_t i = 0; i < files_.size(); ++i) {
    if (std::rename(files_[i].tmp.c_str(), files_[i].target.c_str()) == 0) continue;
    const std::string why = std::strerror(errno);
    // Undo: the targets renamed so far get their old content back (or go, if they were new).
    for (std::size_t j = 0; j < i; ++j) {
      if (!backup[j].empty())
        (void)std::rename(backup[j].c_str(), files_[j].target.c_str());
      else
        (void)std::remove(files_[j].target.c_str());
    }
    for (std::size_t j = i; j < files_.size(); ++j) std::remove(files_[j].tmp.c_str());
    for (std::size_t j = i; j < files_.size(); ++j)
      if (!backup[j].empty()) std::remove(backup[j].c_str());
    for (const auto& f : files_)
      if (f.slot >= 0) g_used[f.slot] = 0;
    remove_directories();
    done_ = true;
    throw Error("cannot write '" + files_[i].path + "': " + why + " (no output written)");
  }
  for (const auto& b : backup)
    if (!b.empty()) std::remove(b.c_str());
  for (const auto& f : files_)
    if (f.slot >= 0) g_used[f.slot] = 0;
  for (const auto& d : dirs_)
    if (d.second >= 0) g_used[d.second] = 0;
  done_ = true;
}

void write_file_atomically(const std::string& path, const std::string& text) {
  AtomicFile f(path);
  f.stream() << text;
  f.commit();
}

}  // namespace mtcal
