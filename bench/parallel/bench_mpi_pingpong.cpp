// Ping-pong between ranks 0 and 1 (half round trip: latency for small messages, bandwidth for large
// ones) and MPI_Allreduce of one double over all ranks. Prints a table; asserts nothing.
//   mpirun -n 2 build/release/bin/bench_mpi_pingpong [--repeats N]
#include <mpi.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  int repeats = 5;
  for (int k = 1; k + 1 < argc; ++k)
    if (std::strcmp(argv[k], "--repeats") == 0) repeats = std::max(1, std::atoi(argv[k + 1]));
  if (size < 2) {
    if (rank == 0) std::fprintf(stderr, "bench_mpi_pingpong: needs at least 2 ranks\n");
    MPI_Finalize();
    return 2;
  }
  if (rank == 0) std::printf("%12s %10s %14s %12s\n", "bytes", "iters", "one_way_us", "GB/s");
  std::vector<char> buf(std::size_t(64) << 20);
  for (std::size_t bytes = 8; bytes <= buf.size(); bytes *= 8) {
    const int iters = bytes <= 4096 ? 2000 : bytes <= (1 << 20) ? 200 : 20;
    double best = 1e300;
    for (int r = 0; r < repeats; ++r) {
      MPI_Barrier(MPI_COMM_WORLD);
      const double t0 = MPI_Wtime();
      for (int i = 0; i < iters; ++i) {
        if (rank == 0) {
          MPI_Send(buf.data(), int(bytes), MPI_BYTE, 1, 0, MPI_COMM_WORLD);
          MPI_Recv(buf.data(), int(bytes), MPI_BYTE, 1, 0, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        } else if (rank == 1) {
          MPI_Recv(buf.data(), int(bytes), MPI_BYTE, 0, 0, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
          MPI_Send(buf.data(), int(bytes), MPI_BYTE, 0, 0, MPI_COMM_WORLD);
        }
      }
      best = std::min(best, (MPI_Wtime() - t0) / (2.0 * iters));
    }
    if (rank == 0) std::printf("%12zu %10d %14.3f %12.3f\n", bytes, iters, best * 1e6, double(bytes) / best / 1e9);
  }
  double best = 1e300;
  for (int r = 0; r < repeats; ++r) {
    double v = rank, out = 0;
    MPI_Barrier(MPI_COMM_WORLD);
    const double t0 = MPI_Wtime();
    for (int i = 0; i < 2000; ++i) MPI_Allreduce(&v, &out, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
    best = std::min(best, (MPI_Wtime() - t0) / 2000.0);
  }
  if (rank == 0) std::printf("allreduce(1 double) over %d ranks: %.3f us\n", size, best * 1e6);
  MPI_Finalize();
  return 0;
}
