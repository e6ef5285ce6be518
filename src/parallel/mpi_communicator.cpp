#include "parallel/mpi_communicator.hpp"

#ifdef VARSPH_HAVE_MPI
#include <mpi.h>

#include <climits>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace varsph::parallel {
namespace {

// Messages longer than INT_MAX bytes go as a contiguous type of 1 MiB blocks plus a byte tail.
constexpr std::size_t kBlock = std::size_t(1) << 20;

class Mpi final : public Communicator {
 public:
  explicit Mpi(MPI_Comm c) : comm_(c) {
    MPI_Comm_rank(comm_, &rank_);
    MPI_Comm_size(comm_, &size_);
    counts_.resize(std::size_t(size_));
    displs_.resize(std::size_t(size_));
    MPI_Type_contiguous(int(kBlock), MPI_BYTE, &block_);
    MPI_Type_commit(&block_);
    MPI_Comm node;
    if (MPI_Comm_split_type(comm_, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &node) == MPI_SUCCESS) {
      MPI_Comm_size(node, &node_size_);
      MPI_Comm_free(&node);
    }
  }
  int node_size() const override { return node_size_; }
  ~Mpi() override {
    int finalized = 0;
    MPI_Finalized(&finalized);
    if (!finalized) MPI_Type_free(&block_);
  }
  int rank() const override { return rank_; }
  int size() const override { return size_; }

  void sum(std::span<double> v) override { reduce(v.data(), int(v.size()), MPI_DOUBLE, MPI_SUM); }
  void sum(std::span<std::int64_t> v) override { reduce(v.data(), int(v.size()), MPI_INT64_T, MPI_SUM); }
  void max(std::span<double> v) override { reduce(v.data(), int(v.size()), MPI_DOUBLE, MPI_MAX); }
  void min(std::span<double> v) override { reduce(v.data(), int(v.size()), MPI_DOUBLE, MPI_MIN); }
  std::int64_t exscan(std::int64_t v) override {
    WaitTimer t(wait_seconds_);
    std::int64_t out = 0;
    check(MPI_Exscan(&v, &out, 1, MPI_INT64_T, MPI_SUM, comm_), "MPI_Exscan");
    return rank_ == 0 ? 0 : out;
  }
  std::vector<std::int64_t> allgather(std::int64_t v) override {
    WaitTimer t(wait_seconds_);
    std::vector<std::int64_t> out(static_cast<std::size_t>(size_));
    check(MPI_Allgather(&v, 1, MPI_INT64_T, out.data(), 1, MPI_INT64_T, comm_), "MPI_Allgather");
    return out;
  }
  std::vector<double> allgather(double v) override {
    WaitTimer t(wait_seconds_);
    std::vector<double> out(static_cast<std::size_t>(size_));
    check(MPI_Allgather(&v, 1, MPI_DOUBLE, out.data(), 1, MPI_DOUBLE, comm_), "MPI_Allgather");
    return out;
  }
  void allgatherv(std::span<const std::byte> local, std::vector<std::byte>& out) override {
    WaitTimer t(wait_seconds_);
    if (local.size() > std::size_t(INT_MAX)) throw std::runtime_error("allgatherv: payload above INT_MAX bytes");
    const int n = int(local.size());
    check(MPI_Allgather(&n, 1, MPI_INT, counts_.data(), 1, MPI_INT, comm_), "MPI_Allgather");
    std::size_t total = 0;
    for (int q = 0; q < size_; ++q) {
      if (total > std::size_t(INT_MAX)) throw std::runtime_error("allgatherv: payload above INT_MAX bytes");
      displs_[std::size_t(q)] = int(total);
      total += std::size_t(counts_[std::size_t(q)]);
    }
    out.resize(total);
    check(MPI_Allgatherv(local.data(), n, MPI_BYTE, out.data(), counts_.data(), displs_.data(), MPI_BYTE, comm_),
          "MPI_Allgatherv");
  }
  std::string broadcast(const std::string& s, int root) override {
    WaitTimer t(wait_seconds_);
    long long n = (long long)s.size();
    check(MPI_Bcast(&n, 1, MPI_LONG_LONG, root, comm_), "MPI_Bcast");
    std::string out = rank_ == root ? s : std::string(std::size_t(n), '\0');
    if (n > 0) check(MPI_Bcast(out.data(), int(n), MPI_CHAR, root, comm_), "MPI_Bcast");
    return out;
  }
  void barrier() override {
    WaitTimer t(wait_seconds_);
    check(MPI_Barrier(comm_), "MPI_Barrier");
  }
  std::vector<std::int64_t> alltoall(const std::vector<std::int64_t>& c) override {
    WaitTimer t(wait_seconds_);
    std::vector<std::int64_t> out(static_cast<std::size_t>(size_));
    check(MPI_Alltoall(c.data(), 1, MPI_INT64_T, out.data(), 1, MPI_INT64_T, comm_), "MPI_Alltoall");
    return out;
  }
  void begin_exchange(std::span<const Message> out, std::span<const Message> in) override {
    WaitTimer t(wait_seconds_);
    requests_.clear();
    for (const Message& m : in) post(m, true);
    for (const Message& m : out) post(m, false);
  }
  void finish_exchange() override {
    WaitTimer t(wait_seconds_);
    if (!requests_.empty())
      check(MPI_Waitall(int(requests_.size()), requests_.data(), MPI_STATUSES_IGNORE), "MPI_Waitall");
    requests_.clear();
  }

