# Every dependency comes from Debian packages (scripts/install-deps.sh).
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(yaml-cpp REQUIRED)
find_package(CLI11 REQUIRED)
find_package(fmt REQUIRED)
find_package(spdlog REQUIRED)
find_package(nanoflann REQUIRED)
find_package(OpenMP REQUIRED COMPONENTS CXX)
# Plots and the independent VTU reader in the tests use Debian's Python (matplotlib,
# meshio come from Debian packages), not whatever python3 is first on PATH.
if(EXISTS /usr/bin/python3 AND NOT Python3_EXECUTABLE)
  set(Python3_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "Python with matplotlib and meshio")
endif()
find_package(Python3 REQUIRED COMPONENTS Interpreter)

# Debian's libgmsh-dev ships gmsh.h and libgmsh.so but no CMake package.
find_path(GMSH_INCLUDE_DIR gmsh.h REQUIRED)
find_library(GMSH_LIBRARY gmsh REQUIRED)
add_library(Gmsh::gmsh UNKNOWN IMPORTED)
set_target_properties(Gmsh::gmsh PROPERTIES
  IMPORTED_LOCATION "${GMSH_LIBRARY}"
  INTERFACE_INCLUDE_DIRECTORIES "${GMSH_INCLUDE_DIR}")
# Gmsh's executable is not needed at run time (the library meshes), but tests use
# it nowhere either; find it only to report it.
find_program(GMSH_EXECUTABLE gmsh)

# Debian's libmetis-dev (METIS 5.1, serial) ships metis.h and libmetis.so but no CMake package.
find_path(METIS_INCLUDE_DIR metis.h REQUIRED)
find_library(METIS_LIBRARY metis REQUIRED)
add_library(METIS::metis UNKNOWN IMPORTED)
set_target_properties(METIS::metis PROPERTIES
  IMPORTED_LOCATION "${METIS_LIBRARY}"
  INTERFACE_INCLUDE_DIRECTORIES "${METIS_INCLUDE_DIR}")

if(SHELLFLOW_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()
if(SHELLFLOW_BUILD_BENCHMARKS)
  find_package(benchmark REQUIRED)
endif()
