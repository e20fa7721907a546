list(APPEND CAPTURE_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/stream_session.cpp
  ${CMAKE_CURRENT_LIST_DIR}/system_v4l2_device.cpp
  ${CMAKE_CURRENT_LIST_DIR}/v4l2_camera.cpp
  ${CMAKE_CURRENT_LIST_DIR}/v4l2_probe.cpp)
