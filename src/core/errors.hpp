#pragma once
// Error classes mapped to the exit codes of CONTRACT.md.
#include <stdexcept>
#include <string>

namespace varsph {

enum ExitCode : int {
  kExitOk = 0,
  kExitInternal = 1,
  kExitInput = 2,
  kExitNumerical = 3,
  kExitIo = 4,
  kExitSigint = 130,
  kExitSigterm = 143,
};

// Invalid input or usage: scene, --set, command line, mesh, checkpoint (exit 2).
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
// NaN, blow-up, non-converging fixed point (exit 3).
struct NumericalError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
// Disk full, unwritable directory (exit 4).
struct IoError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace varsph
