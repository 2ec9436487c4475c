# Ceres's shared library in place of Debian's static one, for builds for
# another instruction set than baseline x86-64 (AXIS_MARCH, CMakeLists.txt).
# Debian's CeresConfig imports libceres.a, compiled for baseline x86-64.
# Linked statically, it and this project's code share one copy of each Eigen
# routine both instantiate (the linker keeps one), and Eigen built for AVX
# aligns and allocates its memory otherwise (32 bytes, its own allocator)
# than Eigen built for baseline x86-64 (16 bytes, malloc): a routine of one
# given memory of the other crashed (SIGSEGV in JacobiSVD::compute and in
# ColPivHouseholderQR). libceres.so keeps its Eigen routines to itself (it
# exports none), and Ceres's API as this project uses it passes no Eigen
# object. Included by the top CMakeLists.txt and by the installed
# servo_axis_idConfig.cmake.

# Points the imported target Ceres::ceres at the libceres.so beside each
# libceres.a it names (IMPORTED_LOCATION and IMPORTED_LOCATION_<CONFIG>);
# `march` names the -march in the error. A fatal error if that file does not
# exist, or if the target names no location at all (a static Ceres would
# then stay linked unseen). Sets nothing in the caller's scope.
function(axis_use_shared_ceres march)
  get_target_property(configs Ceres::ceres IMPORTED_CONFIGURATIONS)
  set(properties IMPORTED_LOCATION)
  if(configs)
    foreach(config ${configs})
      string(TOUPPER "${config}" config)
      list(APPEND properties IMPORTED_LOCATION_${config})
    endforeach()
  endif()
  set(found FALSE)
  foreach(property ${properties})
    get_target_property(location Ceres::ceres ${property})
    if(NOT location)
      continue()
    endif()
    set(found TRUE)
    if(location MATCHES "\\.a$")
      string(REGEX REPLACE "\\.a$" ".so" shared "${location}")
      if(NOT EXISTS "${shared}")
        message(FATAL_ERROR "${shared} not found: a build for -march=${march} needs Ceres's "
                            "shared library beside ${location} (or configure with -DAXIS_MARCH=)")
      endif()
      set_target_properties(Ceres::ceres PROPERTIES ${property} "${shared}")
    endif()
  endforeach()
  if(NOT found)
    message(FATAL_ERROR "Ceres::ceres names no library file: cannot tell whether it is the static "
                        "one a build for -march=${march} must not link (configure with -DAXIS_MARCH=)")
  endif()
endfunction()
