# Precompiled headers. Nearly every translation unit includes Eigen (through the engine headers)
# and much of the standard library: 150k-230k preprocessed lines, 4-6 s of GCC's time per file
# before any of mgelastic's own code is compiled, about a third of a cold build on two cores.
# Each target precompiles them once (targets differ in definitions and include paths, so a
# shared precompiled header would be rejected); with ccache, sloppiness must allow PCH (set by
# the launcher in the top-level CMakeLists.txt).
option(MGELASTIC_PCH "Precompile Eigen, the standard library and the test/CLI frameworks" ON)

set(MGELASTIC_PCH_HEADERS
  <algorithm> <array> <cmath> <cstddef> <cstdint> <functional> <memory> <optional> <span>
  <string> <vector> <Eigen/Dense>)

# mgelastic_precompile_headers(target [extra headers...])
function(mgelastic_precompile_headers target)
  if(MGELASTIC_PCH)
    target_precompile_headers(${target} PRIVATE ${MGELASTIC_PCH_HEADERS} ${ARGN})
  endif()
endfunction()

# More headers for a target that already has the common ones (e.g. a module using JSON).
function(mgelastic_precompile_more_headers target)
  if(MGELASTIC_PCH)
    target_precompile_headers(${target} PRIVATE ${ARGN})
  endif()
endfunction()
