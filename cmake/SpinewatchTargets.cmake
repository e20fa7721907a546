# Shared compile settings for project code. Third-party headers are
# included as SYSTEM so -Werror applies to our code only.
add_library(spinewatch_warnings INTERFACE)
target_compile_options(spinewatch_warnings INTERFACE -Wall -Wextra -Wpedantic)
if(SPINEWATCH_WERROR)
  target_compile_options(spinewatch_warnings INTERFACE -Werror)
endif()

# The fuzz build instruments every library for libFuzzer's coverage
# (fuzzer-no-link) under ASan + UBSan; only the harnesses link the
# fuzzer's main (tests/fuzz/CMakeLists.txt).
if(SPINEWATCH_BUILD_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "SPINEWATCH_BUILD_FUZZ needs clang (the fuzz preset sets clang-14), not ${CMAKE_CXX_COMPILER_ID}")
  endif()
  add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
elseif(SPINEWATCH_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
  # GCC 12's -Wmaybe-uninitialized gives false positives under the
  # sanitizers' instrumentation: optimised, it flags libstdc++'s own
  # std::regex compiler (std::function in _M_disjunction) in a test that
  # only builds a pattern. The release build keeps the warning, as an
  # error, for the same code.
  target_compile_options(spinewatch_warnings INTERFACE -Wno-maybe-uninitialized)
endif()

# Release builds at -O2 but for the hot libraries (spinewatch_hot_library,
# below): CMake's Release default is -O3 for everything.
string(REPLACE "-O3" "-O2" CMAKE_CXX_FLAGS_RELEASE "${CMAKE_CXX_FLAGS_RELEASE}")

# The pure-computation libraries (frames, estimator, the phantom renderer)
# are hot (spinewatch_hot_library): compiled at -O2 under the sanitizers (checks below); the rest of the
# code at the ASan preset's -Og, which compiles the daemon's Asio/Beast
# batch in 62 s where -O1 takes 95 s (and -O0 51 s, but running the
# daemon's and tools' loops slower). At -O1 GCC inlines little of
# Eigen's fixed-size expressions or of the bit loops, and the tests that
# drive the estimator over many pairs ran 25–33× slower than in release
# (PopulationSweep 254 s against 7.6 s, ExposurePhantom 199 s against
# 7.0 s): most of CI's time under ASan.
#
# Two of UBSan's checks are left out there: `null` and `alignment`. GCC
# emits both on every reference bound and every member function called
# (each Eigen coefficient accessor, each evaluator), and in Eigen's
# fixed-size code they were half of the sanitized time: the OpenSim
# motion test (ExternalMotion.FactorsFitted…) ran 42 s with them, 22 s
# without, and its spine-dynamics batch compiled in 45 s instead of 72 s.
# What they would find here still fails loudly: a null pointer read is
# ASan's SEGV report with its stack, and Eigen reads its aligned types
# with aligned vector loads, which fault when misaligned. Every other check
# (ASan's, use-after-scope included; signed overflow, bounds, object size,
# shifts, enum and bool values, vptr) stays on in these libraries, and
# everything else is built with all of them.
#
# In a Release build (the release and arm64 presets) the same libraries are
# the only ones at -O3; everything else is at -O2, Debian's own level for
# its packages: the daemon's Asio/Beast batch, the CLI's and capture's
# compiled in 168.6 s of CPU against 197.2 s at -O3 (six batches, release
# flags), and nothing there runs per pixel.
function(spinewatch_hot_library target)
  if(SPINEWATCH_SANITIZE)
    target_compile_options(${target} PRIVATE -O2 -fno-sanitize=null,alignment)
  else()
    target_compile_options(${target} PRIVATE $<$<CONFIG:Release>:-O3>)
  endif()
endfunction()

# spinewatch_measurement_program(<target>)
# A program run by hand to measure (a sweep behind a table in docs/), with
# no test that runs it: the release build compiles it, so it keeps building;
# the sanitizer and cross builds leave it out of `all`, since nothing there
# runs it (docs/testing.md, "Build speed").
function(spinewatch_measurement_program target)
  if(SPINEWATCH_SANITIZE OR CMAKE_CROSSCOMPILING)
    set_target_properties(${target} PROPERTIES EXCLUDE_FROM_ALL ON)
  endif()
endfunction()

# spinewatch_unity_build(<target>)
# With SPINEWATCH_UNITY (the CI presets), the target's sources are compiled
# a batch at a time, each batch one translation unit: the inline code of
# CLI11, nlohmann::json, fmt and Eigen that every source instantiates is
# then parsed and optimised once a batch instead of once a file (the CLI's
# 22 sources: 320 s of CPU one by one, 73 s in three batches of 8). 16
# sources a batch: the release build took 1 066 s of CPU against 1 208 s
# with 8 (docs/testing.md, "Build speed"). Sources of one target therefore
# must not define the same name at namespace scope, anonymous namespaces
# included (shared constants: estimator/units.hpp, phantom's
# backdrop_wall.hpp).
# GCC's -Wsubobject-linkage is off there: a class with a member of an
# anonymous-namespace type is fine in a .cpp, and a batch is a .cpp that
# includes .cpps. Only the debug preset builds file by file, where every
# source must compile on its own (docs/testing.md, "Build speed").
set(SPINEWATCH_UNITY_BATCH 16 CACHE STRING "Sources per unity batch (SPINEWATCH_UNITY)")
function(spinewatch_unity_build target)
  if(SPINEWATCH_UNITY)
    set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE ${SPINEWATCH_UNITY_BATCH})
    if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
      target_compile_options(${target} PRIVATE -Wno-subobject-linkage)
    endif()
  endif()
