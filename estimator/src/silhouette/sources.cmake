list(APPEND ESTIMATOR_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/bit_mask.cpp
  ${CMAKE_CURRENT_LIST_DIR}/silhouette_extractor.cpp
  ${CMAKE_CURRENT_LIST_DIR}/threshold_row.cpp
  ${CMAKE_CURRENT_LIST_DIR}/blob_cleaning.cpp)
