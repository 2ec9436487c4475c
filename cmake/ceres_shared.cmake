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
# libceres.a it names. A fatal error if that file does not exist.
function(axis_use_shared_ceres)
  get_target_property(configs Ceres::ceres IMPORTED_CONFIGURATIONS)
  foreach(config ${configs})
    get_target_property(location Ceres::ceres IMPORTED_LOCATION_${config})
    if(location MATCHES "\\.a$")
      string(REGEX REPLACE "\\.a$" ".so" shared "${location}")
      if(NOT EXISTS "${shared}")
        message(FATAL_ERROR "${shared} not found: a build for -march=${AXIS_MARCH} needs Ceres's "
                            "shared library beside ${location} (or configure with -DAXIS_MARCH=)")
      endif()
      set_target_properties(Ceres::ceres PROPERTIES IMPORTED_LOCATION_${config} "${shared}")
    endif()
  endforeach()
endfunction()
