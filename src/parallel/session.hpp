#pragma once
// The process's place in a parallel run. MPI is initialised only when this build has MPI and the
// process was started by an MPI launcher (mpirun, mpiexec, srun: detected from the environment they
// set) or VARSPH_MPI=1 asks for it; otherwise the run is the serial program, unchanged, and needs no
// MPI runtime at all (tests and every command run directly keep working without mpirun).
#include <memory>
#include <string>

#include "parallel/communicator.hpp"

namespace varsph::parallel {

class Session {
 public:
  // Initialises MPI when launched by an MPI launcher (see above); argc/argv as given to main.
  Session(int& argc, char**& argv);
  ~Session();  // finalises MPI when it was initialised here
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  // The communicator over all processes of the run (a SerialCommunicator outside MPI).
  const std::shared_ptr<Communicator>& world() const { return world_; }
  bool distributed() const { return world_->size() > 1; }
  // Ends the process with `code`, and under MPI every other rank with it (MPI_Abort): for an error that
  // reached main on some ranks only, so that no rank is left waiting in a collective call.
  [[noreturn]] void abort(int code);

 private:
  std::shared_ptr<Communicator> world_;
  bool initialised_here_ = false;
};

// True when the build has MPI support compiled in (CMake found MPI, VARSPH_MPI not OFF).
bool mpi_compiled();
// True when an MPI launcher started this process (environment variables of OpenMPI, MPICH/Hydra, PMIx,
// Slurm's PMI) or VARSPH_MPI=1; false for a child of an Open MPI singleton (a program pvpython runs).
bool launched_by_mpi();
// The number of processes the launcher started (OMPI_COMM_WORLD_SIZE, PMI_SIZE, MV2_COMM_WORLD_SIZE,
// SLURM_STEP_NUM_TASKS), 0 when none of them is set or readable.
int launcher_world_size();
// Why a build without MPI must not run as started, or "" when it may: under a launcher with more than one
// process every copy would run the whole scene into the same run directory; VARSPH_MPI=1 asks for MPI
// that is not there. Pure: the caller passes what it read.
std::string refusal_without_mpi(bool mpi_compiled, bool launched, int world_size, bool forced);

}  // namespace varsph::parallel
