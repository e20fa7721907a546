# The libcamera frame source (issue #6 item 2): the real one when libcamera
# is found, else stubs whose every call says it is not built.
if(LIBCAMERA_FOUND)
  list(APPEND CAPTURE_SOURCES
    ${CMAKE_CURRENT_LIST_DIR}/camera_manager.cpp
    ${CMAKE_CURRENT_LIST_DIR}/libcamera_camera.cpp)
  # capture/CMakeLists.txt creates spinewatch_capture after including this
  # file: link once the directory is processed.
  cmake_language(DEFER CALL target_link_libraries spinewatch_capture PRIVATE PkgConfig::LIBCAMERA)
  cmake_language(DEFER CALL target_compile_definitions spinewatch_capture PUBLIC SPINEWATCH_HAVE_LIBCAMERA)
else()
  list(APPEND CAPTURE_SOURCES ${CMAKE_CURRENT_LIST_DIR}/libcamera_unavailable.cpp)
endif()
