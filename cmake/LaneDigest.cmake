# spinewatch_lane_digest(NAME <name> SUITE <test prefix> SOURCES ...)
#
# A hot loop with lanes (SSE2 on x86-64, NEON or scalar on aarch64, a
# generic fallback on any CPU) is proven the same on every CPU by a digest
# program: it runs the loop over many random inputs and prints one line.
# Built three ways from the same sources, the lines must be equal:
#   <name>_native   this build's CPU (SSE2 here)
#   <name>_generic  SPINEWATCH_LANES_GENERIC: the fallback, on this CPU
#   <name>.aarch64  aarch64-linux-gnu-g++ -static, run under qemu-aarch64
#                   (label arm64; scripts/install-deps installs both)
# Sources may use the estimator's (public and internal) and frames' headers and Eigen, nothing
# that needs a library of another architecture.
#
# In a cross build (the arm64 preset) this build's CPU is aarch64: _native
# is the NEON/scalar build, both programs run under the emulator, and the
# test is labelled arm64 with the preset's other tests.
find_program(SPINEWATCH_AARCH64_CXX aarch64-linux-gnu-g++)
find_program(SPINEWATCH_QEMU_AARCH64 NAMES qemu-aarch64-static qemu-aarch64)

function(spinewatch_lane_digest)
  cmake_parse_arguments(D "" "NAME;SUITE" "SOURCES" ${ARGN})
  set(includes ${SPINEWATCH_SOURCE_DIR}/estimator/include ${SPINEWATCH_SOURCE_DIR}/estimator/src
               ${SPINEWATCH_SOURCE_DIR}/frames/include)
  foreach(flavour native generic)
    add_executable(${D_NAME}_${flavour} ${D_SOURCES})
    target_link_libraries(${D_NAME}_${flavour} PRIVATE spinewatch_warnings Eigen3::Eigen)
    target_include_directories(${D_NAME}_${flavour} PRIVATE ${includes})
    target_compile_options(${D_NAME}_${flavour} PRIVATE -ffp-contract=off)
  endforeach()
  target_compile_definitions(${D_NAME}_generic PRIVATE SPINEWATCH_LANES_GENERIC)
  set(run "")
  set(labels unit)
  if(CMAKE_CROSSCOMPILING)
    set(run "${CMAKE_CROSSCOMPILING_EMULATOR};")
    set(labels "unit;arm64")
  endif()
  add_test(NAME ${D_SUITE}.GenericLanesPrintLikeTheBuild
           COMMAND ${CMAKE_COMMAND} "-DFIRST=${run}$<TARGET_FILE:${D_NAME}_native>" "-DSECOND=${run}$<TARGET_FILE:${D_NAME}_generic>"
                   -P ${SPINEWATCH_SOURCE_DIR}/cmake/compare_outputs.cmake)
  set_tests_properties(${D_SUITE}.GenericLanesPrintLikeTheBuild PROPERTIES LABELS "${labels}")

  if(CMAKE_CROSSCOMPILING)
    return()
  endif()
  if(NOT SPINEWATCH_AARCH64_CXX OR NOT SPINEWATCH_QEMU_AARCH64)
    message(STATUS "${D_NAME}: no aarch64-linux-gnu-g++ or qemu-aarch64; the arm64 digest is not built (scripts/install-deps)")
    return()
  endif()
  get_target_property(eigen_include Eigen3::Eigen INTERFACE_INCLUDE_DIRECTORIES)
  set(out ${CMAKE_CURRENT_BINARY_DIR}/${D_NAME}.aarch64)
  set(include_flags "")
  foreach(dir IN LISTS includes)
    list(APPEND include_flags -I${dir})
  endforeach()
  set(deps "")
  foreach(src IN LISTS D_SOURCES)
    list(APPEND deps ${src})
  endforeach()
  add_custom_command(OUTPUT ${out}
    COMMAND ${SPINEWATCH_AARCH64_CXX} -std=c++20 -O2 -static -ffp-contract=off -Wall -Wextra -Werror
            ${include_flags} -isystem ${eigen_include} ${D_SOURCES} -o ${out}
    DEPENDS ${deps} ${SPINEWATCH_SOURCE_DIR}/estimator/src/cvsm/lanes.hpp
    IMPLICIT_DEPENDS CXX ${D_SOURCES}
    COMMENT "${D_NAME} for aarch64")
  add_custom_target(${D_NAME}_aarch64 ALL DEPENDS ${out})
  add_test(NAME ${D_SUITE}.Arm64PrintsLikeTheBuild
           COMMAND ${CMAKE_COMMAND} "-DFIRST=$<TARGET_FILE:${D_NAME}_native>" "-DSECOND=${SPINEWATCH_QEMU_AARCH64};${out}"
                   -P ${SPINEWATCH_SOURCE_DIR}/cmake/compare_outputs.cmake)
  set_tests_properties(${D_SUITE}.Arm64PrintsLikeTheBuild PROPERTIES LABELS "unit;arm64")
endfunction()
