# cmake -DSRC=<repo>/src -P check_mpi_isolation.cmake
# A build without MPI (VARSPH_MPI=OFF) compiles every source file as a build with MPI does, except the
# lines under VARSPH_HAVE_MPI. This keeps those lines in the files that test_session_serial compiles
# without MPI in every build (session.cpp, mpi_communicator.*), and mpi.h in mpi_communicator.cpp alone:
# then CI's build with MPI also shows that the build without it compiles and links (docs/parallel.md).
file(GLOB_RECURSE _files RELATIVE ${SRC} ${SRC}/*.cpp ${SRC}/*.hpp ${SRC}/*.h ${SRC}/*.cu ${SRC}/*.cuh)
set(_allowed_macro parallel/session.cpp parallel/mpi_communicator.cpp parallel/mpi_communicator.hpp)
set(_bad "")
foreach(_f ${_files})
  file(STRINGS ${SRC}/${_f} _mpi_h REGEX "#[ \t]*include[ \t]*[<\"]mpi\\.h[>\"]")
  if(_mpi_h AND NOT _f STREQUAL "parallel/mpi_communicator.cpp")
    list(APPEND _bad "${_f} includes mpi.h (only parallel/mpi_communicator.cpp may)")
  endif()
  file(STRINGS ${SRC}/${_f} _macro REGEX "VARSPH_HAVE_MPI")
  list(FIND _allowed_macro ${_f} _i)
  if(_macro AND _i LESS 0)
    list(APPEND _bad "${_f} uses VARSPH_HAVE_MPI (only ${_allowed_macro} may: they are compiled without MPI in every build)")
  endif()
endforeach()
list(LENGTH _files _n)
if(_n LESS 50)
  message(FATAL_ERROR "check_mpi_isolation: only ${_n} source files under ${SRC}: wrong SRC?")
endif()
if(_bad)
  string(REPLACE ";" "\n  " _msg "${_bad}")
  message(FATAL_ERROR "MPI outside its isolation:\n  ${_msg}")
endif()
message(STATUS "check_mpi_isolation: ${_n} files, MPI confined to parallel/session.cpp and parallel/mpi_communicator.*")
