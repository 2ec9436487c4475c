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
  axis_use_pch(${name} library)  # cmake/precompiled_headers.cmake
endfunction()

# axis_fuzz_coverage(TARGET...): compiles the sources of each TARGET that
# read text (all of the io library; elsewhere every .cc that uses YAML::)
# with libFuzzer's coverage hooks (-fsanitize=fuzzer-no-link, clang), so the
# fuzz targets of fuzz/ see the branches of the loaders they drive while the
# numerical code of the same libraries stays uninstrumented. Used only with
# -DAXIS_FUZZ=ON (scripts/configure-sanitize).
function(axis_fuzz_coverage)
  foreach(target ${ARGN})
    get_target_property(sources ${target} SOURCES)
    get_target_property(source_dir ${target} SOURCE_DIR)
    set(instrumented "")
    foreach(source ${sources})
      get_filename_component(path ${source} ABSOLUTE BASE_DIR ${source_dir})
      file(READ ${path} text)
      if(target STREQUAL "io" OR text MATCHES "YAML::")
        list(APPEND instrumented ${path})
      endif()
    endforeach()
    if(instrumented)
      # Without the precompiled header (cmake/precompiled_headers.cmake):
      # clang refuses one built with another -fsanitize set.
      set_source_files_properties(${instrumented} TARGET_DIRECTORY ${target}
                                  PROPERTIES COMPILE_OPTIONS -fsanitize=fuzzer-no-link
                                             SKIP_PRECOMPILE_HEADERS ON)
    endif()
  endforeach()
endfunction()
