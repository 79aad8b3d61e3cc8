# What `cmake --install` puts under the prefix (docs/install.md):
#   bin/mesodpd                                   the command
#   include/mesodpd/*.hpp                         the public headers (nothing from src/)
#   lib/libmesodpd*.a                             the static libraries
#   lib/cmake/mesodpd/                            the package: find_package(mesodpd), targets mesodpd::<name>
#   ${MESODPD_PYTHON_INSTALL_DIR}/mesodpd/        the Python package (_core and the .py files)
# Components: runtime (the command), development (libraries, headers, package), python.
# Included last from the top-level CMakeLists.txt, so every target below already exists.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

# The libraries a consumer links, exported as mesodpd::<target>: the shared options and every module
# library (mesodpd_module() in cmake/MesodpdModules.cmake records each), the umbrella mesodpd among them.
# Their other PUBLIC link dependencies are found by mesodpdConfig.cmake.in.
set(MESODPD_LIBRARY_TARGETS mesodpd_options ${MESODPD_MODULE_TARGETS})

set(MESODPD_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/mesodpd CACHE STRING
    "Where the CMake package files go, relative to the prefix")

# The public headers use std::span and friends: a consumer must compile as C++20 even when it does not
# set CMAKE_CXX_STANDARD itself. In this build the flag is the same -std=c++20 as before.
target_compile_features(mesodpd_options INTERFACE cxx_std_20)

install(TARGETS mesodpd_app RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT runtime)

install(TARGETS ${MESODPD_LIBRARY_TARGETS} EXPORT mesodpdTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT development
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT development
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/mesodpd DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
        COMPONENT development FILES_MATCHING PATTERN "*.hpp")
install(EXPORT mesodpdTargets NAMESPACE mesodpd:: FILE mesodpdTargets.cmake
        DESTINATION ${MESODPD_INSTALL_CMAKEDIR} COMPONENT development)
# The same names in this build tree, so a project that adds mesodpd with add_subdirectory() links
# mesodpd::mesodpd exactly as one that finds the installed package.
foreach(t ${MESODPD_LIBRARY_TARGETS})
  if(NOT TARGET mesodpd::${t})
    add_library(mesodpd::${t} ALIAS ${t})
  endif()
endforeach()

# The package config finds what the exported targets link: it needs to know whether this build had MPI.
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/mesodpdConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/mesodpdConfig.cmake
                              INSTALL_DESTINATION ${MESODPD_INSTALL_CMAKEDIR})
# 0.x: a minor release may change the API, so only the same major.minor satisfies a request.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/mesodpdConfigVersion.cmake
                                 VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/mesodpdConfig.cmake ${PROJECT_BINARY_DIR}/mesodpdConfigVersion.cmake
        DESTINATION ${MESODPD_INSTALL_CMAKEDIR} COMPONENT development)

# The Python package. Default place: lib/python3.X/site-packages, the layout of upstream Python's
# prefix scheme and of a virtual environment, so `--prefix` a venv puts it on that venv's path; with any
# other prefix, PYTHONPATH=<prefix>/lib/python3.X/site-packages. Debian's own interpreter reads
# dist-packages instead: -DMESODPD_PYTHON_INSTALL_DIR=lib/python3/dist-packages for a /usr/local install.
# The version is in the path because _core is built for that interpreter's ABI only.
if(TARGET mesodpd_python)
  get_directory_property(py_major DIRECTORY ${PROJECT_SOURCE_DIR}/python DEFINITION Python3_VERSION_MAJOR)
  get_directory_property(py_minor DIRECTORY ${PROJECT_SOURCE_DIR}/python DEFINITION Python3_VERSION_MINOR)
  get_directory_property(py_files DIRECTORY ${PROJECT_SOURCE_DIR}/python DEFINITION MESODPD_PY_FILES)
  set(MESODPD_PYTHON_INSTALL_DIR lib/python${py_major}.${py_minor}/site-packages CACHE STRING
      "Where the Python package mesodpd/ goes, relative to the prefix (or absolute)")
  install(TARGETS mesodpd_python LIBRARY DESTINATION ${MESODPD_PYTHON_INSTALL_DIR}/mesodpd COMPONENT python)
  list(TRANSFORM py_files PREPEND ${PROJECT_SOURCE_DIR}/python/mesodpd/)
  install(FILES ${py_files} DESTINATION ${MESODPD_PYTHON_INSTALL_DIR}/mesodpd COMPONENT python)
endif()
