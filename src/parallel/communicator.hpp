#pragma once
// The only door to message passing. The decomposition layer (domain.hpp), the run loop's reductions and
// the output of pieces talk to other ranks through this interface; physics and integrators never do.
// Two implementations: SerialCommunicator (one process: every reduction is the identity, there is no
// peer) and MpiCommunicator (mpi_communicator.cpp, compiled only when CMake found MPI). A later rank that
// drives one GPU uses the same interface: the buffers it is handed are host memory.
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace varsph::parallel {

// One message of a sparse exchange: `bytes` to or from rank `peer`.
struct Message {
  int peer = 0;
  std::byte* data = nullptr;
  std::size_t bytes = 0;
};

class Communicator {
 public:
  virtual ~Communicator() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  bool root() const { return rank() == 0; }
  // Ranks on this machine (shared memory), for the default number of OpenMP threads per rank.
  virtual int node_size() const { return 1; }

  // In-place reductions over all ranks (every rank gets the result).
  virtual void sum(std::span<double> v) = 0;
  virtual void sum(std::span<std::int64_t> v) = 0;
  virtual void max(std::span<double> v) = 0;
  virtual void min(std::span<double> v) = 0;
  double sum(double v) { sum(std::span<double>(&v, 1)); return v; }
  std::int64_t sum(std::int64_t v) { sum(std::span<std::int64_t>(&v, 1)); return v; }
  double max(double v) { max(std::span<double>(&v, 1)); return v; }
  double min(double v) { min(std::span<double>(&v, 1)); return v; }
  // Exclusive prefix sum over ranks (rank 0 gets 0).
  virtual std::int64_t exscan(std::int64_t v) = 0;
  // Every rank's value, in rank order.
  virtual std::vector<std::int64_t> allgather(std::int64_t v) = 0;
  virtual std::vector<double> allgather(double v) = 0;
  // Every rank's bytes, concatenated in rank order, into `out` on every rank (small payloads: a gauge's
  // column of particles). `out` keeps its capacity: no allocation once it has held the largest payload.
  virtual void allgatherv(std::span<const std::byte> local, std::vector<std::byte>& out) = 0;
  // `root`'s string on every rank.
  virtual std::string broadcast(const std::string& s, int root) = 0;
  virtual void barrier() = 0;

  // counts_out[q] = what this rank sends to q; returns what every q sends to this rank.
  virtual std::vector<std::int64_t> alltoall(const std::vector<std::int64_t>& counts_out) = 0;
  // Sends every message in `out` and receives every message in `in` (sizes known on both sides).
  // begin/finish split it so that work can run while the messages travel.
  virtual void begin_exchange(std::span<const Message> out, std::span<const Message> in) = 0;
  virtual void finish_exchange() = 0;
  void exchange(std::span<const Message> out, std::span<const Message> in) {
    begin_exchange(out, in);
    finish_exchange();
  }

  // Seconds this rank spent inside communication calls (waiting included) since construction: the
  // busy time of a step is its wall time minus this (load-imbalance report).
  double wait_seconds() const { return wait_seconds_; }

 protected:
  // Adds the time of one communication call to wait_seconds().
  struct WaitTimer {
    explicit WaitTimer(double& acc) : acc_(acc), t0_(std::chrono::steady_clock::now()) {}
    ~WaitTimer() { acc_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count(); }
    double& acc_;
    std::chrono::steady_clock::time_point t0_;
  };
  double wait_seconds_ = 0;
};

// One process: reductions are the identity; there is never a peer to exchange with.
class SerialCommunicator final : public Communicator {
 public:
  int rank() const override { return 0; }
  int size() const override { return 1; }
  void sum(std::span<double>) override {}
  void sum(std::span<std::int64_t>) override {}
  void max(std::span<double>) override {}
  void min(std::span<double>) override {}
  std::int64_t exscan(std::int64_t) override { return 0; }
  std::vector<std::int64_t> allgather(std::int64_t v) override { return {v}; }
  std::vector<double> allgather(double v) override { return {v}; }
  void allgatherv(std::span<const std::byte> local, std::vector<std::byte>& out) override {
    out.assign(local.begin(), local.end());
  }
  std::string broadcast(const std::string& s, int) override { return s; }
  void barrier() override {}
  std::vector<std::int64_t> alltoall(const std::vector<std::int64_t>& c) override { return c; }
  void begin_exchange(std::span<const Message> out, std::span<const Message> in) override {
    if (!out.empty() || !in.empty()) throw std::logic_error("serial communicator: no peer to exchange with");
  }
  void finish_exchange() override {}
};

}  // namespace varsph::parallel
