# The SIMD kernel sets (accel/dispatch/kernel_table.h): the sources below are the structures' SIMD
# paths, reached only through a set's table.
#
# Native build (default): compiled into arbor_accel with the build's -march, one set.
#
# Portable build (ARBOR_PORTABLE): compiled three times, for x86-64-v2 (sse4), x86-64-v3 (avx2)
# and x86-64-v4 (avx512). Compiling one source with different -m flags is not enough on its own:
# each object also holds the inline functions and templates it uses (std::vector's growth, xsimd's
# helpers, arbor's own inline kernels), under the same names in every set, and the linker keeps
# one copy of each, possibly an AVX-512 one that a call from the sse4 set or the rest of arbor
# would then run on a CPU without AVX-512. So each set's objects are linked into one relocatable
# object (ld -r; --force-group-allocation merges their COMDAT groups and leaves none for the final
# link to merge with another object's), and objcopy makes every symbol it defines local except its
# entry, arbor_kernels_<set> (and the sanitizers' own registration symbols, which must stay
# shared). Only the entry can then be reached from outside, and every call inside the object stays
# inside it. tests/CMakeLists.txt checks the result: the sse4 object holds no ymm/zmm register,
# the avx2 object no zmm, and each object defines one global symbol of arbor's.
set(ARBOR_KERNEL_SOURCES
  dispatch/kernel_table.cpp
  structures/kdtree_simd.cpp
  structures/wide_paths.cpp
  structures/wide_paths4.cpp
  structures/wide_paths8.cpp
  structures/wide_paths16.cpp
  structures/compact_paths.cpp
)
set(ARBOR_KERNEL_SETS sse4 avx2 avx512)
set(ARBOR_KERNEL_MARCH_sse4 x86-64-v2)
set(ARBOR_KERNEL_MARCH_avx2 x86-64-v3)
set(ARBOR_KERNEL_MARCH_avx512 x86-64-v4)

# arbor_kernel_sets(TARGET): the kernel sets into TARGET (arbor_accel), from the current directory's
# ARBOR_KERNEL_SOURCES.
function(arbor_kernel_sets target)
  if(NOT ARBOR_PORTABLE)
    target_sources(${target} PRIVATE ${ARBOR_KERNEL_SOURCES})
    return()
  endif()
  set_property(SOURCE dispatch/kernel_set.cpp APPEND PROPERTY COMPILE_DEFINITIONS ARBOR_PORTABLE_BUILD)
  # GNU ld for the relocatable link, whatever the toolchain's linker (lld 14 has no
  # --force-group-allocation); it reads clang's objects as well as gcc's.
  find_program(ARBOR_GNU_LD NAMES ld.bfd REQUIRED)
  foreach(set IN LISTS ARBOR_KERNEL_SETS)
    set(lib arbor_kernels_${set}_objects)
    add_library(${lib} OBJECT ${ARBOR_KERNEL_SOURCES})
    target_include_directories(${lib} PRIVATE ${PROJECT_SOURCE_DIR})
    # (-fno-gnu-unique: GCC would give inline variables and static locals the binding STB_GNU_UNIQUE,
    # which objcopy cannot make local and the dynamic linker merges across objects.)
    target_compile_options(${lib} PRIVATE -march=${ARBOR_KERNEL_MARCH_${set}} ${ARBOR_FP_FLAGS}
                                          $<$<CXX_COMPILER_ID:GNU>:-fno-gnu-unique>)
    target_compile_definitions(${lib} PRIVATE ARBOR_KERNEL_ENTRY=arbor_kernels_${set})
    target_compile_features(${lib} PRIVATE cxx_std_20)
    target_link_libraries(${lib} PRIVATE xsimd TBB::tbb arbor_warnings arbor_sanitize)
    set(out ${CMAKE_CURRENT_BINARY_DIR}/arbor_kernels_${set}.o)
    add_custom_command(OUTPUT ${out}
      COMMAND ${ARBOR_GNU_LD} -r --force-group-allocation -o ${out}.all.o $<TARGET_OBJECTS:${lib}>
      COMMAND ${CMAKE_OBJCOPY} --wildcard --keep-global-symbol=arbor_kernels_${set}
              --keep-global-symbol=__asan* --keep-global-symbol=__sancov* ${out}.all.o ${out}
      DEPENDS $<TARGET_OBJECTS:${lib}>
      COMMENT "Kernel set ${set}: one object, one global symbol"
      COMMAND_EXPAND_LISTS VERBATIM)
    target_sources(${target} PRIVATE ${out})
  endforeach()
endfunction()
