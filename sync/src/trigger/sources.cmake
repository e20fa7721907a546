list(APPEND SYNC_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/edge_clock.cpp
  ${CMAKE_CURRENT_LIST_DIR}/gpiod_trigger_line.cpp
  ${CMAKE_CURRENT_LIST_DIR}/latency_histogram.cpp
  ${CMAKE_CURRENT_LIST_DIR}/trigger_master.cpp
  ${CMAKE_CURRENT_LIST_DIR}/trigger_slave.cpp
  ${CMAKE_CURRENT_LIST_DIR}/trigger_source.cpp)
