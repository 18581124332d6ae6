# `cmake --install build --prefix P`: the drape command, libdrape (the simulation: the target
# drape::drape) with its public headers, a CMake package (find_package(drape CONFIG)), a
# pkg-config file (drape.pc) and the shipped scenes. The Python module installs itself
# (python/CMakeLists.txt).
include(CMakePackageConfigHelpers)

install(TARGETS drape RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS drape_core EXPORT drapeTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY include/drape DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY scenes/ DESTINATION ${CMAKE_INSTALL_DATADIR}/drape/scenes)

set(DRAPE_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/drape)
install(EXPORT drapeTargets NAMESPACE drape:: DESTINATION ${DRAPE_CMAKE_DIR})
configure_package_config_file(cmake/drapeConfig.cmake.in
                              ${CMAKE_CURRENT_BINARY_DIR}/drapeConfig.cmake
                              INSTALL_DESTINATION ${DRAPE_CMAKE_DIR})
# 0.x: a new minor version may change the API.
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/drapeConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/drapeConfig.cmake
              ${CMAKE_CURRENT_BINARY_DIR}/drapeConfigVersion.cmake
        DESTINATION ${DRAPE_CMAKE_DIR})

# pkg-config: the prefix is found from the .pc file's own place, so `--prefix` at install time
# (not the one configured) is what it names. A static libdrape needs OpenMP's runtime at link.
set(DRAPE_PC_DIR ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
file(RELATIVE_PATH DRAPE_PC_TO_PREFIX /prefix/${DRAPE_PC_DIR} /prefix)
set(DRAPE_PC_LIBS "")
if(DRAPE_OPENMP)
  set(DRAPE_PC_LIBS "${OpenMP_CXX_FLAGS}")
endif()
configure_file(cmake/drape.pc.in ${CMAKE_CURRENT_BINARY_DIR}/drape.pc @ONLY)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/drape.pc DESTINATION ${DRAPE_PC_DIR})
