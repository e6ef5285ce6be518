#include "study/child_process.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <chrono>
#include <cstdlib>
#include <cstring>

#include "core/errors.hpp"

namespace varsph::study {
namespace {
volatile std::sig_atomic_t g_interrupt = 0;
extern "C" void on_interrupt(int sig) { g_interrupt = sig; }
}  // namespace

void install_interrupt_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_interrupt;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = 0;  // no SA_RESTART: the wait for a level returns EINTR, so the signal can be passed on
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

int interrupt_signal() { return g_interrupt; }

std::filesystem::path self_executable() {
  std::error_code ec;
  auto p = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) throw IoError("cannot resolve /proc/self/exe to run the study's levels: " + ec.message());
  return p;
}

ChildResult run_child(const std::vector<std::string>& argv, const std::filesystem::path& log) {
  ChildResult r;
  double la[1] = {0};
  if (getloadavg(la, 1) == 1) r.load_before = la[0];
  const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (fd < 0) throw IoError(log.string() + ": cannot open the level's log for writing: " + std::strerror(errno));
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const auto t0 = std::chrono::steady_clock::now();
  const pid_t pid = fork();
  if (pid < 0) {
    ::close(fd);
    throw IoError(std::string("fork failed: ") + std::strerror(errno));
  }
  if (pid == 0) {
    ::dup2(fd, STDOUT_FILENO);
    ::dup2(fd, STDERR_FILENO);
    ::execv(args[0], args.data());
    const char msg[] = "varsph study: exec of the level run failed\n";
    ssize_t ignored = ::write(STDERR_FILENO, msg, sizeof msg - 1);
    (void)ignored;
    _exit(127);
  }
  ::close(fd);
  int status = 0;
  struct rusage ru {};
  pid_t w;
  bool forwarded = false;
  for (;;) {
    w = wait4(pid, &status, 0, &ru);
    if (!(w < 0 && errno == EINTR)) break;
    // SIGINT / SIGTERM sent to the study alone: pass it on, so the level writes its checkpoint and stops
    if (const int sig = g_interrupt; sig && !forwarded) {
      ::kill(pid, sig);
      forwarded = true;
    }
  }
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (w < 0) throw IoError(std::string("waiting for the level run failed: ") + std::strerror(errno));
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : (WIFSIGNALED(status) ? 128 + WTERMSIG(status) : -1);
  r.cpu_seconds = double(ru.ru_utime.tv_sec) + 1e-6 * double(ru.ru_utime.tv_usec) + double(ru.ru_stime.tv_sec) +
                  1e-6 * double(ru.ru_stime.tv_usec);
  r.peak_rss_mb = double(ru.ru_maxrss) / 1024.0;
  if (getloadavg(la, 1) == 1) r.load_after = la[0];
  return r;
}

}  // namespace varsph::study
