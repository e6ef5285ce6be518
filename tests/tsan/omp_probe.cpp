// ThreadSanitizer probe of the OpenMP runtime (docs/reliability.md, "ThreadSanitizer"): a race-free loop in
// which each thread writes its own slots, as varsph's pair loop does, and with -DRACE=1 a planted race on a
// shared counter. Built by hand, not by CMake:
//   clang++-14 -O0 -g -fopenmp=libomp -fsanitize=thread [-DRACE=1] tests/tsan/omp_probe.cpp -o probe
//   g++ -O1 -g -fopenmp -fsanitize=thread tests/tsan/omp_probe.cpp -o probe_gcc
#include <cstdio>
#include <vector>
int main() {
  std::vector<double> a(100000), b(100000, 1.0);
  double shared = 0;
  for (int rep = 0; rep < 3; ++rep) {
#pragma omp parallel for schedule(static)
    for (int i = 0; i < (int)a.size(); ++i) {
      a[i] = b[i] * 2 + (i > 0 ? b[i - 1] : 0);
#if RACE
      shared += 1;
#endif
    }
  }
  std::printf("%g %g\n", a[5], shared);
}
