# `cmake --install` puts the public library (libarbor.so), its one header <arbor/arbor.h>, the
# `arbor` command and a CMake package under the prefix: a separate project does find_package(arbor)
# and links arbor::arbor. `arbor bench` runs the lab tool arbor-bench, installed beside arbor as
# the separate component "bench" (it links Embree when built with it; `arbor` never does), which a
# package may leave out: `cmake --install build --component Unspecified` installs all but it.
# libarbor.a (api/CMakeLists.txt) is installed beside libarbor.so for programs that link statically:
# arbor::arbor_static names what it needs. Nothing else is installed: no internal header, and no
# compile option reaches the user's code (arbor's own -march and -ffp-contract stay on its targets).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

install(TARGETS arbor_api EXPORT arborTargets
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(FILES ${PROJECT_SOURCE_DIR}/include/arbor/arbor.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/arbor)
install(FILES ${ARBOR_STATIC_ARCHIVE} DESTINATION ${CMAKE_INSTALL_LIBDIR})
# What arbor::arbor_static links besides libarbor.a (the package finds the same libraries again):
# the link options of a sanitizer build, and stb's library, which has no CMake package.
set(ARBOR_STATIC_LINK_OPTIONS "")
if(ARBOR_SANITIZE)
  set(ARBOR_STATIC_LINK_OPTIONS "-fsanitize=address,undefined")
elseif(ARBOR_TSAN)
  set(ARBOR_STATIC_LINK_OPTIONS "-fsanitize=thread")
endif()
set(ARBOR_STATIC_STB_LIBRARY ${STB_LIBRARY})
install(TARGETS arbor RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
if(TARGET arbor-bench)
  install(TARGETS arbor-bench RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT bench)
endif()
install(EXPORT arborTargets NAMESPACE arbor:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/arbor)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/arborConfig.cmake.in
  ${PROJECT_BINARY_DIR}/arborConfig.cmake INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/arbor)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/arborConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/arborConfig.cmake ${PROJECT_BINARY_DIR}/arborConfigVersion.cmake
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/arbor)
