// What an OpenMP fork/join costs against a worksharing loop inside an existing parallel region (issue 19
// point 2: "one parallel region per step, no fork/join per loop"). Times R repetitions of a light loop over
// N doubles three ways: a `parallel for` per loop (what the step does today, ~10 per Verlet step), an
// `omp for` per loop inside one parallel region (the refactor's best case: a barrier per loop), and the
// same loop serially. Prints microseconds per loop; the difference of the first two, times the regions per
// step (callgrind's GOMP_parallel count, docs/performance.md), is the most the refactor can save per step.
//   bench_fork_join [N = 2030 (the paper scene's particles)] [R = 100000]; threads from OMP_NUM_THREADS
#include <omp.h>

#include <cstdio>
#include <cstdlib>
#include <vector>

namespace {

void touch(double* a, long n) {
  for (long i = 0; i < n; ++i) a[i] = a[i] * 1.0000001 + 1e-9;
}

}  // namespace

int main(int argc, char** argv) {
  const long n = argc > 1 ? std::atol(argv[1]) : 2030;
  const int reps = argc > 2 ? std::atoi(argv[2]) : 100000;
  if (n <= 0 || reps <= 0) {
    std::fprintf(stderr, "usage: bench_fork_join [N > 0] [R > 0]\n");
    return 2;
  }
  std::vector<double> a(std::size_t(n), 1.0);
  double* p = a.data();
  const double t0 = omp_get_wtime();
  for (int r = 0; r < reps; ++r) {
#pragma omp parallel for schedule(static)
    for (long i = 0; i < n; ++i) p[i] = p[i] * 1.0000001 + 1e-9;
  }
  const double t1 = omp_get_wtime();
#pragma omp parallel
  for (int r = 0; r < reps; ++r) {
#pragma omp for schedule(static)
    for (long i = 0; i < n; ++i) p[i] = p[i] * 1.0000001 + 1e-9;
  }
  const double t2 = omp_get_wtime();
  for (int r = 0; r < reps; ++r) touch(p, n);
  const double t3 = omp_get_wtime();
  const double fork = (t1 - t0) / reps * 1e6, inside = (t2 - t1) / reps * 1e6, serial = (t3 - t2) / reps * 1e6;
  std::printf("threads %d, N %ld, %d loops each (checksum %.6g)\n", omp_get_max_threads(), n, reps, p[n / 2]);
  std::printf("%-44s %8.3f us per loop\n", "parallel for (a fork/join per loop)", fork);
  std::printf("%-44s %8.3f us per loop\n", "omp for inside one region (a barrier)", inside);
  std::printf("%-44s %8.3f us per loop\n", "serial loop", serial);
  std::printf("saving of one region per loop: %.3f us per loop\n", fork - inside);
  return 0;
}
