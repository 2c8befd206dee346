# Every dependency comes from a Debian 12 package (scripts/install-deps).
find_package(PkgConfig REQUIRED)
find_package(MPI REQUIRED COMPONENTS C CXX)
pkg_check_modules(PETSC REQUIRED IMPORTED_TARGET PETSc)
pkg_check_modules(FFTW REQUIRED IMPORTED_TARGET fftw3)
find_library(FFTW_MPI_LIBRARY fftw3_mpi REQUIRED)
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(tomlplusplus REQUIRED)
find_package(CLI11 REQUIRED)
find_package(GTest REQUIRED)
find_package(Ceres REQUIRED)
find_package(nlohmann_json 3 REQUIRED)
# {fmt} (libfmt-dev): GCC 12 has no <format>; target fmt::fmt.
find_package(fmt REQUIRED)

# HDF5, Open MPI flavour (parallel I/O).
set(HDF5_PREFER_PARALLEL TRUE)
find_package(HDF5 REQUIRED COMPONENTS C)
if(NOT HDF5_IS_PARALLEL)
  message(FATAL_ERROR "ibvalve needs the parallel (Open MPI) HDF5: apt-get install libhdf5-openmpi-dev")
endif()
add_library(ibvalve_hdf5 INTERFACE)
target_include_directories(ibvalve_hdf5 SYSTEM INTERFACE ${HDF5_C_INCLUDE_DIRS})
target_link_libraries(ibvalve_hdf5 INTERFACE ${HDF5_C_LIBRARIES})
target_compile_definitions(ibvalve_hdf5 INTERFACE ${HDF5_C_DEFINITIONS})

# The gmsh API (libgmsh-dev) ships a header and a library but no CMake or pkg-config file.
find_path(GMSH_INCLUDE_DIR gmsh.h REQUIRED)
find_library(GMSH_LIBRARY gmsh REQUIRED)
add_library(ibvalve_gmsh INTERFACE)
target_include_directories(ibvalve_gmsh SYSTEM INTERFACE ${GMSH_INCLUDE_DIR})
target_link_libraries(ibvalve_gmsh INTERFACE ${GMSH_LIBRARY})

# kainjow-mustache (libkainjow-mustache-dev) is one header, without a CMake or pkg-config file.
find_path(MUSTACHE_INCLUDE_DIR kainjow/mustache.hpp REQUIRED)
add_library(ibvalve_mustache INTERFACE)
target_include_directories(ibvalve_mustache SYSTEM INTERFACE ${MUSTACHE_INCLUDE_DIR})

# PETSc brings MPI; keep its headers out of -Werror's reach.
add_library(ibvalve_petsc INTERFACE)
target_link_libraries(ibvalve_petsc INTERFACE PkgConfig::PETSC MPI::MPI_CXX)
get_target_property(_petsc_inc PkgConfig::PETSC INTERFACE_INCLUDE_DIRECTORIES)
if(_petsc_inc)
  target_include_directories(ibvalve_petsc SYSTEM INTERFACE ${_petsc_inc})
endif()

add_library(ibvalve_fftw INTERFACE)
target_link_libraries(ibvalve_fftw INTERFACE ${FFTW_MPI_LIBRARY} PkgConfig::FFTW MPI::MPI_CXX)

# Debian's interpreter, which sees python3-matplotlib/numpy/h5py (a python3 earlier on PATH may not).
set(Python3_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "Python with matplotlib, numpy and h5py")
find_package(Python3 REQUIRED COMPONENTS Interpreter)

find_program(MPIEXEC_PROGRAM NAMES mpiexec mpirun REQUIRED)
