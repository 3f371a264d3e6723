# Debian packages by CPack, from a release build (cmake/install.cmake's components), configured
# for /usr so that the library goes to Debian's multiarch directory:
#   cmake --preset release -DCMAKE_INSTALL_PREFIX=/usr && cmake --build --preset release
#   (cd build/release && cpack -G DEB)
#   -> facet_<version>_<arch>.deb         facet, facet-view, their man pages (and a shared libfacet)
#      libfacet-dev_<version>_<arch>.deb  headers, libfacet.a, the CMake package, facet.pc
# The runtime dependencies of facet are read off its executables by dpkg-shlibdeps; libfacet-dev
# depends on the -dev packages a static libfacet links with. docs/PACKAGING.md lists what lintian
# says of them and why what remains remains.
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME facet)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
# A packager sets the maintainer; lintian rejects the placeholder's host only if it is not a domain.
set(FACET_PACKAGE_MAINTAINER "facet developers <facet@example.org>" CACHE STRING "Maintainer of the Debian packages")
set(CPACK_PACKAGE_CONTACT "${FACET_PACKAGE_MAINTAINER}")
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_COMPONENTS_ALL runtime dev)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)

set(CPACK_DEBIAN_RUNTIME_PACKAGE_NAME facet)
set(CPACK_DEBIAN_RUNTIME_PACKAGE_SECTION graphics)
set(CPACK_DEBIAN_RUNTIME_PACKAGE_SHLIBDEPS ON)
# Opened with dlopen when a PNG is read (src/io/png.cpp), so dpkg-shlibdeps does not see it.
set(CPACK_DEBIAN_RUNTIME_PACKAGE_DEPENDS "libspng0")
set(CPACK_DEBIAN_RUNTIME_DESCRIPTION "software 3D renderer: model files to PNG on the CPU
facet renders 3D model files (OBJ, STL, PLY, OFF, glTF, FBX, 3MF, COLLADA and
every other format assimp reads) to PNG images on the CPU, without a GPU or a
display, deterministic to the byte whatever the thread count or instruction
set. It makes thumbnails of whole directories, compares images for visual
tests (facet diff, facet render --reference) and shows models in a window
(facet view).")

set(CPACK_DEBIAN_DEV_PACKAGE_NAME libfacet-dev)
set(CPACK_DEBIAN_DEV_PACKAGE_SECTION libdevel)
set(CPACK_DEBIAN_DEV_PACKAGE_DEPENDS "libassimp-dev, libseccomp-dev, zlib1g-dev, libstb-dev, pkg-config")
if(NOT FACET_STATIC)
  set(CPACK_DEBIAN_DEV_PACKAGE_DEPENDS "facet (= ${PROJECT_VERSION}), ${CPACK_DEBIAN_DEV_PACKAGE_DEPENDS}")
endif()
set(CPACK_DEBIAN_DEV_DESCRIPTION "software 3D renderer - development files
facet is a software 3D renderer in C++20: triangles to pixels on the CPU,
tile-binned, SIMD with run-time dispatch, deterministic to the byte.
.
This package holds the headers, the library, the CMake package
(find_package(facet) gives facet::facet) and facet.pc for pkg-config.")

# Debian's documentation files for each package: a changelog (a native package's, compressed as
# policy asks), the third-party code in what it installs with the copyright files and licence texts
# of what is compiled or linked in (docs/THIRD_PARTY.md, packaging/licenses/) and, once the project
# declares a license in LICENSE, the copyright file.
string(TIMESTAMP _facet_date "%a, %d %b %Y %H:%M:%S +0000" UTC)
foreach(component IN ITEMS runtime dev)
  string(TOUPPER ${component} _c)
  set(_facet_pkg ${CPACK_DEBIAN_${_c}_PACKAGE_NAME})
  set(_facet_doc ${PROJECT_BINARY_DIR}/debian/${_facet_pkg})
  file(WRITE ${_facet_doc}/changelog "${_facet_pkg} (${PROJECT_VERSION}) unstable; urgency=medium

  * Built from facet's source tree by CPack (cmake/package.cmake).

 -- ${FACET_PACKAGE_MAINTAINER}  ${_facet_date}
")
  add_custom_command(OUTPUT ${_facet_doc}/changelog.gz
    COMMAND gzip -9nkf ${_facet_doc}/changelog
    DEPENDS ${_facet_doc}/changelog VERBATIM)
  add_custom_target(facet_debian_changelog_${component} ALL DEPENDS ${_facet_doc}/changelog.gz)
  install(FILES ${_facet_doc}/changelog.gz DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/${_facet_pkg} COMPONENT ${component})
  install(FILES ${PROJECT_SOURCE_DIR}/docs/THIRD_PARTY.md DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/${_facet_pkg}
    COMPONENT ${component})
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/packaging/licenses DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/${_facet_pkg}
    COMPONENT ${component})
  if(EXISTS ${PROJECT_SOURCE_DIR}/LICENSE)
    install(FILES ${PROJECT_SOURCE_DIR}/LICENSE DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/${_facet_pkg}
      RENAME copyright COMPONENT ${component})
  endif()
endforeach()

include(CPack)
