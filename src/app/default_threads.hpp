#pragma once
// The default thread count of one process on a shared machine (issue 35, point 6). OpenMP's default, one
// thread per core with threads that spin while they wait, collapses when other jobs hold cores: measured on
// the 2-core build machine at load average 7.5-8.5, the paper's dam break (1,682 particles, 500 steps) took
// 0.78 s on 1 thread and 26.9 s on 2 (5.1 s in a second try), and a 27k-particle case 4.95 s on 1 thread and
// 14.5 s on 2 (README "Threads on a busy machine"). On an idle machine 2 threads are 1.7-2.3x faster
// (docs/performance.md). So: one thread per core that the load average says is free, at least one.
#include <algorithm>
#include <cmath>
#include <fstream>

namespace varsph {

// Threads for `cores` cores when the 1-minute load average is `load`: whole busy cores are left out.
inline int threads_for_load(int cores, double load) {
  if (!(load >= 0) || cores < 1) return std::max(cores, 1);
  return std::max(1, cores - int(std::floor(load)));
}

// The 1-minute load average (/proc/loadavg), or -1 where there is none.
inline double load_average() {
  std::ifstream in("/proc/loadavg");
  double load = -1;
  if (!(in >> load)) return -1;
  return load;
}

}  // namespace varsph
