# The Debian package (`make deb`, docs/hardware.md "Installing from the
# package"): CPack's DEB generator over the project's install() rules.
# The architecture is the building machine's (dpkg --print-architecture),
# so the same command makes the amd64 package here and the arm64 one on a
# Pi. The maintainer scripts live in packaging/deb.
# A cross build (the arm64 preset) packages for its target: the Debian
# architecture of the toolchain's GNU triplet.
find_program(SPINEWATCH_DPKG dpkg)
find_program(SPINEWATCH_DPKG_ARCHITECTURE dpkg-architecture)
if(CMAKE_CROSSCOMPILING AND SPINEWATCH_DPKG_ARCHITECTURE)
  execute_process(COMMAND ${SPINEWATCH_DPKG_ARCHITECTURE} --host-type ${CMAKE_LIBRARY_ARCHITECTURE} --query DEB_HOST_ARCH
    OUTPUT_VARIABLE SPINEWATCH_DEB_ARCHITECTURE OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
elseif(SPINEWATCH_DPKG)
  execute_process(COMMAND ${SPINEWATCH_DPKG} --print-architecture
    OUTPUT_VARIABLE SPINEWATCH_DEB_ARCHITECTURE OUTPUT_STRIP_TRAILING_WHITESPACE)
endif()
set(SPINEWATCH_DEB_MAINTAINER "spinewatch maintainers <spinewatch@localhost>"
  CACHE STRING "The Maintainer: field of the Debian package")

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME spinewatch)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_VENDOR spinewatch)
set(CPACK_PACKAGE_CONTACT ${SPINEWATCH_DEB_MAINTAINER})
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "spine posture from two calibrated cameras (daemon and CLI)")
# One paragraph, lines under 80 columns (CPack indents them for control).
set(CPACK_PACKAGE_DESCRIPTION "\
spinewatchd estimates the 3D pose of the vertebrae T1 to L5 from two
calibrated cameras' silhouettes and publishes the posture stream on a TCP
port and a Unix socket; spinewatch is its command line (calibration,
recording, replay, reports). Ships the systemd unit, the annotated
configuration in /etc/spinewatch and a demo recording the daemon replays
when no cameras are present.")
# Installed where the configured paths say (the unit's ExecStart=, the
# daemon's compiled-in demo directory): the release preset uses /usr.
set(CPACK_PACKAGING_INSTALL_PREFIX ${CMAKE_INSTALL_PREFIX})
set(CPACK_DEBIAN_PACKAGE_RELEASE 1)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)  # spinewatch_<version>-<release>_<arch>.deb
if(SPINEWATCH_DEB_ARCHITECTURE)
  set(CPACK_DEBIAN_PACKAGE_ARCHITECTURE ${SPINEWATCH_DEB_ARCHITECTURE})
endif()
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
# The shared libraries' packages come from dpkg-shlibdeps; systemd brings
# systemctl and systemd-sysusers, which the maintainer scripts use.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "systemd")
# Cross-built programs: this machine's dpkg knows no arm64 library, so
# CPack's own dpkg-shlibdeps run would fail. PackagingChecks.cmake runs it
# instead on the two programs, finding the libraries in the sysroot and
# their packages in the shlibs files scripts/arm64-sysroot kept.
if(CMAKE_CROSSCOMPILING)
  set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS OFF)
  set(CPACK_SPINEWATCH_SYSROOT ${CMAKE_SYSROOT})
  set(CPACK_SPINEWATCH_MULTIARCH ${CMAKE_LIBRARY_ARCHITECTURE})
  set(CPACK_SPINEWATCH_PROGRAMS_FILE ${CMAKE_BINARY_DIR}/packaging/programs.cmake)
  file(GENERATE OUTPUT ${CPACK_SPINEWATCH_PROGRAMS_FILE}
       CONTENT "set(spinewatch_programs \"$<TARGET_FILE:spinewatchd>\" \"$<TARGET_FILE:spinewatch>\")\n")
endif()

# The maintainer scripts and the conffile list name the installed paths.
set(SPINEWATCH_CONFIG_DIR ${CMAKE_INSTALL_FULL_SYSCONFDIR}/spinewatch)
set(SPINEWATCH_CONFIG_FILE ${SPINEWATCH_CONFIG_DIR}/spinewatch.toml)
set(SPINEWATCH_DEB_CONTROL_DIR ${CMAKE_BINARY_DIR}/packaging/deb)
foreach(script conffiles postinst prerm postrm)
  configure_file(${CMAKE_CURRENT_LIST_DIR}/../packaging/deb/${script}.in ${SPINEWATCH_DEB_CONTROL_DIR}/${script} @ONLY)
endforeach()
set(CPACK_DEBIAN_PACKAGE_CONTROL_EXTRA
  ${SPINEWATCH_DEB_CONTROL_DIR}/conffiles ${SPINEWATCH_DEB_CONTROL_DIR}/postinst
  ${SPINEWATCH_DEB_CONTROL_DIR}/prerm ${SPINEWATCH_DEB_CONTROL_DIR}/postrm)
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)  # scripts 0755, conffiles 0644

# Only the package: no source package, no other generator.
set(CPACK_SOURCE_GENERATOR "")
set(CPACK_PROJECT_CONFIG_FILE ${CMAKE_CURRENT_LIST_DIR}/PackagingChecks.cmake)
set(CPACK_SPINEWATCH_INSTALL_PREFIX ${CMAKE_INSTALL_PREFIX})
include(CPack)
