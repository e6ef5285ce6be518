// The serial side of parallel/session.cpp, compiled without VARSPH_HAVE_MPI in every build (the target
// links session.cpp and mpi_communicator.cpp directly, not varsph_core): a build with MPI (CI) thereby
// also compiles and links what a build without MPI runs. A varsph without MPI is the serial program;
// started by a launcher as several processes it refuses (exit 2) instead of running N copies of the scene
// into one run directory.
#include <gtest/gtest.h>

#include <cstdlib>

#include "parallel/session.hpp"

namespace varsph::parallel {
namespace {

void clear_launcher_env() {
  for (const char* n : {"OMPI_COMM_WORLD_SIZE", "OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK", "PMI_SIZE",
                        "MPI_LOCALNRANKS", "MV2_COMM_WORLD_SIZE", "SLURM_STEP_NUM_TASKS", "VARSPH_MPI",
                        "OMPI_MCA_ess"})
    unsetenv(n);
}

TEST(SessionWithoutMpi, IsTheSerialProgram) {
  clear_launcher_env();
  EXPECT_FALSE(mpi_compiled());
  int argc = 1;
  char name[] = "varsph";
  char* args[] = {name, nullptr};
  char** argv = args;
  Session s(argc, argv);
  EXPECT_EQ(s.world()->size(), 1);
  EXPECT_EQ(s.world()->rank(), 0);
  EXPECT_FALSE(s.distributed());
}

TEST(SessionWithoutMpi, ReadsTheLaunchersProcessCount) {
  clear_launcher_env();
  EXPECT_EQ(launcher_world_size(), 0);
  setenv("PMI_SIZE", "6", 1);
  EXPECT_EQ(launcher_world_size(), 6);
  setenv("OMPI_COMM_WORLD_SIZE", "4", 1);  // Open MPI's own variable first
  EXPECT_EQ(launcher_world_size(), 4);
  setenv("OMPI_COMM_WORLD_SIZE", "four", 1);  // unreadable: the next one
  EXPECT_EQ(launcher_world_size(), 6);
  clear_launcher_env();
}

// The environments measured on Debian 12's Open MPI 4.1: `mpirun -n 1` gives PMIX_RANK=0,
// OMPI_COMM_WORLD_SIZE=1 and OMPI_MCA_ess=^singleton; a program started by pvpython (an Open MPI
// singleton) inherits PMIX_RANK=0 and OMPI_MCA_ess=singleton, and no OMPI_COMM_WORLD_SIZE.
TEST(SessionWithoutMpi, AChildOfAnMpiSingletonWasNotLaunchedByMpi) {
  clear_launcher_env();
  EXPECT_FALSE(launched_by_mpi());
  setenv("PMIX_RANK", "0", 1);
  EXPECT_TRUE(launched_by_mpi());  // PMIx alone (another launcher): launched
  setenv("OMPI_MCA_ess", "singleton", 1);
  EXPECT_FALSE(launched_by_mpi());  // pvpython's child
  setenv("OMPI_MCA_ess", "^singleton", 1);
  setenv("OMPI_COMM_WORLD_SIZE", "1", 1);
  EXPECT_TRUE(launched_by_mpi());  // mpirun -n 1
  setenv("OMPI_MCA_ess", "singleton", 1);
  EXPECT_TRUE(launched_by_mpi());  // a launcher's world size wins
  clear_launcher_env();
}

TEST(SessionWithoutMpi, RefusesSeveralProcessesAndForcedMpiOnly) {
  EXPECT_EQ(refusal_without_mpi(false, false, 0, false), "");  // run directly
  EXPECT_EQ(refusal_without_mpi(false, true, 1, false), "");   // mpirun -n 1: one serial process
  EXPECT_EQ(refusal_without_mpi(false, true, 0, false), "");   // launcher without a size: cannot tell
  const std::string many = refusal_without_mpi(false, true, 3, false);
  EXPECT_NE(many.find("3 processes"), std::string::npos) << many;
  EXPECT_NE(many.find("VARSPH_MPI=OFF"), std::string::npos) << many;
  EXPECT_NE(refusal_without_mpi(false, false, 0, true).find("VARSPH_MPI=1"), std::string::npos);
  EXPECT_EQ(refusal_without_mpi(true, true, 3, true), "");  // a build with MPI runs them as ranks
}

TEST(SessionWithoutMpiDeathTest, SeveralProcessesExitWithTwoAndAMessage) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  clear_launcher_env();
  int argc = 1;
  char name[] = "varsph";
  char* args[] = {name, nullptr};
  char** argv = args;
  setenv("OMPI_COMM_WORLD_SIZE", "2", 1);
  setenv("OMPI_COMM_WORLD_RANK", "0", 1);
  EXPECT_EXIT(Session(argc, argv), testing::ExitedWithCode(2), "2 processes by an MPI launcher.*without MPI");
  clear_launcher_env();
  setenv("VARSPH_MPI", "1", 1);
  EXPECT_EXIT(Session(argc, argv), testing::ExitedWithCode(2), "VARSPH_MPI=1 asks for MPI");
  setenv("VARSPH_MPI", "0", 1);  // forbids MPI: every process is the serial program, as asked
  setenv("OMPI_COMM_WORLD_SIZE", "2", 1);
  Session s(argc, argv);
  EXPECT_EQ(s.world()->size(), 1);
  clear_launcher_env();
}

}  // namespace
}  // namespace varsph::parallel
