// How much of a halo exchange can hide behind work on this MPI (a benchmark; asserts nothing). Ranks 0 and
// 1 exchange `bytes` each way as the halo refresh does (MPI_Irecv + MPI_Isend, then MPI_Waitall), with
// three schedules per size:
//   alone    post, wait at once                                     T_x: the exchange's own time
//   overlap  post, a fixed work W of about 2 T_x (busy loop), wait  T_w: post-to-end time minus W
//   poked    as overlap, with MPI_Testall after every 16th of W      (the Testall calls' cost counts in T_w)
// hidden = 1 - T_w / T_x: the share of the exchange that cost nothing. Rendezvous messages (above the transport's eager limit) move only when the
// library is entered, unless the network progresses them (RDMA) or a progress thread does; the table says
// which holds here. Best over --repeats rounds of the median over `iters` exchanges; both ranks run the
// same schedule.
//   mpirun -n 2 build/release/bin/bench_mpi_overlap [--repeats N]
#include <mpi.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

namespace {

// A fixed amount of busy work (what a sweep would do): `chunks` chunks of 1000 loop iterations, with
// MPI_Testall after every `poke` chunks when poke > 0.
void work(long chunks, long poke, int n_req, MPI_Request* req) {
  volatile double sink = 0;
  for (long c = 0; c < chunks; ++c) {
    for (int k = 0; k < 1000; ++k) sink = sink + 1e-9 * k;
    if (poke > 0 && (c + 1) % poke == 0) {
      int done = 0;
      MPI_Testall(n_req, req, &done, MPI_STATUSES_IGNORE);
    }
  }
}

// Median over the exchanges of the seconds from the post to the end of the wait, minus the work done in
// between (chunks < 0: no work). The median, not the mean: on a shared machine a rank descheduled for a
// time slice (ms) makes a few exchanges wait for it, which says nothing about the library.
double exchange(std::vector<char>& out, std::vector<char>& in, int peer, int iters, long chunks, long poke,
                double work_seconds) {
  std::vector<double> cost(std::size_t(iters), 0.0);
  for (int i = 0; i < iters; ++i) {
    MPI_Request req[2];
    const double t0 = MPI_Wtime();
    MPI_Irecv(in.data(), int(in.size()), MPI_BYTE, peer, 7, MPI_COMM_WORLD, &req[0]);
    MPI_Isend(out.data(), int(out.size()), MPI_BYTE, peer, 7, MPI_COMM_WORLD, &req[1]);
    if (chunks > 0) work(chunks, poke, 2, req);
    MPI_Waitall(2, req, MPI_STATUSES_IGNORE);
    cost[std::size_t(i)] = MPI_Wtime() - t0 - (chunks > 0 ? work_seconds : 0.0);
  }
  std::nth_element(cost.begin(), cost.begin() + iters / 2, cost.end());
  return std::max(0.0, cost[std::size_t(iters / 2)]);
}

// Seconds of `chunks` chunks of work alone (median of 51).
double time_work(long chunks) {
  std::vector<double> t(51);
  for (double& x : t) {
    const double t0 = MPI_Wtime();
    work(chunks, 0, 0, nullptr);
    x = MPI_Wtime() - t0;
  }
  std::nth_element(t.begin(), t.begin() + 25, t.end());
  return t[25];
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  int repeats = 5;
  for (int k = 1; k + 1 < argc; ++k)
    if (std::strcmp(argv[k], "--repeats") == 0) repeats = std::max(1, std::atoi(argv[k + 1]));
  if (size != 2) {
    if (rank == 0) std::fprintf(stderr, "bench_mpi_overlap: needs exactly 2 ranks\n");
    MPI_Finalize();
    return 2;
  }
  const int peer = 1 - rank;
  if (rank == 0)
    std::printf("%10s %6s %12s %12s %12s %12s %9s %9s\n", "bytes", "iters", "alone_us", "work_us", "left_us",
                "left_poked_us", "hidden", "hidden_p");
  for (std::size_t bytes : {std::size_t(512), std::size_t(4096), std::size_t(32768), std::size_t(262144),
                            std::size_t(2097152)}) {
    std::vector<char> out(bytes, char(rank)), in(bytes);
    const int iters = bytes <= 32768 ? 400 : 50;
    double alone = 1e300, wait = 1e300, poked = 1e300;
    for (int r = 0; r < repeats; ++r) {
      MPI_Barrier(MPI_COMM_WORLD);
      alone = std::min(alone, exchange(out, in, peer, iters, -1, 0, 0));
    }
    // work of about twice the exchange (at least 20 us): enough to hide all of it
    const double per_chunk = time_work(100) / 100;
    long chunks = std::max(16L, long(std::max(2 * alone, 20e-6) / per_chunk));
    MPI_Allreduce(MPI_IN_PLACE, &chunks, 1, MPI_LONG, MPI_MAX, MPI_COMM_WORLD);
    const double w = time_work(chunks);
    for (int r = 0; r < repeats; ++r) {
      MPI_Barrier(MPI_COMM_WORLD);
      wait = std::min(wait, exchange(out, in, peer, iters, chunks, 0, w));
      MPI_Barrier(MPI_COMM_WORLD);
      poked = std::min(poked, exchange(out, in, peer, iters, chunks, chunks / 16, w));
    }
    double v[4] = {alone, wait, poked, w};
    MPI_Allreduce(MPI_IN_PLACE, v, 4, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);  // the slower rank's figure
    if (rank == 0)
      std::printf("%10zu %6d %12.2f %12.2f %12.2f %12.2f %8.0f%% %8.0f%%\n", bytes, iters, v[0] * 1e6, v[3] * 1e6,
                  v[1] * 1e6, v[2] * 1e6, 100 * (1 - v[1] / v[0]), 100 * (1 - v[2] / v[0]));
  }
  MPI_Finalize();
  return 0;
}
