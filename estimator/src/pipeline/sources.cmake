list(APPEND ESTIMATOR_SOURCES ${CMAKE_CURRENT_LIST_DIR}/posture_estimator.cpp ${CMAKE_CURRENT_LIST_DIR}/estimator_config.cpp)
