#pragma once
// Runs a child process (a `varsph run` of one study level) and measures it: wall seconds, CPU seconds and
// peak resident memory from wait4's rusage, the machine's load average before and after.
#include <filesystem>
#include <string>
#include <vector>

namespace varsph::study {

struct ChildResult {
  int exit_code = -1;        // the child's exit status; 128 + N when killed by signal N
  double wall_seconds = 0;   // fork to reap, steady clock
  double cpu_seconds = 0;    // user + system time of the child (ru_utime + ru_stime)
  double peak_rss_mb = 0;    // ru_maxrss (KiB on Linux) / 1024
  double load_before = 0, load_after = 0;  // 1-minute load average (getloadavg)
};

// Path of the running executable (/proc/self/exe), so a study runs its levels with the same build.
std::filesystem::path self_executable();

// SIGINT / SIGTERM set a flag (interrupt_signal()) instead of ending the study; a running level receives
// them too (process group, or passed on by run_child) and stops with a checkpoint.
void install_interrupt_handlers();
int interrupt_signal();

// Runs `argv` (argv[0] is the program path) with stdout and stderr appended to `log`. While the child
// runs, SIGINT / SIGTERM reach it through the process group; the caller sees them in the exit code.
ChildResult run_child(const std::vector<std::string>& argv, const std::filesystem::path& log);

}  // namespace varsph::study
