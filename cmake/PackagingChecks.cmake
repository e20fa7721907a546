# Read by cpack (CPACK_PROJECT_CONFIG_FILE) before it packages: a package
# built from a tree configured for /usr/local would install a unit and a
# daemon that point at /usr/local (Debian packages own /usr only).
if(NOT CPACK_SPINEWATCH_INSTALL_PREFIX STREQUAL "/usr")
  message(FATAL_ERROR "spinewatch package: this build tree is configured with CMAKE_INSTALL_PREFIX="
    "${CPACK_SPINEWATCH_INSTALL_PREFIX}; the package needs /usr. Build it with `make deb`, or configure "
    "with `cmake --preset release` (which sets /usr) or -DCMAKE_INSTALL_PREFIX=/usr.")
endif()
