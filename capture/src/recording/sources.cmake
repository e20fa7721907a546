# Recording directories: recording.json, the .raw size rule, reader, writer,
# the paced/looping frame source, and the recorder (cameras → directory).
list(APPEND CAPTURE_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/json_text.cpp
  ${CMAKE_CURRENT_LIST_DIR}/recording_json.cpp
  ${CMAKE_CURRENT_LIST_DIR}/recording_json_format.cpp
  ${CMAKE_CURRENT_LIST_DIR}/raw_layout.cpp
  ${CMAKE_CURRENT_LIST_DIR}/reader.cpp
  ${CMAKE_CURRENT_LIST_DIR}/writer.cpp
  ${CMAKE_CURRENT_LIST_DIR}/recording_source.cpp
  ${CMAKE_CURRENT_LIST_DIR}/recorder.cpp)
