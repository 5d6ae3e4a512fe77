# `cmake --install build --prefix P` and `cpack -G DEB`: the executable in P/bin, everything it reads at run
# time in P/share/shearbench (core/base/install_paths.hpp finds it from the executable: bin/../share/shearbench).
# The data root (../shared/data) is never installed: it keeps its own licences (NOTICE).
include(GNUInstallDirs)
set(SHEARBENCH_SHARE_DIR ${CMAKE_INSTALL_DATADIR}/shearbench)

install(TARGETS shearbench RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})

# The library and its CMake package: find_package(shearbench CONFIG) -> shearbench::shearbench (docs/library.md).
if(TARGET shearbench_library)
  include(CMakePackageConfigHelpers)
  set(SHEARBENCH_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/shearbench)
  install(TARGETS shearbench_library EXPORT shearbenchTargets
          LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} NAMELINK_COMPONENT Unspecified)
  install(DIRECTORY include/shearbench DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  install(EXPORT shearbenchTargets NAMESPACE shearbench:: DESTINATION ${SHEARBENCH_CMAKE_DIR})
  configure_package_config_file(cmake/shearbenchConfig.cmake.in ${CMAKE_BINARY_DIR}/shearbenchConfig.cmake
                                INSTALL_DESTINATION ${SHEARBENCH_CMAKE_DIR})
  write_basic_package_version_file(${CMAKE_BINARY_DIR}/shearbenchConfigVersion.cmake COMPATIBILITY SameMinorVersion)
  install(FILES ${CMAKE_BINARY_DIR}/shearbenchConfig.cmake ${CMAKE_BINARY_DIR}/shearbenchConfigVersion.cmake
          DESTINATION ${SHEARBENCH_CMAKE_DIR})
endif()
# The Python module, for Debian's python3 (python/CMakeLists.txt sets SHEARBENCH_PYTHON_DIR).
if(TARGET shearbench_python)
  install(TARGETS shearbench_python LIBRARY DESTINATION ${SHEARBENCH_PYTHON_DIR})
endif()
install(DIRECTORY scenes/ DESTINATION ${SHEARBENCH_SHARE_DIR}/scenes FILES_MATCHING PATTERN "*.json")
# The parameter sets and the procedural indenter meshes `shearbench assets` writes.
install(DIRECTORY assets/ DESTINATION ${SHEARBENCH_SHARE_DIR}/assets
        FILES_MATCHING PATTERN "*.json" PATTERN "*.obj")
# The docs the program's messages and help point to (docs/effects.md, docs/sensors.md, ...), with their
# figures; not the scripts that regenerate them.
# screenshot_real_recording.png shows a frame of a GPL-3.0 recording (NOTICE): not ours to ship under MIT.
install(DIRECTORY docs/ DESTINATION ${SHEARBENCH_SHARE_DIR}/docs
        FILES_MATCHING PATTERN "*.md" PATTERN "*.png" PATTERN "*.json"
        PATTERN "screenshot_real_recording.png" EXCLUDE)
install(FILES README.md CHANGELOG.md LICENSE NOTICE DESTINATION ${SHEARBENCH_SHARE_DIR})
# Debian's place for the licence.
install(FILES LICENSE DESTINATION ${CMAKE_INSTALL_DOCDIR} RENAME copyright)

# ---------------------------------------------------------------- CPack: a Debian package
set(CPACK_PACKAGE_NAME shearbench)
set(CPACK_PACKAGE_VENDOR "shearbench maintainers")
set(CPACK_PACKAGE_CONTACT "shearbench maintainers <maintainers@users.noreply.github.com>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "workbench for tactile shear models (HydroShear, FOTS, TacSL) against GelSight data")
set(CPACK_PACKAGE_DESCRIPTION
  "Three shear models side by side against real and synthetic GelSight Mini marker fields, with calibration fits, residual analysis and a headless CLI (render, simulate, evaluate, fit, params, ...). Measured data is not included: point --data or SHEARBENCH_DATA at a tsd/1 data root.")
set(CPACK_RESOURCE_FILE_LICENSE ${PROJECT_SOURCE_DIR}/LICENSE)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
set(CPACK_GENERATOR DEB)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
# Depends: the runtime libraries the executable links, as dpkg-shlibdeps reads them from its ELF NEEDED
# entries (libvtk9.1, libopencv-*406, libopenvdb10.0, libtbb12, libglfw3, ...; never -dev). Ceres is linked
# from libceres-dev's libceres.a, so glog, CHOLMOD, CXSparse and LAPACK appear rather than libceres3.
# Besides those: what the binary opens at run time without linking it (the GUI's font, Mesa's GL drivers
# for llvmpipe); Xvfb only to render without a display.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# python3-numpy: the Python module's arrays (it links no libpython; python3 itself is what imports it).
set(CPACK_DEBIAN_PACKAGE_DEPENDS "fonts-dejavu-core, libgl1-mesa-dri, python3-numpy")
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "xvfb, xauth")
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
include(CPack)
