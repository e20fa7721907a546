list(APPEND ESTIMATOR_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/cvsm_spec.cpp
  ${CMAKE_CURRENT_LIST_DIR}/body_model.cpp
  ${CMAKE_CURRENT_LIST_DIR}/fixed_camera.cpp
  ${CMAKE_CURRENT_LIST_DIR}/xor_cost.cpp
  ${CMAKE_CURRENT_LIST_DIR}/outline_ends.cpp
  ${CMAKE_CURRENT_LIST_DIR}/silhouette_edges.cpp
  ${CMAKE_CURRENT_LIST_DIR}/outline_fit.cpp
  ${CMAKE_CURRENT_LIST_DIR}/occluder_edge.cpp
  ${CMAKE_CURRENT_LIST_DIR}/unseen_end.cpp
  ${CMAKE_CURRENT_LIST_DIR}/side_cut.cpp
  ${CMAKE_CURRENT_LIST_DIR}/lower_residual.cpp
  ${CMAKE_CURRENT_LIST_DIR}/pelvis_in_view.cpp
  ${CMAKE_CURRENT_LIST_DIR}/head_in_view.cpp
  ${CMAKE_CURRENT_LIST_DIR}/posture_hidden.cpp
  ${CMAKE_CURRENT_LIST_DIR}/legs_region.cpp
  ${CMAKE_CURRENT_LIST_DIR}/segment_scan.cpp
  ${CMAKE_CURRENT_LIST_DIR}/subject_estimate.cpp
  ${CMAKE_CURRENT_LIST_DIR}/subject_heading.cpp
  ${CMAKE_CURRENT_LIST_DIR}/facing_check.cpp
  ${CMAKE_CURRENT_LIST_DIR}/upright_view.cpp
  ${CMAKE_CURRENT_LIST_DIR}/template_fit.cpp
  ${CMAKE_CURRENT_LIST_DIR}/search_params.cpp
  ${CMAKE_CURRENT_LIST_DIR}/armless_model.cpp
  ${CMAKE_CURRENT_LIST_DIR}/tracker.cpp
  ${CMAKE_CURRENT_LIST_DIR}/tracker_building.cpp
  ${CMAKE_CURRENT_LIST_DIR}/tracker_search.cpp
  ${CMAKE_CURRENT_LIST_DIR}/tracker_limbs.cpp
  ${CMAKE_CURRENT_LIST_DIR}/tracker_refine.cpp
  ${CMAKE_CURRENT_LIST_DIR}/tracker_heading.cpp
  ${CMAKE_CURRENT_LIST_DIR}/tracker_legs.cpp
  ${CMAKE_CURRENT_LIST_DIR}/tracker_hidden.cpp)
# The generic model, built into the library (like config/spine-generic.toml).
embed_text(${CMAKE_CURRENT_BINARY_DIR}/embedded/cvsm_generic.cpp
  ${SPINEWATCH_SOURCE_DIR}/config/cvsm-generic.toml generic_cvsm_toml)
list(APPEND ESTIMATOR_SOURCES ${CMAKE_CURRENT_BINARY_DIR}/embedded/cvsm_generic.cpp)
