/* Counts a process's MPI calls through the profiling interface (PMPI) and prints them at MPI_Finalize:
 * the messages and collectives per step behind the latency term of the cluster projection
 * (docs/performance.md "Beyond one machine"). Not part of the build:
 *   mpicc -O2 -shared -fPIC bench/parallel/mpi_call_counter.c -o /tmp/libmpicount.so
 *   mpirun -n 2 -x LD_PRELOAD=/tmp/libmpicount.so build/release/bin/varsph run SCENE ...
 * Each rank prints one line "mpi_calls rank R: isend N (bytes B) irecv N allreduce N ..." on stderr. */
#include <mpi.h>
#include <stdio.h>

static long long n_isend, n_irecv, n_allreduce, n_allgather, n_alltoall, n_bcast, n_barrier, n_exscan, n_waitall;
static long long isend_bytes;

int MPI_Isend(const void* buf, int count, MPI_Datatype type, int dest, int tag, MPI_Comm comm, MPI_Request* req) {
  int size = 0;
  PMPI_Type_size(type, &size);
  ++n_isend;
  isend_bytes += (long long)count * size;
  return PMPI_Isend(buf, count, type, dest, tag, comm, req);
}
int MPI_Irecv(void* buf, int count, MPI_Datatype type, int src, int tag, MPI_Comm comm, MPI_Request* req) {
  ++n_irecv;
  return PMPI_Irecv(buf, count, type, src, tag, comm, req);
}
int MPI_Allreduce(const void* s, void* r, int count, MPI_Datatype type, MPI_Op op, MPI_Comm comm) {
  ++n_allreduce;
  return PMPI_Allreduce(s, r, count, type, op, comm);
}
int MPI_Allgather(const void* s, int sc, MPI_Datatype st, void* r, int rc, MPI_Datatype rt, MPI_Comm comm) {
  ++n_allgather;
  return PMPI_Allgather(s, sc, st, r, rc, rt, comm);
}
int MPI_Alltoall(const void* s, int sc, MPI_Datatype st, void* r, int rc, MPI_Datatype rt, MPI_Comm comm) {
  ++n_alltoall;
  return PMPI_Alltoall(s, sc, st, r, rc, rt, comm);
}
int MPI_Bcast(void* b, int c, MPI_Datatype t, int root, MPI_Comm comm) {
  ++n_bcast;
  return PMPI_Bcast(b, c, t, root, comm);
}
int MPI_Barrier(MPI_Comm comm) {
  ++n_barrier;
  return PMPI_Barrier(comm);
}
int MPI_Exscan(const void* s, void* r, int c, MPI_Datatype t, MPI_Op op, MPI_Comm comm) {
  ++n_exscan;
  return PMPI_Exscan(s, r, c, t, op, comm);
}
int MPI_Waitall(int n, MPI_Request* reqs, MPI_Status* st) {
  ++n_waitall;
  return PMPI_Waitall(n, reqs, st);
}
int MPI_Finalize(void) {
  int rank = -1;
  PMPI_Comm_rank(MPI_COMM_WORLD, &rank);
  fprintf(stderr,
          "mpi_calls rank %d: isend %lld (bytes %lld) irecv %lld waitall %lld allreduce %lld allgather %lld "
          "alltoall %lld bcast %lld barrier %lld exscan %lld\n",
          rank, n_isend, isend_bytes, n_irecv, n_waitall, n_allreduce, n_allgather, n_alltoall, n_bcast, n_barrier,
          n_exscan);
  return PMPI_Finalize();
}
