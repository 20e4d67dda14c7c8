# Installs the library with an exported, namespaced package: find_package(expanse CONFIG).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

install(TARGETS expanse EXPORT expanseTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
# The interop headers mention device API types: each is installed only with its backend.
install(DIRECTORY engine/include/expanse DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
        PATTERN "*_interop.hpp" EXCLUDE)
if(EXPANSE_WITH_VULKAN)
  install(FILES engine/include/expanse/vulkan_interop.hpp
          DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/expanse)
endif()
if(EXPANSE_WITH_CUDA)
  install(FILES engine/include/expanse/cuda_interop.hpp
          DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/expanse)
endif()
if(TARGET expanse_cli)
  install(TARGETS expanse_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()
install(EXPORT expanseTargets NAMESPACE expanse:: FILE expanseTargets.cmake
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/expanse)
configure_package_config_file(cmake/expanseConfig.cmake.in
        ${CMAKE_CURRENT_BINARY_DIR}/expanseConfig.cmake
        INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/expanse)
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/expanseConfigVersion.cmake
        COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/expanseConfig.cmake
              ${CMAKE_CURRENT_BINARY_DIR}/expanseConfigVersion.cmake
              cmake/FindGMP.cmake
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/expanse)
