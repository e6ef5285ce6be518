#include "parallel/session.hpp"

#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "parallel/mpi_communicator.hpp"

namespace varsph::parallel {

bool mpi_compiled() {
#ifdef VARSPH_HAVE_MPI
  return true;
#else
  return false;
#endif
}

bool launched_by_mpi() {
  if (const char* v = std::getenv("VARSPH_MPI")) return std::strcmp(v, "0") != 0;
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE", "MPI_LOCALNRANKS",
                           "MV2_COMM_WORLD_SIZE"})
    if (std::getenv(name)) return true;
  return false;
}

Session::Session(int& argc, char**& argv) {
#ifdef VARSPH_HAVE_MPI
  if (launched_by_mpi()) {
    world_ = MpiCommunicator::initialise(argc, argv);
    initialised_here_ = true;
    return;
  }
#else
  (void)argc;
  (void)argv;
#endif
  world_ = std::make_shared<SerialCommunicator>();
}

Session::~Session() {
#ifdef VARSPH_HAVE_MPI
  if (initialised_here_) {
    world_.reset();
    MpiCommunicator::finalise();
  }
#endif
}

void Session::abort(int code) {
#ifdef VARSPH_HAVE_MPI
  if (initialised_here_) MpiCommunicator::abort_all(code);
#endif
  std::fflush(stdout);
  std::fflush(stderr);
  std::_Exit(code);
}

}  // namespace varsph::parallel
