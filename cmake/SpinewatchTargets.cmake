# Shared compile settings for project code. Third-party headers are
# included as SYSTEM so -Werror applies to our code only.
add_library(spinewatch_warnings INTERFACE)
target_compile_options(spinewatch_warnings INTERFACE -Wall -Wextra -Wpedantic)
if(SPINEWATCH_WERROR)
  target_compile_options(spinewatch_warnings INTERFACE -Werror)
endif()

if(SPINEWATCH_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
endif()

# spinewatch_module(NAME <target> SOURCES ... DEPS ...)
# One library per module, public headers under <dir>/include/spinewatch/<module>/.
function(spinewatch_module)
  cmake_parse_arguments(M "" "NAME" "SOURCES;DEPS;PRIVATE_DEPS" ${ARGN})
  add_library(${M_NAME} STATIC ${M_SOURCES})
  target_include_directories(${M_NAME} PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include)
  target_link_libraries(${M_NAME} PUBLIC ${M_DEPS} PRIVATE spinewatch_warnings ${M_PRIVATE_DEPS})
  add_library(spinewatch::${M_NAME} ALIAS ${M_NAME})
endfunction()
