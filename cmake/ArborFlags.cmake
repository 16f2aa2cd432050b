# Flags live on INTERFACE targets, never on the global command line.

add_library(arbor_warnings INTERFACE)
target_compile_options(arbor_warnings INTERFACE -Wall -Wextra -Wpedantic -Wshadow -Wno-unused-parameter)

# One ISA per build. -ffp-contract=off is a correctness setting, not a speed one: the watertight
# triangle test relies on a*b - c*d being rounded twice so that an edge shared by two triangles
# gets exactly opposite signs (a fused multiply-add would break that symmetry).
# (The portable build's kernel sets take ARBOR_FP_FLAGS with their own -march: ArborKernelSets.cmake.)
set(ARBOR_FP_FLAGS -ffp-contract=off -fno-math-errno -fno-semantic-interposition)
add_library(arbor_arch INTERFACE)
target_compile_options(arbor_arch INTERFACE -march=${ARBOR_ARCH} ${ARBOR_FP_FLAGS})

add_library(arbor_sanitize INTERFACE)
if(ARBOR_SANITIZE)
  target_compile_options(arbor_sanitize INTERFACE -fsanitize=address,undefined -fno-omit-frame-pointer
                                                  -fno-sanitize-recover=undefined)
  target_link_options(arbor_sanitize INTERFACE -fsanitize=address,undefined)
endif()
if(ARBOR_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "ARBOR_FUZZ needs clang (libFuzzer): configure with the preset fuzz")
  endif()
  # Coverage feedback for libFuzzer in every arbor library; the harnesses link -fsanitize=fuzzer.
  target_compile_options(arbor_sanitize INTERFACE -fsanitize=fuzzer-no-link)
endif()
if(ARBOR_TSAN)
  target_compile_options(arbor_sanitize INTERFACE -fsanitize=thread -fno-omit-frame-pointer)
  target_link_options(arbor_sanitize INTERFACE -fsanitize=thread)
endif()