endfunction()

# spinewatch_module(NAME <target> SOURCES ... DEPS ...)
# One library per module. Public headers (what other modules use) under
# <dir>/include/spinewatch/<module>/, included as "spinewatch/<module>/x.hpp";
# internal ones beside their sources, included by their path under <dir>/src
# ("cvsm/lanes.hpp"), which only the module itself sees (docs/architecture.md,
# "Headers").
function(spinewatch_module)
  cmake_parse_arguments(M "" "NAME" "SOURCES;DEPS;PRIVATE_DEPS" ${ARGN})
  add_library(${M_NAME} STATIC ${M_SOURCES})
  spinewatch_unity_build(${M_NAME})
  target_include_directories(${M_NAME} PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include
                                       PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/src)
  target_link_libraries(${M_NAME} PUBLIC ${M_DEPS} PRIVATE spinewatch_warnings ${M_PRIVATE_DEPS})
  add_library(spinewatch::${M_NAME} ALIAS ${M_NAME})
  # For spinewatch_fuzz_slice(): the deps as given, before CMake adds its own.
  set_target_properties(${M_NAME} PROPERTIES SPINEWATCH_DEPS "${M_DEPS}" SPINEWATCH_PRIVATE_DEPS "${M_PRIVATE_DEPS}")
endfunction()

# spinewatch_fuzz_slice(<module> [SOURCES <path>...])
# <module>_fuzzed: the module's sources that the fuzz harnesses' code
# reaches, and no others, compiled with the module's own settings; the
# module's deps that have a slice are replaced by it. The harnesses link
# slices, so the fuzz build compiles about 30 of the project's sources
# instead of every library whole: the estimator alone was 265 s of the
# fuzz build's 472 s of CPU, for 10 of its 76 sources (docs/testing.md,
# "Fuzzing"). Each path is the end of one of the module's sources
# ("camera/camera_model.cpp"); one that matches none, or two, stops the
# configure. Without SOURCES the slice is the module's headers and deps
# only (the harnesses call none of its code). A source that starts
# calling into another one shows up as an undefined symbol when a harness
# links: add that source to its module's slice in tests/fuzz/CMakeLists.txt.
function(spinewatch_fuzz_slice module)
  cmake_parse_arguments(S "" "" "SOURCES" ${ARGN})
  get_target_property(dir ${module} SOURCE_DIR)
  get_target_property(all_sources ${module} SOURCES)
  set(slice ${module}_fuzzed)
  set(deps "")
  set(private_deps "")
  foreach(kind deps private_deps)
    string(TOUPPER ${kind} property)
    get_target_property(given ${module} SPINEWATCH_${property})
    foreach(dep IN LISTS given)
      if(TARGET ${dep}_fuzzed)
        set(dep ${dep}_fuzzed)
      endif()
      list(APPEND ${kind} ${dep})
    endforeach()
  endforeach()
  if(NOT S_SOURCES)
    add_library(${slice} INTERFACE)
    target_include_directories(${slice} INTERFACE ${dir}/include)
    target_link_libraries(${slice} INTERFACE ${deps})
    return()
  endif()
  set(sources "")
  foreach(wanted IN LISTS S_SOURCES)
    set(found "")
    foreach(source IN LISTS all_sources)
      if(source MATCHES "(^|/)${wanted}$")
        list(APPEND found ${source})
      endif()
    endforeach()
    list(LENGTH found count)
    if(NOT count EQUAL 1)
      message(FATAL_ERROR "spinewatch_fuzz_slice(${module}): '${wanted}' matches ${count} of its sources (${found}); give a path that ends exactly one")
    endif()
    cmake_path(ABSOLUTE_PATH found BASE_DIRECTORY ${dir})
    list(APPEND sources ${found})
  endforeach()
  add_library(${slice} STATIC ${sources})
  spinewatch_unity_build(${slice})
  target_include_directories(${slice} PUBLIC ${dir}/include PRIVATE ${dir}/src)
  target_compile_options(${slice} PRIVATE $<TARGET_PROPERTY:${module},COMPILE_OPTIONS>)
  target_link_libraries(${slice} PUBLIC ${deps} PRIVATE spinewatch_warnings ${private_deps})
endfunction()

# spinewatch_internal_headers(NAME <target>)
# An INTERFACE target that puts this module's src/ on the include path: its
# internal headers, for its tests, benchmarks and fuzz harnesses (never for
# tools/ or another module). Link the module's library beside it. Tests see
# several modules' src/ at once, so an internal header's path under src/
# must be unique across them: checked here, at configure time.
function(spinewatch_internal_headers)
  cmake_parse_arguments(I "" "NAME" "" ${ARGN})
  set(src ${CMAKE_CURRENT_SOURCE_DIR}/src)
  add_library(${I_NAME} INTERFACE)
  target_include_directories(${I_NAME} INTERFACE ${src})
  file(GLOB_RECURSE headers RELATIVE ${src} CONFIGURE_DEPENDS ${src}/*.hpp)
  get_property(seen GLOBAL PROPERTY SPINEWATCH_INTERNAL_HEADERS)
  foreach(header IN LISTS headers)
    if(header IN_LIST seen)
      message(FATAL_ERROR "${src}/${header}: another module's src/ has an internal header at the same path; "
                          "rename one (tests see both src/ directories)")
    endif()
  endforeach()
  set_property(GLOBAL APPEND PROPERTY SPINEWATCH_INTERNAL_HEADERS ${headers})
endfunction()
