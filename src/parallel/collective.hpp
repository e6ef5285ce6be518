#pragma once
// Agreement between ranks on failures and messages, so that an error raised on one rank (a file that
// cannot be written, a particle that blew up) stops every rank the same way: no rank is left waiting in
// a collective call, and every rank exits with the code the serial program would use.
#include <atomic>
#include <string>

#include "parallel/communicator.hpp"

namespace varsph::parallel {

// Runs `work` on every rank. If it throws on any rank, every rank throws the same kind of error
// (InputError, NumericalError, IoError, or std::runtime_error for anything else) carrying the message
// of the lowest failing rank, and agreed_failure() becomes true. Costs one allgather of one integer.
template <class Work>
void collectively(Communicator& comm, Work&& work);

// The first non-empty string in rank order (empty when all are empty); every rank gets it.
std::string first_message(Communicator& comm, const std::string& local);

// True once an error was agreed on by every rank (main then ends normally instead of aborting).
bool agreed_failure();
void mark_agreed_failure();

// --- implementation -------------------------------------------------------------------------------
namespace detail {
// 0 none, 1 internal, 2 input, 3 numerical, 4 I/O
int error_kind(const std::exception_ptr& e, std::string& message);
[[noreturn]] void throw_kind(int kind, const std::string& message);
}  // namespace detail

template <class Work>
void collectively(Communicator& comm, Work&& work) {
  std::exception_ptr error;
  try {
    work();
  } catch (...) {
    error = std::current_exception();
  }
  if (comm.size() == 1) {
    if (error) std::rethrow_exception(error);
    return;
  }
  std::string message;
  const int kind = error ? detail::error_kind(error, message) : 0;
  const auto kinds = comm.allgather(std::int64_t(kind));
  int first = -1;
  for (int r = 0; r < int(kinds.size()); ++r)
    if (kinds[std::size_t(r)] != 0) {
      first = r;
      break;
    }
  if (first < 0) return;
  message = comm.broadcast(message, first);
  mark_agreed_failure();
  detail::throw_kind(int(kinds[std::size_t(first)]), message);
}

}  // namespace varsph::parallel
