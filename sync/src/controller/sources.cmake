list(APPEND SYNC_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/serial_line.cpp
  ${CMAKE_CURRENT_LIST_DIR}/trigger_controller.cpp
  ${CMAKE_CURRENT_LIST_DIR}/trigger_replies.cpp)