 private:
  static void check(int rc, const char* what) {
    if (rc != MPI_SUCCESS) throw std::runtime_error(std::string("MPI call failed: ") + what);
  }
  void reduce(void* data, int n, MPI_Datatype type, MPI_Op op) {
    WaitTimer t(wait_seconds_);
    check(MPI_Allreduce(MPI_IN_PLACE, data, n, type, op, comm_), "MPI_Allreduce");
  }
  // One message as up to two requests (whole 1 MiB blocks, then the byte tail); tag 1 / 2 keeps the
  // parts of one message apart (MPI keeps the order of messages with the same peer and tag).
  void post(const Message& m, bool receive) {
    const std::size_t blocks = m.bytes / kBlock, tail = m.bytes % kBlock;
    if (blocks > std::size_t(INT_MAX)) throw std::runtime_error("MPI message too large");
    auto one = [&](void* p, int count, MPI_Datatype type, int tag) {
      requests_.emplace_back();
      if (receive) check(MPI_Irecv(p, count, type, m.peer, tag, comm_, &requests_.back()), "MPI_Irecv");
      else check(MPI_Isend(p, count, type, m.peer, tag, comm_, &requests_.back()), "MPI_Isend");
    };
    if (blocks > 0) one(m.data, int(blocks), block_, 1);
    if (tail > 0 || m.bytes == 0) one(m.data + blocks * kBlock, int(tail), MPI_BYTE, 2);
  }

  MPI_Comm comm_;
  int rank_ = 0, size_ = 1, node_size_ = 1;
  MPI_Datatype block_;
  std::vector<MPI_Request> requests_;
  std::vector<int> counts_, displs_;  // allgatherv: one per rank, sized once
};

}  // namespace

std::shared_ptr<Communicator> MpiCommunicator::initialise(int& argc, char**& argv) {
  int provided = 0;
  if (MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS) {
    std::fprintf(stderr, "varsph: error: MPI_Init_thread failed\n");
    std::exit(1);
  }
  // errors come back as return codes (turned into exceptions above), not as an abort inside MPI
  MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
  return std::make_shared<Mpi>(MPI_COMM_WORLD);
}

void MpiCommunicator::finalise() {
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (!finalized) MPI_Finalize();
}

void MpiCommunicator::abort_all(int code) {
  std::fflush(stdout);
  std::fflush(stderr);
  MPI_Abort(MPI_COMM_WORLD, code);
  std::_Exit(code);
}

}  // namespace varsph::parallel
#endif
