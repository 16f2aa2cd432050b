# `cmake --install` puts the public library (libarbor.so), its one header <arbor/arbor.h>, the
# `arbor` command and a CMake package under the prefix: a separate project does find_package(arbor)
# and links arbor::arbor. `arbor bench` runs the lab tool arbor-bench, installed beside arbor as
# the separate component "bench" (it links Embree when built with it; `arbor` never does), which a
# package may leave out: `cmake --install build --component Unspecified` installs all but it. Nothing
# else is installed: no internal header, no static library, and no
# compile option reaches the user's code (arbor's own -march and -ffp-contract stay on its targets).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

install(TARGETS arbor_api EXPORT arborTargets
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(FILES ${PROJECT_SOURCE_DIR}/include/arbor/arbor.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/arbor)
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
