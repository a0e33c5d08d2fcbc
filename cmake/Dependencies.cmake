# Every dependency comes from Debian packages (scripts/install-deps.sh).
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(yaml-cpp REQUIRED)
find_package(CLI11 REQUIRED)
find_package(fmt REQUIRED)
find_package(spdlog REQUIRED)
find_package(nanoflann REQUIRED)
find_package(OpenMP REQUIRED COMPONENTS CXX)
# OpenMPI 4.1 (libopenmpi-dev, openmpi-bin): the ranks of a distributed run (dist/). Its C API
# from C++ (the project enables no C compiler; the deprecated C++ bindings are skipped).
set(MPI_CXX_SKIP_MPICXX ON)
find_package(MPI REQUIRED COMPONENTS CXX)
# Plots and the independent VTU reader in the tests use Debian's Python (matplotlib,
# meshio come from Debian packages), not whatever python3 is first on PATH.
if(EXISTS /usr/bin/python3 AND NOT Python3_EXECUTABLE)
  set(Python3_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "Python with matplotlib and meshio")
endif()
find_package(Python3 REQUIRED COMPONENTS Interpreter)

# A Debian library that ships its header and shared library but no CMake package: the
# IMPORTED target `target` (<PREFIX>_INCLUDE_DIR and <PREFIX>_LIBRARY are cached).
function(shellflow_import_library target prefix header library)
  find_path(${prefix}_INCLUDE_DIR ${header} REQUIRED)
  find_library(${prefix}_LIBRARY ${library} REQUIRED)
  add_library(${target} UNKNOWN IMPORTED GLOBAL)
  set_target_properties(${target} PROPERTIES
    IMPORTED_LOCATION "${${prefix}_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${${prefix}_INCLUDE_DIR}")
endfunction()

# Debian's libgmsh-dev ships gmsh.h and libgmsh.so.
shellflow_import_library(Gmsh::gmsh GMSH gmsh.h gmsh)
# Gmsh's executable is not needed at run time (the library meshes), but tests use
# it nowhere either; find it only to report it.
find_program(GMSH_EXECUTABLE gmsh)
# Debian's libmetis-dev (METIS 5.1, serial): partitions of the fluid mesh (mesh/partition.h).
shellflow_import_library(METIS::metis METIS metis.h metis)

if(SHELLFLOW_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()
if(SHELLFLOW_BUILD_BENCHMARKS)
  find_package(benchmark REQUIRED)
endif()
