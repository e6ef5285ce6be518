#include "parallel/collective.hpp"

#include <stdexcept>

#include "core/errors.hpp"

namespace varsph::parallel {
namespace {
std::atomic<bool> g_agreed{false};
}

bool agreed_failure() { return g_agreed.load(); }
void mark_agreed_failure() { g_agreed.store(true); }

std::string first_message(Communicator& comm, const std::string& local) {
  if (comm.size() == 1) return local;
  const auto has = comm.allgather(std::int64_t(local.empty() ? 0 : 1));
  for (int r = 0; r < int(has.size()); ++r)
    if (has[std::size_t(r)]) return comm.broadcast(local, r);
  return {};
}

namespace detail {

int error_kind(const std::exception_ptr& e, std::string& message) {
  try {
    std::rethrow_exception(e);
  } catch (const InputError& x) {
    message = x.what();
    return 2;
  } catch (const NumericalError& x) {
    message = x.what();
    return 3;
  } catch (const IoError& x) {
    message = x.what();
    return 4;
  } catch (const std::exception& x) {
    message = x.what();
    return 1;
  } catch (...) {
    message = "unknown exception";
    return 1;
  }
}

void throw_kind(int kind, const std::string& message) {
  switch (kind) {
    case 2: throw InputError(message);
    case 3: throw NumericalError(message);
    case 4: throw IoError(message);
    default: throw std::runtime_error(message);
  }
}

}  // namespace detail
}  // namespace varsph::parallel
