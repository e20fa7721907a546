# Read by cpack (CPACK_PROJECT_CONFIG_FILE) before it packages: a package
# built from a tree configured for /usr/local would install a unit and a
# daemon that point at /usr/local (Debian packages own /usr only).
if(NOT CPACK_SPINEWATCH_INSTALL_PREFIX STREQUAL "/usr")
  message(FATAL_ERROR "spinewatch package: this build tree is configured with CMAKE_INSTALL_PREFIX="
    "${CPACK_SPINEWATCH_INSTALL_PREFIX}; the package needs /usr. Build it with `make deb`, or configure "
    "with `cmake --preset release` (which sets /usr) or -DCMAKE_INSTALL_PREFIX=/usr.")
endif()

# A cross build's Depends (cmake/Packaging.cmake): dpkg-shlibdeps on the
# built programs, libraries looked up in the sysroot, their packages in the
# sysroot's shlibs files (scripts/arm64-sysroot).
if(CPACK_SPINEWATCH_SYSROOT)
  include(${CPACK_SPINEWATCH_PROGRAMS_FILE})
  set(shlibs ${CPACK_SPINEWATCH_SYSROOT}/var/lib/spinewatch-sysroot/shlibs)
  if(NOT EXISTS ${shlibs})
    message(FATAL_ERROR "spinewatch package: ${shlibs} is missing; the sysroot predates it: "
      "run scripts/arm64-sysroot (scripts/install-deps) to make it again")
  endif()
  set(work ${CPACK_PACKAGE_DIRECTORY}/_CPack_Packages/shlibdeps)
  file(MAKE_DIRECTORY ${work}/debian)
  file(WRITE ${work}/debian/control "Source: spinewatch\n\nPackage: spinewatch\nArchitecture: ${CPACK_DEBIAN_PACKAGE_ARCHITECTURE}\n")
  execute_process(
    COMMAND dpkg-shlibdeps -O -L${shlibs}
            -l${CPACK_SPINEWATCH_SYSROOT}/usr/lib/${CPACK_SPINEWATCH_MULTIARCH}
            -l${CPACK_SPINEWATCH_SYSROOT}/lib/${CPACK_SPINEWATCH_MULTIARCH}
            ${spinewatch_programs}
    WORKING_DIRECTORY ${work} OUTPUT_VARIABLE substvars ERROR_VARIABLE errors RESULT_VARIABLE rc)
  string(REGEX MATCH "shlibs:Depends=([^\n]*)" found "${substvars}")
  if(NOT rc EQUAL 0 OR NOT found)
    message(FATAL_ERROR "spinewatch package: dpkg-shlibdeps failed on ${spinewatch_programs}: ${errors}")
  endif()
  set(CPACK_DEBIAN_PACKAGE_DEPENDS "${CPACK_DEBIAN_PACKAGE_DEPENDS}, ${CMAKE_MATCH_1}")
endif()
