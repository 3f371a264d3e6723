# Installing facet (cmake --install) and packaging it (cpack -G DEB), under the GNU directories:
#   include/facet/...                 the public headers
#   lib/<arch>/libfacet.a or .so.*    static by default, shared with -DBUILD_SHARED_LIBS=ON
#   lib/<arch>/cmake/facet/           find_package(facet 0.1 CONFIG REQUIRED) -> facet::facet
#   lib/<arch>/pkgconfig/facet.pc     pkg-config --cflags --libs [--static] facet
#   bin/facet, bin/facet-view         the command line and its viewer (they find each other side by side)
#   share/man/man1/facet*.1.gz        generated from --help by help2man, when it is installed
#   share/thumbnailers/facet.thumbnailer, share/mime/packages/facet.xml   the desktop thumbnailer
#   share/doc/facet/, share/doc/libfacet-dev/   THIRD_PARTY.md and licenses/ (cmake/package.cmake)
# Components: `runtime` (executables, man pages, the shared library) and `dev` (the rest), which
# the Debian packaging turns into the packages facet and libfacet-dev. tests/install builds two
# consumer programs against an installed tree.
include(CMakePackageConfigHelpers)

set(FACET_CMAKE_INSTALL_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/facet)
get_target_property(_facet_type facet TYPE)
if(_facet_type STREQUAL "STATIC_LIBRARY")
  set(FACET_STATIC ON)
else()
  set(FACET_STATIC OFF)
endif()

install(TARGETS facet EXPORT facetTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT dev
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT runtime NAMELINK_COMPONENT dev)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/facet DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} COMPONENT dev
  FILES_MATCHING PATTERN "*.hpp")
install(EXPORT facetTargets NAMESPACE facet:: DESTINATION ${FACET_CMAKE_INSTALL_DIR} COMPONENT dev)

# Version rule: while the major version is 0, a minor release may break the API and ABI, so 0.1.x
# satisfies find_package(facet 0.1) but not 0.2 (SameMinorVersion); from 1.0 on, SameMajorVersion.
if(PROJECT_VERSION_MAJOR EQUAL 0)
  set(_facet_compatibility SameMinorVersion)
else()
  set(_facet_compatibility SameMajorVersion)
endif()
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/facetConfig.cmake.in
  ${PROJECT_BINARY_DIR}/facetConfig.cmake INSTALL_DESTINATION ${FACET_CMAKE_INSTALL_DIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/facetConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY ${_facet_compatibility})
install(FILES ${PROJECT_BINARY_DIR}/facetConfig.cmake ${PROJECT_BINARY_DIR}/facetConfigVersion.cmake
  DESTINATION ${FACET_CMAKE_INSTALL_DIR} COMPONENT dev)

# pkg-config: a static libfacet needs its dependencies on the link line (--static reads
# Requires.private and Libs.private); a shared one carries them itself. The prefix is found from
# the file's own place (${pcfiledir}), so a tree installed with --prefix or DESTDIR works as is.
string(REGEX REPLACE "[^/]+" ".." _facet_up "${CMAKE_INSTALL_LIBDIR}/pkgconfig")
if(NOT IS_ABSOLUTE "${CMAKE_INSTALL_LIBDIR}")
  set(FACET_PC_PREFIX "\${pcfiledir}/${_facet_up}")
else()
  set(FACET_PC_PREFIX "${CMAKE_INSTALL_PREFIX}")
endif()
if(IS_ABSOLUTE "${CMAKE_INSTALL_LIBDIR}")
  set(FACET_PC_LIBDIR "${CMAKE_INSTALL_LIBDIR}")
else()
  set(FACET_PC_LIBDIR "\${exec_prefix}/${CMAKE_INSTALL_LIBDIR}")
endif()
if(IS_ABSOLUTE "${CMAKE_INSTALL_INCLUDEDIR}")
  set(FACET_PC_INCLUDEDIR "${CMAKE_INSTALL_INCLUDEDIR}")
else()
  set(FACET_PC_INCLUDEDIR "\${prefix}/${CMAKE_INSTALL_INCLUDEDIR}")
endif()
set(FACET_PC_REQUIRES_PRIVATE "")
if(FACET_STATIC)
  set(FACET_PC_REQUIRES_PRIVATE "Requires.private: zlib stb libturbojpeg assimp libseccomp\n")
