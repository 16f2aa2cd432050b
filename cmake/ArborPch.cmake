# Precompiled headers (cmake/pch/): CI builds every preset from scratch on two cores without ccache,
# and most of each file's compile time is spent parsing the same standard, xsimd and TBB headers.
# On by default; off when a compiler launcher (ccache) is set, because ccache caches nothing that
# uses a precompiled header unless its sloppiness allows it, and a rebuilt header never matches the
# cache (pass -DARBOR_PCH=ON to try the CI configuration with ccache; it compiles, uncached).
set(_arbor_pch_default ON)
if(CMAKE_CXX_COMPILER_LAUNCHER)
  set(_arbor_pch_default OFF)
endif()
option(ARBOR_PCH "Precompile the common standard and third-party headers (off when a compiler launcher is set)"
       ${_arbor_pch_default})
message(STATUS "arbor: precompiled headers ${ARBOR_PCH}")

# arbor_pch(TARGET [TEST]): precompile cmake/pch/arbor_pch.h (TEST: arbor_test_pch.h, with doctest)
# for TARGET's C++ files. Only for targets of many files: each precompiled header costs about two
# ordinary files' time to make.
function(arbor_pch target)
  if(NOT ARBOR_PCH)
    return()
  endif()
  set(header ${PROJECT_SOURCE_DIR}/cmake/pch/arbor_pch.h)
  if(ARGV1 STREQUAL "TEST")
    set(header ${PROJECT_SOURCE_DIR}/cmake/pch/arbor_test_pch.h)
  endif()
  target_precompile_headers(${target} PRIVATE "$<$<COMPILE_LANGUAGE:CXX>:${header}>")
endfunction()
