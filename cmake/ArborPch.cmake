# Precompiled headers (cmake/pch/): CI builds every preset from scratch on two cores without ccache,
# and most of each file's compile time is spent parsing the same standard and xsimd headers.
# On by default when no compiler launcher is set (CI's uncached builds); with a compiler launcher
# (ccache) it stays off: ccache caches nothing that uses a precompiled
# header unless its sloppiness allows it, and a rebuilt header never matches the cache.
if(CMAKE_CXX_COMPILER_LAUNCHER)
  set(_arbor_pch_default OFF)
else()
  set(_arbor_pch_default ON)
endif()
option(ARBOR_PCH "Precompile the common standard and xsimd headers for the large targets"
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
