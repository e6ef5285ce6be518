#pragma once
// MPI behind the Communicator interface (only in builds where CMake found MPI: VARSPH_HAVE_MPI).
// mpi.h stays inside mpi_communicator.cpp.
#include <memory>

#include "parallel/communicator.hpp"

namespace varsph::parallel {

#ifdef VARSPH_HAVE_MPI
struct MpiCommunicator {
  // MPI_Init_thread (MPI_THREAD_FUNNELED: only the thread that runs the step loop calls MPI; OpenMP
  // threads work between the calls) and the communicator over MPI_COMM_WORLD.
  static std::shared_ptr<Communicator> initialise(int& argc, char**& argv);
  static void finalise();
  [[noreturn]] static void abort_all(int code);
};
#endif

}  // namespace varsph::parallel