endif()
configure_file(${CMAKE_CURRENT_LIST_DIR}/facet.pc.in ${PROJECT_BINARY_DIR}/facet.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/facet.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig COMPONENT dev)

if(FACET_BUILD_APPS)
  install(TARGETS facet_cli facet_view RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT runtime)
  install(TARGETS facet_exr LIBRARY DESTINATION ${FACET_MODULE_INSTALL_DIR} COMPONENT runtime)
endif()
install(TARGETS facet_assimp LIBRARY DESTINATION ${FACET_MODULE_INSTALL_DIR} COMPONENT runtime)
if(FACET_BUILD_APPS)
  # Man pages from the executables' own --help, so they cannot drift from it: facet(1) for the
  # command and facet-render(1), facet-thumbs(1), facet-thumbnail(1), facet-view(1) (also the
  # viewer executable's) and facet-diff(1) for the subcommands. help2man names a page after the program it runs, so each
  # page runs a small wrapper of that name, which also makes the usage line say "facet", not the
  # build tree's path.
  # Not in sanitizer builds, whose executables are for the tests (and whose leak checker would
  # judge each run of --help).
  find_program(FACET_HELP2MAN help2man)
  if(FACET_HELP2MAN AND NOT CMAKE_CXX_FLAGS MATCHES "-fsanitize")
    set(_facet_man_pages)
    foreach(entry IN ITEMS
        "facet|a software 3D renderer: model files to PNG on the CPU, or in a window"
        "render|render a model file, or the default scene, to a PNG"
        "thumbs|render a thumbnail PNG of every model in files and directories"
        "thumbnail|render one thumbnail PNG for a file manager (the freedesktop thumbnailer)"
        "view|show a model in an interactive window"
        "diff|compare two PNG images for visual tests")
      string(REPLACE "|" ";" entry "${entry}")
      list(GET entry 0 sub)
      list(GET entry 1 description)
      if(sub STREQUAL "facet")
        set(page facet)
        set(args "")
      else()
        set(page facet-${sub})
        set(args " ${sub}")
      endif()
      set(wrapper ${PROJECT_BINARY_DIR}/man/programs/${page})
      file(GENERATE OUTPUT ${wrapper}
        CONTENT "#!/bin/bash\nexec -a facet '$<TARGET_FILE:facet_cli>'${args} \"$@\"\n"
        FILE_PERMISSIONS OWNER_READ OWNER_WRITE OWNER_EXECUTE GROUP_READ GROUP_EXECUTE WORLD_READ WORLD_EXECUTE)
      set(out ${PROJECT_BINARY_DIR}/man/${page}.1)
      add_custom_command(OUTPUT ${out}.gz
        COMMAND ${FACET_HELP2MAN} --no-info --no-discard-stderr --section=1 --version-string=${PROJECT_VERSION}
                "--name=${description}" --output=${out} ${wrapper}
        COMMAND gzip -9nf ${out}
        DEPENDS facet_cli ${wrapper}
        COMMENT "Man page ${page}.1 from facet${args} --help"
        VERBATIM)
      list(APPEND _facet_man_pages ${out}.gz)
    endforeach()
    add_custom_target(facet_man_pages ALL DEPENDS ${_facet_man_pages})
    install(FILES ${_facet_man_pages} DESTINATION ${CMAKE_INSTALL_MANDIR}/man1 COMPONENT runtime)
  elseif(NOT FACET_HELP2MAN)
    message(STATUS "help2man not found: no man pages (scripts/setup installs it)")
  endif()
endif()

# The desktop thumbnailer (README, "Thumbnails in the file manager"): the entry file managers read
# to call `facet thumbnail`, and the MIME types of facet's formats that shared-mime-info lacks (as
# facet.xml: one file per package; Debian's shared-mime-info trigger updates the database).
if(FACET_BUILD_APPS)
  install(FILES ${PROJECT_SOURCE_DIR}/packaging/facet.thumbnailer DESTINATION ${CMAKE_INSTALL_DATADIR}/thumbnailers
    COMPONENT runtime)
  install(FILES ${PROJECT_SOURCE_DIR}/packaging/facet-mime.xml DESTINATION ${CMAKE_INSTALL_DATADIR}/mime/packages
    RENAME facet.xml COMPONENT runtime)
endif()

include(${CMAKE_CURRENT_LIST_DIR}/package.cmake)
