# embed_text(<out.cpp> <file> <function>): a .cpp defining
# `std::string_view <function>()` that returns the file's text.
function(embed_text out file function)
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${file})
  file(READ ${file} content)
  file(WRITE ${out}.tmp "// Generated from ${file}; do not edit.\n#include <string_view>\nnamespace spinewatch {\nstd::string_view ${function}() {\n  static constexpr char text[] = R\"embed(${content})embed\";\n  return {text, sizeof(text) - 1};\n}\n}  // namespace spinewatch\n")
  file(COPY_FILE ${out}.tmp ${out} ONLY_IF_DIFFERENT)
endfunction()
