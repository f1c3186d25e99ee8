# Precompiled headers. Nearly every translation unit includes Eigen (through the engine headers)
# and much of the standard library: 150k-230k preprocessed lines, 4-6 s of GCC's time per file
# before any of mgelastic's own code is compiled, about a third of a cold build on two cores.
# By default each target precompiles them once (with the Python module or -march=native, targets
# differ in code-generation options, so one precompiled header would be rejected by some); with
# ccache, sloppiness must allow PCH (set by the launcher in the top-level CMakeLists.txt).
option(MGELASTIC_PCH "Precompile Eigen, the standard library and the test/CLI frameworks" ON)
# Preset demo: the library modules share one precompiled header instead of precompiling one each
# (7-10 s of GCC's time per target).
option(MGELASTIC_SHARED_PCH "One precompiled header for all library modules" OFF)

set(MGELASTIC_PCH_HEADERS
  <algorithm> <array> <cmath> <cstddef> <cstdint> <functional> <memory> <optional> <span>
  <string> <vector> <Eigen/Dense>)
# The shared one adds the modules' extra headers. Not CLI11: in a precompiled header it costs
# GCC 5-7 s more per translation unit that loads it (measured on grid at -O1), so the CLI keeps
# its own.
set(MGELASTIC_SHARED_PCH_HEADERS ${MGELASTIC_PCH_HEADERS} <Eigen/Sparse> <nlohmann/json.hpp>)
if(MGELASTIC_SHARED_PCH AND (MGELASTIC_HAVE_PYTHON OR MGELASTIC_NATIVE OR MGELASTIC_FUZZ))
  message(STATUS "MGELASTIC_SHARED_PCH is ignored with the Python module, native or fuzz builds")
  set(MGELASTIC_SHARED_PCH OFF)
endif()

# The target that compiles the shared precompiled header (with an empty translation unit, as
# CMake precompiles headers only for targets with sources), created on first use.
function(mgelastic_shared_pch_target)
  if(TARGET mgelastic_pch)
    return()
  endif()
  set(source ${PROJECT_BINARY_DIR}/mgelastic_pch.cpp)
  file(CONFIGURE OUTPUT ${source} CONTENT "// The translation unit of the shared precompiled header.\n")
  add_library(mgelastic_pch OBJECT ${source})
  target_link_libraries(mgelastic_pch PRIVATE mgelastic_warnings Eigen3::Eigen OpenMP::OpenMP_CXX
    nlohmann_json::nlohmann_json)
  target_precompile_headers(mgelastic_pch PRIVATE ${MGELASTIC_SHARED_PCH_HEADERS})
endfunction()

# mgelastic_precompile_headers(target [extra headers...])
function(mgelastic_precompile_headers target)
  if(NOT MGELASTIC_PCH)
    return()
  endif()
  set(shared ${MGELASTIC_SHARED_PCH})
  foreach(header IN LISTS ARGN)
    if(NOT header IN_LIST MGELASTIC_SHARED_PCH_HEADERS)
      set(shared OFF)  # the CLI's CLI11, the tests' GoogleTest
    endif()
  endforeach()
  if(shared)
    mgelastic_shared_pch_target()
    target_precompile_headers(${target} REUSE_FROM mgelastic_pch)
    set_target_properties(${target} PROPERTIES MGELASTIC_SHARES_PCH ON)
  else()
    target_precompile_headers(${target} PRIVATE ${MGELASTIC_PCH_HEADERS} ${ARGN})
  endif()
endfunction()

# More headers for a target that already has the common ones (e.g. a module using JSON); the
# shared precompiled header has them already.
function(mgelastic_precompile_more_headers target)
  get_target_property(shares ${target} MGELASTIC_SHARES_PCH)
  if(MGELASTIC_PCH AND NOT shares)
    target_precompile_headers(${target} PRIVATE ${ARGN})
  endif()
endfunction()
