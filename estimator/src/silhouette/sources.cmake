list(APPEND ESTIMATOR_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/bit_mask.cpp
  ${CMAKE_CURRENT_LIST_DIR}/silhouette_extractor.cpp
  ${CMAKE_CURRENT_LIST_DIR}/threshold_row.cpp
  ${CMAKE_CURRENT_LIST_DIR}/threshold_colour.cpp
  ${CMAKE_CURRENT_LIST_DIR}/blob_cleaning.cpp
  ${CMAKE_CURRENT_LIST_DIR}/background_model.cpp
  ${CMAKE_CURRENT_LIST_DIR}/background_bootstrap.cpp
  ${CMAKE_CURRENT_LIST_DIR}/person_prior.cpp
  ${CMAKE_CURRENT_LIST_DIR}/view_coverage.cpp
  ${CMAKE_CURRENT_LIST_DIR}/still_scenery.cpp
  ${CMAKE_CURRENT_LIST_DIR}/scene_edges.cpp)
