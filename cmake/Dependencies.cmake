# Every third-party dependency is found here, once, from the system (Debian packages).
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(OpenMP REQUIRED COMPONENTS CXX)
find_package(nlohmann_json 3.10 REQUIRED)
# zlib compresses the binary data of the VTK XML outputs (vtkZLibDataCompressor).
find_package(ZLIB REQUIRED)
# libdeflate (optional, Debian libdeflate-dev): a faster encoder of the same zlib streams; the VTK
# writers use it when found (io/vtk_compressed_blocks.hpp).
find_path(LIBDEFLATE_INCLUDE_DIR libdeflate.h)
find_library(LIBDEFLATE_LIBRARY deflate)
add_library(mgelastic_libdeflate INTERFACE)
if(LIBDEFLATE_INCLUDE_DIR AND LIBDEFLATE_LIBRARY)
  target_include_directories(mgelastic_libdeflate SYSTEM INTERFACE ${LIBDEFLATE_INCLUDE_DIR})
  target_link_libraries(mgelastic_libdeflate INTERFACE ${LIBDEFLATE_LIBRARY})
  target_compile_definitions(mgelastic_libdeflate INTERFACE MGELASTIC_HAVE_LIBDEFLATE)
else()
  message(STATUS "libdeflate not found: VTK data blocks are compressed with zlib (slower)")
endif()

# SuiteSparse CHOLMOD: sparse Cholesky for the coarsest multigrid level and tet hierarchies;
# UMFPACK: sparse LU for a coarsest level with Galerkin band rows (unsymmetric).
find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse REQUIRED)
find_library(CHOLMOD_LIBRARY cholmod REQUIRED)
find_library(UMFPACK_LIBRARY umfpack REQUIRED)
add_library(mgelastic_cholmod INTERFACE)
target_include_directories(mgelastic_cholmod SYSTEM INTERFACE ${CHOLMOD_INCLUDE_DIR})
target_link_libraries(mgelastic_cholmod INTERFACE ${CHOLMOD_LIBRARY} ${UMFPACK_LIBRARY})

if(MGELASTIC_BUILD_APP)
  find_package(CLI11 REQUIRED)
endif()
if(MGELASTIC_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()
if(MGELASTIC_BUILD_BENCH)
  find_package(benchmark REQUIRED)
endif()

# Python module (python/): Python 3 with NumPy and pybind11. The Debian interpreter is preferred
# over one earlier on PATH (a pyenv build without NumPy, say); -DPython3_EXECUTABLE=... chooses.
set(MGELASTIC_HAVE_PYTHON OFF)
if(MGELASTIC_PYTHON)
  if(NOT DEFINED Python3_EXECUTABLE AND EXISTS /usr/bin/python3)
    set(Python3_EXECUTABLE /usr/bin/python3)
  endif()
  find_package(Python3 COMPONENTS Interpreter Development.Module NumPy)
  if(Python3_FOUND AND Python3_NumPy_FOUND)
    find_package(pybind11 CONFIG)
  endif()
  if(Python3_FOUND AND Python3_NumPy_FOUND AND pybind11_FOUND)
    set(MGELASTIC_HAVE_PYTHON ON)
  else()
    message(STATUS "Python 3 with NumPy and pybind11 not found: Python module disabled")
  endif()
endif()

# hypre (BoomerAMG) is the optional baseline solver for benchmarks.
set(MGELASTIC_HAVE_HYPRE OFF)
if(MGELASTIC_WITH_HYPRE)
  find_path(HYPRE_INCLUDE_DIR HYPRE.h PATH_SUFFIXES hypre)
  find_library(HYPRE_LIBRARY HYPRE)
  # Debian's hypre is built with MPI: the baseline runs as a single-process MPI program.
  find_package(MPI COMPONENTS CXX QUIET)
  if(HYPRE_INCLUDE_DIR AND HYPRE_LIBRARY AND MPI_CXX_FOUND)
    set(MGELASTIC_HAVE_HYPRE ON)
    add_library(mgelastic_hypre INTERFACE)
    target_include_directories(mgelastic_hypre SYSTEM INTERFACE ${HYPRE_INCLUDE_DIR})
    target_link_libraries(mgelastic_hypre INTERFACE ${HYPRE_LIBRARY} MPI::MPI_CXX)
    target_compile_definitions(mgelastic_hypre INTERFACE OMPI_SKIP_MPICXX MPICH_SKIP_MPICXX)
  else()
    message(STATUS "hypre not found: BoomerAMG baselines disabled")
  endif()
endif()
