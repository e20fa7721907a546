embed_text(${CMAKE_CURRENT_BINARY_DIR}/embedded/segments.cpp
  ${SPINEWATCH_SOURCE_DIR}/config/segments.toml segments_toml)
embed_text(${CMAKE_CURRENT_BINARY_DIR}/embedded/alerts.cpp
  ${SPINEWATCH_SOURCE_DIR}/config/alerts.toml builtin_alerts_toml)
list(APPEND ESTIMATOR_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/schultz.cpp
  ${CMAKE_CURRENT_LIST_DIR}/ergonomics.cpp
  ${CMAKE_CURRENT_LIST_DIR}/exposure_summary.cpp
  ${CMAKE_CURRENT_LIST_DIR}/exposure_accumulator.cpp
  ${CMAKE_CURRENT_LIST_DIR}/exposure_json.cpp
  ${CMAKE_CURRENT_LIST_DIR}/alerts.cpp
  ${CMAKE_CURRENT_LIST_DIR}/alert_json.cpp
  ${CMAKE_CURRENT_BINARY_DIR}/embedded/alerts.cpp
  ${CMAKE_CURRENT_BINARY_DIR}/embedded/segments.cpp)
