#pragma once
// P ranks whose particles all live in this one process (partition tests and studies): every reduction is
// the identity, which is exact when each "rank" already holds the global data; nothing is exchanged.
#include "parallel/communicator.hpp"

namespace varsph::parallel {

class AllInOneCommunicator final : public Communicator {
 public:
  explicit AllInOneCommunicator(int p) : p_(p) {}
  int rank() const override { return 0; }
  int size() const override { return p_; }
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
  void begin_exchange(std::span<const Message>, std::span<const Message>) override {}
  void finish_exchange() override {}

 private:
  int p_;
};

}  // namespace varsph::parallel
