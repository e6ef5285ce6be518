#include "parallel/session.hpp"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

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
  // A child of an Open MPI singleton was not started by a launcher: pvpython and pvbatch initialise MPI
  // as singletons and pass PMIX_RANK with OMPI_MCA_ess=singleton to every program they run (varsph
  // paraview, the bundled pvpython scripts), whereas mpirun sets OMPI_MCA_ess=^singleton and
  // OMPI_COMM_WORLD_SIZE.
  if (const char* ess = std::getenv("OMPI_MCA_ess");
      ess && std::strcmp(ess, "singleton") == 0 && !std::getenv("OMPI_COMM_WORLD_SIZE"))
    return false;
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE", "MPI_LOCALNRANKS",
                           "MV2_COMM_WORLD_SIZE"})
    if (std::getenv(name)) return true;
  return false;
}

int launcher_world_size() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "MV2_COMM_WORLD_SIZE", "SLURM_STEP_NUM_TASKS"})
    if (const char* v = std::getenv(name)) {
      char* end = nullptr;
      const long n = std::strtol(v, &end, 10);
      if (end != v && n > 0 && n < (1L << 30)) return int(n);
    }
  return 0;
}

std::string refusal_without_mpi(bool compiled, bool launched, int world_size, bool forced) {
  if (compiled) return "";
  const std::string fix = "rebuild with MPI (Debian: libopenmpi-dev; cmake -DVARSPH_MPI=ON, docs/parallel.md) ";
  if (forced)
    return "VARSPH_MPI=1 asks for MPI, but this varsph was built without it (VARSPH_MPI=OFF or MPI not found): " +
           fix + "or unset VARSPH_MPI";
  if (launched && world_size > 1)
    return "started as " + std::to_string(world_size) +
           " processes by an MPI launcher, but this varsph was built without MPI (VARSPH_MPI=OFF or MPI not "
           "found): each process would run the whole scene into the same run directory; " +
           fix + "or run it without mpirun";
  return "";
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
  const char* forced = std::getenv("VARSPH_MPI");  // "0" forbids MPI: the serial program, as asked
  const std::string why = refusal_without_mpi(false, launched_by_mpi(), launcher_world_size(),
                                              forced && std::strcmp(forced, "0") != 0);
  if (!why.empty()) {
    // every process of the launch gets here: the first one says it (exit 2: invalid usage, CONTRACT.md)
    const char* r = std::getenv("OMPI_COMM_WORLD_RANK");
    if (!r) r = std::getenv("PMI_RANK");
    if (!r || std::strcmp(r, "0") == 0) std::fprintf(stderr, "varsph: error: %s\n", why.c_str());
    std::exit(2);
  }
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
