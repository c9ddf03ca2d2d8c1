# SPDX-License-Identifier: Apache-2.0
# Installation and packaging: `cmake --install` puts the morphmill binary and its man page
# (component "runtime"), and the libraries, public headers, CMake package (MorphMillConfig.cmake:
# MorphMill::morph, ::vdb_ref, ::raytest, ::planar_ref, ::morphmill) and pkg-config file
# (component "development") under the prefix. `cpack` (in the build directory) makes one .deb per
# component: morphmill and libmorphmill-dev. Tested by tests/install/install_test.sh.
include(CMakePackageConfigHelpers)

# Installed names that cannot clash with other packages' libraries (libmorph.a would).
set_target_properties(morph PROPERTIES OUTPUT_NAME morphmill_morph)
set_target_properties(vdb_ref PROPERTIES OUTPUT_NAME morphmill_vdb_ref)
set_target_properties(raytest PROPERTIES OUTPUT_NAME morphmill_raytest)
set_target_properties(planar_ref PROPERTIES OUTPUT_NAME morphmill_planar_ref)
# The library behind the CLI (job files, mesh I/O, verify): libmorphmill.a, MorphMill::morphmill.
set_target_properties(morphmill_app PROPERTIES OUTPUT_NAME morphmill EXPORT_NAME morphmill)

# A sanitized build installs instrumented libraries: whoever links them needs the runtimes, so the
# CMake package and the pkg-config file say so.
set(MORPHMILL_PC_SANITIZE "")
if(MORPHMILL_SANITIZE)
  set_property(TARGET morph APPEND PROPERTY INTERFACE_LINK_OPTIONS
               "$<INSTALL_INTERFACE:-fsanitize=address,undefined>")
  set(MORPHMILL_PC_SANITIZE " -fsanitize=address,undefined")
endif()

set(MORPHMILL_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/MorphMill)

install(TARGETS morphmill RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT runtime)
# The man page is generated from the program's own --help (scripts/make-manpage.sh).
add_custom_command(OUTPUT ${CMAKE_CURRENT_BINARY_DIR}/morphmill.1
                   COMMAND bash ${PROJECT_SOURCE_DIR}/scripts/make-manpage.sh $<TARGET_FILE:morphmill>
                           ${CMAKE_CURRENT_BINARY_DIR}/morphmill.1 ${PROJECT_VERSION}
                   DEPENDS morphmill ${PROJECT_SOURCE_DIR}/scripts/make-manpage.sh
                   COMMENT "Generating the morphmill(1) man page from --help" VERBATIM)
add_custom_target(morphmill_manpage ALL DEPENDS ${CMAKE_CURRENT_BINARY_DIR}/morphmill.1)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/morphmill.1 DESTINATION ${CMAKE_INSTALL_MANDIR}/man1 COMPONENT runtime)
install(FILES ${PROJECT_SOURCE_DIR}/LICENSE ${PROJECT_SOURCE_DIR}/NOTICE
              ${PROJECT_SOURCE_DIR}/LICENSES/LGPL-3.0-or-later.txt ${PROJECT_SOURCE_DIR}/LICENSES/GPL-3.0-or-later.txt
        DESTINATION ${CMAKE_INSTALL_DATAROOTDIR}/doc/morphmill COMPONENT runtime)

install(TARGETS morph vdb_ref raytest planar_ref morphmill_app
        EXPORT MorphMillTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT development
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
foreach(library morph vdb_ref raytest planar_ref)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${library}/include/${library}
          DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} COMPONENT development)
endforeach()
install(DIRECTORY ${PROJECT_SOURCE_DIR}/apps/include/morphmill
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} COMPONENT development)
install(EXPORT MorphMillTargets NAMESPACE MorphMill:: DESTINATION ${MORPHMILL_CMAKE_DIR}
        COMPONENT development)

# OpenVDB 10 ships only a Find module, in a directory of its own; consumers need it too.
set(MORPHMILL_OPENVDB_MODULE_DIR /usr/lib/x86_64-linux-gnu/cmake/OpenVDB)
foreach(dir IN LISTS CMAKE_MODULE_PATH)
  if(EXISTS ${dir}/FindOpenVDB.cmake)
    set(MORPHMILL_OPENVDB_MODULE_DIR ${dir})
  endif()
endforeach()
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/MorphMillConfig.cmake.in
                              ${CMAKE_CURRENT_BINARY_DIR}/MorphMillConfig.cmake
                              INSTALL_DESTINATION ${MORPHMILL_CMAKE_DIR})
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/MorphMillConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/MorphMillConfig.cmake
              ${CMAKE_CURRENT_BINARY_DIR}/MorphMillConfigVersion.cmake
        DESTINATION ${MORPHMILL_CMAKE_DIR} COMPONENT development)

# Relocatable: the prefix is found from the .pc file's own place (the .deb installs under /usr).
file(RELATIVE_PATH MORPHMILL_PC_TO_PREFIX /prefix/${CMAKE_INSTALL_LIBDIR}/pkgconfig /prefix)
configure_file(${PROJECT_SOURCE_DIR}/cmake/morphmill.pc.in ${CMAKE_CURRENT_BINARY_DIR}/morphmill.pc @ONLY)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/morphmill.pc
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig COMPONENT development)

# Debian packages (cpack -G DEB). The binary's shared-library dependencies come from
# dpkg-shlibdeps; PLPlot loads its cairo driver at run time, so that one is named. The -dev package
# needs the development packages of everything the static libraries and headers use.
set(CPACK_PACKAGE_NAME morphmill)
set(CPACK_PACKAGE_VENDOR "MorphMill developers")
set(CPACK_PACKAGE_CONTACT "MorphMill developers <morphmill@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "exact milling verification: what a tool leaves of a part, and how exact it is")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_RESOURCE_FILE_LICENSE ${PROJECT_SOURCE_DIR}/LICENSE)
set(CPACK_GENERATOR DEB)
set(CPACK_STRIP_FILES ON)
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_COMPONENTS_ALL runtime development)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_RUNTIME_PACKAGE_NAME morphmill)
set(CPACK_DEBIAN_RUNTIME_PACKAGE_DEPENDS "plplot-driver-cairo")
if(MORPHMILL_PYTHON_DEPENDS)  # the Python module is in the runtime package
  string(APPEND CPACK_DEBIAN_RUNTIME_PACKAGE_DEPENDS ", ${MORPHMILL_PYTHON_DEPENDS}")
endif()
set(CPACK_DEBIAN_DEVELOPMENT_PACKAGE_NAME libmorphmill-dev)
set(CPACK_DEBIAN_DEVELOPMENT_PACKAGE_SECTION libdevel)
set(CPACK_DEBIAN_DEVELOPMENT_PACKAGE_DEPENDS
    "cmake, pkg-config, libeigen3-dev, libtbb-dev, libopenvdb-dev, libembree-dev, libopenmesh-dev, libcgal-dev, nlohmann-json3-dev, libcli11-dev, libfmt-dev, libstb-dev, libpolyclipping-dev, libplplot-dev, libssl-dev, libcairo2-dev")
set(CPACK_COMPONENT_RUNTIME_DESCRIPTION
    "the morphmill command line: exact erosion surfaces of milling jobs (G-code, CAMotics projects), an OpenVDB reference, deviation heatmaps and verification reports")
set(CPACK_COMPONENT_DEVELOPMENT_DESCRIPTION
    "MorphMill's C++ libraries (static), headers, CMake package MorphMill and pkg-config file morphmill")
include(CPack)
