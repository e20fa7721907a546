embed_text(${CMAKE_CURRENT_BINARY_DIR}/embedded/vertebra_geometry.cpp
  ${SPINEWATCH_SOURCE_DIR}/config/vertebra-geometry.toml vertebra_geometry_toml)
embed_text(${CMAKE_CURRENT_BINARY_DIR}/embedded/joint_stiffness.cpp
  ${SPINEWATCH_SOURCE_DIR}/config/spine-stiffness.toml joint_stiffness_toml)
list(APPEND ESTIMATOR_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/mass_properties.cpp
  ${CMAKE_CURRENT_LIST_DIR}/vertebra_geometry.cpp
  ${CMAKE_CURRENT_LIST_DIR}/joint_stiffness.cpp
  ${CMAKE_CURRENT_LIST_DIR}/subject.cpp
  ${CMAKE_CURRENT_LIST_DIR}/spine_model.cpp
  ${CMAKE_CURRENT_LIST_DIR}/spine_dynamics.cpp
  ${CMAKE_CURRENT_LIST_DIR}/deform_report.cpp
  ${CMAKE_CURRENT_LIST_DIR}/target_lines.cpp
  ${CMAKE_CURRENT_LIST_DIR}/stiffness_fit.cpp
  ${CMAKE_CURRENT_BINARY_DIR}/embedded/vertebra_geometry.cpp
  ${CMAKE_CURRENT_BINARY_DIR}/embedded/joint_stiffness.cpp)
