# The station's empty scene as PNG files (docs/interfaces.md §2).
list(APPEND CAPTURE_SOURCES ${CMAKE_CURRENT_LIST_DIR}/background_images.cpp ${CMAKE_CURRENT_LIST_DIR}/png_file.cpp)
