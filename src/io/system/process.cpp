// Running another program without a shell, with a time limit (io/system/process.hpp).
#include "mtcal/io/system/process.hpp"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <string_view>
#include <utility>

#include <fcntl.h>
#include <poll.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "mtcal/util/errors.hpp"

extern char** environ;

namespace mtcal {
namespace {

bool executable(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::access(path.c_str(), X_OK) == 0;
}

// Closes a descriptor once.
struct Fd {
  int fd = -1;
  ~Fd() { reset(); }
  void reset() {
    if (fd >= 0) ::close(fd);
    fd = -1;
  }
};

}  // namespace

std::optional<std::string> find_program(const std::vector<std::string>& names) {
  const char* path_env = std::getenv("PATH");
  const std::string path = path_env ? path_env : "/usr/local/bin:/usr/bin:/bin";
  for (const auto& name : names) {
    if (name.empty()) continue;
    if (name.find('/') != std::string::npos) {
      if (executable(name)) return name;
      continue;
    }
    std::size_t start = 0;
    while (start <= path.size()) {
      const std::size_t end = std::min(path.find(':', start), path.size());
      const std::string dir = end > start ? path.substr(start, end - start) : ".";
      const std::string candidate = dir + "/" + name;
      if (executable(candidate)) return candidate;
      start = end + 1;
    }
  }
  return std::nullopt;
}

ProgramRun run_program(const std::vector<std::string>& argv, double timeout_s, std::size_t max_output,
                       const std::string& working_dir, const std::vector<std::string>& environment) {
  if (argv.empty()) throw Error("run_program: no program given");
  for (const auto& v : environment)
    if (v.empty() || v.front() == '=' || v.find('=') == std::string::npos)
      throw Error("run_program: environment entry '" + v + "' is not NAME=value");
  // The inherited environment less the variables environment sets, then environment's.
  std::vector<char*> envp;
  for (char** e = environ; *e != nullptr; ++e) {
    const std::string_view var(*e);
    const bool replaced = std::any_of(environment.begin(), environment.end(), [&](const std::string& v) {
      const auto eq = v.find('=');
      return var.size() > eq && var.substr(0, eq + 1) == std::string_view(v).substr(0, eq + 1);
    });
    if (!replaced) envp.push_back(*e);
  }
  for (const auto& v : environment) envp.push_back(const_cast<char*>(v.c_str()));
  envp.push_back(nullptr);
  int out_pipe[2], err_pipe[2];
  if (::pipe2(out_pipe, O_CLOEXEC) != 0) throw Error("cannot start " + argv[0] + ": pipe: " + std::strerror(errno));
  Fd out_r{out_pipe[0]}, out_w{out_pipe[1]};
  if (::pipe2(err_pipe, O_CLOEXEC) != 0) throw Error("cannot start " + argv[0] + ": pipe: " + std::strerror(errno));
  Fd err_r{err_pipe[0]}, err_w{err_pipe[1]};

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, out_w.fd, 1);
  posix_spawn_file_actions_adddup2(&actions, err_w.fd, 2);
  // glibc's addchdir_np (2.29; Debian 12 has 2.36): the child changes directory, the caller does not.
  if (!working_dir.empty()) posix_spawn_file_actions_addchdir_np(&actions, working_dir.c_str());
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  // A process group of its own, so that the time limit ends the program's helpers with it; the
  // default signal dispositions, whatever this process ignores (SIGXFSZ, SIGPIPE).
  sigset_t defaults;
  sigemptyset(&defaults);
  for (int s : {SIGPIPE, SIGXFSZ, SIGINT, SIGTERM, SIGHUP}) sigaddset(&defaults, s);
  sigset_t none;
  sigemptyset(&none);
  posix_spawnattr_setsigdefault(&attr, &defaults);
  posix_spawnattr_setsigmask(&attr, &none);
  posix_spawnattr_setpgroup(&attr, 0);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETPGROUP | POSIX_SPAWN_SETSIGDEF | POSIX_SPAWN_SETSIGMASK);

  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = -1;
  const int rc = ::posix_spawn(&pid, argv[0].c_str(), &actions, &attr, args.data(), envp.data());
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attr);
  if (rc != 0) throw Error("cannot start " + argv[0] + ": " + std::strerror(rc));
  out_w.reset();
  err_w.reset();

  ProgramRun run;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  int status = 0;
  bool exited = false;
  char buf[65536];
  // Reads what is there (poll said so); closes the pipe at end of file.
  auto drain = [&](Fd& fd, std::string& into) {
    const ssize_t n = ::read(fd.fd, buf, sizeof buf);
    if (n > 0 && into.size() < max_output)
      into.append(buf, std::min<std::size_t>(static_cast<std::size_t>(n), max_output - into.size()));
    if (n == 0 || (n < 0 && errno != EINTR && errno != EAGAIN)) fd.reset();
  };
  while (true) {
    if (!exited) {
      const pid_t w = ::waitpid(pid, &status, WNOHANG);
      if (w == pid) exited = true;
    }
    // Once the program has exited, what its helpers still hold open is not waited for.
    if (exited) {
      for (auto [fd, into] : {std::pair{&out_r, &run.out}, std::pair{&err_r, &run.err}}) {
        if (fd->fd < 0) continue;
        ::fcntl(fd->fd, F_SETFL, ::fcntl(fd->fd, F_GETFL) | O_NONBLOCK);
        while (true) {
          const ssize_t n = ::read(fd->fd, buf, sizeof buf);
          if (n > 0 && into->size() < max_output)
            into->append(buf, std::min<std::size_t>(static_cast<std::size_t>(n), max_output - into->size()));
          if (n > 0 || (n < 0 && errno == EINTR)) continue;
          break;  // end of file, or nothing more while a helper holds the pipe open
        }
      }
      break;
    }
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) {
      run.timed_out = true;
      ::kill(-pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      exited = true;
      break;
    }
    pollfd fds[2];
    nfds_t n = 0;
    if (out_r.fd >= 0) fds[n++] = {out_r.fd, POLLIN, 0};
    if (err_r.fd >= 0) fds[n++] = {err_r.fd, POLLIN, 0};
    // A short tick: the program's exit is noticed by waitpid, not only by the pipes closing.
    const int ready = ::poll(fds, n, static_cast<int>(std::min<long long>(left.count(), 100)));
    if (ready > 0)
      for (nfds_t k = 0; k < n; ++k)
        if (fds[k].revents & (POLLIN | POLLHUP | POLLERR)) {
          Fd& fd = fds[k].fd == out_r.fd ? out_r : err_r;
          drain(fd, &fd == &out_r ? run.out : run.err);
        }
  }
  // Helpers the program left running in its group (a browser's zygote) end with it.
  ::kill(-pid, SIGKILL);
  if (WIFEXITED(status)) run.exit_status = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) run.signal = WTERMSIG(status);
  return run;
}

}  // namespace mtcal
