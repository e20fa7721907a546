# Station calibration from a board (docs/calibration.md): OpenCV's calib3d
# and aruco (contrib) modules, private to the estimator.
list(APPEND ESTIMATOR_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/board.cpp
  ${CMAKE_CURRENT_LIST_DIR}/camera_views.cpp
  ${CMAKE_CURRENT_LIST_DIR}/rig_checks.cpp
  ${CMAKE_CURRENT_LIST_DIR}/stereo.cpp
  ${CMAKE_CURRENT_LIST_DIR}/station_calibration.cpp
  ${CMAKE_CURRENT_LIST_DIR}/view_collector.cpp)
# Calibrations from other tools (caliscope, anipose, OpenCV JSON): docs/import.md.
list(APPEND ESTIMATOR_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/foreign_calibration.cpp
  ${CMAKE_CURRENT_LIST_DIR}/foreign_json.cpp
  ${CMAKE_CURRENT_LIST_DIR}/foreign_toml.cpp)
