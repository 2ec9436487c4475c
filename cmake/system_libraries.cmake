# libcsv (Debian libcsv-dev), libmatio (libmatio-dev) and FFTW3
# (libfftw3-dev) ship no CMake package: this file finds them and defines the
# imported targets csv::csv, matio::matio and fftw3::fftw3 (each once).
# Included by the top CMakeLists.txt and by the installed
# servo_axis_idConfig.cmake: the static sim library links the first two and
# the common library the third privately, so their consumers need them at
# link time too.
# Sets SERVO_AXIS_ID_MISSING_LIBRARIES to what was not found (empty if all).
set(SERVO_AXIS_ID_MISSING_LIBRARIES "")
if(NOT TARGET csv::csv)
  find_path(CSV_INCLUDE_DIR csv.h)
  find_library(CSV_LIBRARY csv)
  if(CSV_INCLUDE_DIR AND CSV_LIBRARY)
    add_library(csv::csv UNKNOWN IMPORTED)
    set_target_properties(csv::csv PROPERTIES IMPORTED_LOCATION ${CSV_LIBRARY}
                          INTERFACE_INCLUDE_DIRECTORIES ${CSV_INCLUDE_DIR})
  else()
    list(APPEND SERVO_AXIS_ID_MISSING_LIBRARIES "libcsv (Debian libcsv-dev)")
  endif()
endif()
# axis_pkg_config_target(TARGET MODULE PREFIX WHAT): the imported target
# TARGET for the pkg-config module MODULE (variables PREFIX_*), or WHAT
# appended to SERVO_AXIS_ID_MISSING_LIBRARIES if pkg-config does not find it.
function(axis_pkg_config_target target module prefix what)
  if(TARGET ${target})
    return()
  endif()
  find_package(PkgConfig QUIET)
  if(PKG_CONFIG_FOUND)
    pkg_check_modules(${prefix} QUIET IMPORTED_TARGET GLOBAL ${module})
  endif()
  if(TARGET PkgConfig::${prefix})
    add_library(${target} INTERFACE IMPORTED GLOBAL)
    set_target_properties(${target} PROPERTIES INTERFACE_LINK_LIBRARIES PkgConfig::${prefix})
  else()
    set(SERVO_AXIS_ID_MISSING_LIBRARIES ${SERVO_AXIS_ID_MISSING_LIBRARIES} "${what}" PARENT_SCOPE)
  endif()
endfunction()
axis_pkg_config_target(matio::matio matio MATIO
  "libmatio found by pkg-config as 'matio' (Debian libmatio-dev, pkg-config)")
axis_pkg_config_target(fftw3::fftw3 fftw3 FFTW3
  "FFTW3 found by pkg-config as 'fftw3' (Debian libfftw3-dev, pkg-config)")
