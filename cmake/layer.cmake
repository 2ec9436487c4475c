# axis_layer(NAME [PUBLIC deps...] [PRIVATE deps...]): the library of one
# layer folder (docs/architecture.md). Every .cc of the folder and of its
# internal/ subfolder belongs to it; it links only to the layers below it, which the build states here and
# tests/layering_test.py checks against the #include lines. Installed as
# libservo_axis_id_<NAME>.a, exported as servo_axis_id::<NAME>.
function(axis_layer name)
  file(GLOB sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*.cc
                                      ${CMAKE_CURRENT_SOURCE_DIR}/internal/*.cc)
  add_library(${name} ${sources})
  target_link_libraries(${name} ${ARGN})
  set_target_properties(${name} PROPERTIES OUTPUT_NAME servo_axis_id_${name})
endfunction()
