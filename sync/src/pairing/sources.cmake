list(APPEND SYNC_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/frame_pairer.cpp
  ${CMAKE_CURRENT_LIST_DIR}/pairing_stats.cpp
  ${CMAKE_CURRENT_LIST_DIR}/sequence_tracker.cpp)
