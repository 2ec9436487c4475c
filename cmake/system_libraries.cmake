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
if(NOT TARGET matio::matio)
  find_package(PkgConfig QUIET)
  if(PKG_CONFIG_FOUND)
    pkg_check_modules(MATIO QUIET IMPORTED_TARGET matio)
  endif()
  if(TARGET PkgConfig::MATIO)
    add_library(matio::matio INTERFACE IMPORTED)
    set_target_properties(matio::matio PROPERTIES INTERFACE_LINK_LIBRARIES PkgConfig::MATIO)
  else()
    list(APPEND SERVO_AXIS_ID_MISSING_LIBRARIES
         "libmatio found by pkg-config as 'matio' (Debian libmatio-dev, pkg-config)")
  endif()
endif()
if(NOT TARGET fftw3::fftw3)
  find_package(PkgConfig QUIET)
  if(PKG_CONFIG_FOUND)
    pkg_check_modules(FFTW3 QUIET IMPORTED_TARGET fftw3)
  endif()
  if(TARGET PkgConfig::FFTW3)
    add_library(fftw3::fftw3 INTERFACE IMPORTED)
    set_target_properties(fftw3::fftw3 PROPERTIES INTERFACE_LINK_LIBRARIES PkgConfig::FFTW3)
  else()
    list(APPEND SERVO_AXIS_ID_MISSING_LIBRARIES
         "FFTW3 found by pkg-config as 'fftw3' (Debian libfftw3-dev, pkg-config)")
  endif()
endif()
