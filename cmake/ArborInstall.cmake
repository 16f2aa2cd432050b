# `cmake --install` puts the libraries, headers and a CMake package under the prefix, so that a
# separate project can find_package(arbor) and link arbor::engine.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

install(TARGETS arbor_simd arbor_accel arbor_engine EXPORT arborTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/arbor)
install(TARGETS arbor RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
foreach(dir simd accel engine)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${dir}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/arbor/${dir}
          FILES_MATCHING PATTERN "*.h")
endforeach()
install(EXPORT arborTargets NAMESPACE arbor:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/arbor)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/arborConfig.cmake.in
  ${PROJECT_BINARY_DIR}/arborConfig.cmake INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/arbor)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/arborConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/arborConfig.cmake ${PROJECT_BINARY_DIR}/arborConfigVersion.cmake
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/arbor)
