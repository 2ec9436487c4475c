# Precompiled third-party headers (CMake target_precompile_headers): Ceres,
# Eigen, nlohmann/json, yaml-cpp and the standard library are parsed once per
# target kind instead of once per source file.
# Two precompiled headers, each built once and reused by every target of its
# kind (REUSE_FROM needs the same compiler flags): one compiled as the
# libraries are (-fPIC where the Python module needs it), one as the test
# executables are (GoogleTest, the tests' PROJECT_SOURCE_DIR/BINARY_DIR).
# The apps, benchmarks, the io library and the Python module compile
# without.
# The project's own headers are never precompiled, so a file that forgets an
# #include of the project's still fails. One that forgets a third-party or
# standard #include (say <map>) compiles here and fails only without a
# precompiled header: in the io library, in the sanitizer tree's sources
# that read YAML (cmake/layer.cmake axis_fuzz_coverage), or with
# -DAXIS_PCH=OFF.
option(AXIS_PCH "precompile the third-party headers (faster builds)" ON)

set(AXIS_PCH_HEADERS
    <algorithm> <cmath> <functional> <limits> <map> <memory> <optional> <set>
    <sstream> <stdexcept> <string> <utility> <vector>
    <Eigen/Core> <Eigen/Dense> <ceres/ceres.h> <nlohmann/json.hpp> <yaml-cpp/yaml.h>)

# The libraries whose headers are precompiled. A precompiled header is used
# only where the compiler sees the same macros as when it was built (GCC
# -Winvalid-pch; the glog, gflags and Boost targets Ceres and Boost::headers
# bring define GLOG_*, GFLAGS_* and BOOST_ALL_NO_LIB), so
# every target that uses one links these too (privately: they add usage
# requirements and no code a final link does not already have).
set(AXIS_PCH_LIBRARIES Ceres::ceres Eigen3::Eigen yaml-cpp nlohmann_json::nlohmann_json
    Boost::headers)

# axis_pch_targets(): defines the two targets whose precompiled headers the
# others reuse. Call once, after the dependencies are found.
function(axis_pch_targets)
  if(NOT AXIS_PCH)
    return()
  endif()
  find_package(nlohmann_json 3 REQUIRED)
  find_package(Boost REQUIRED)
  # The targets that build them: a library's object and an executable's
  # (position-independent code and executables differ in -fPIC/-fPIE, which
  # a precompiled header must match).
  set(stub ${CMAKE_BINARY_DIR}/axis_pch_stub.cc)
  set(main ${CMAKE_BINARY_DIR}/axis_pch_main.cc)
  if(NOT EXISTS ${main} OR NOT EXISTS ${stub})
    file(WRITE ${stub} "// The translation unit that builds a precompiled header.\n")
    file(WRITE ${main}
         "// The executable that builds a precompiled header.\nint main() { return 0; }\n")
  endif()
  add_library(axis_pch_library OBJECT ${stub})
  target_link_libraries(axis_pch_library PRIVATE ${AXIS_PCH_LIBRARIES})
  target_precompile_headers(axis_pch_library PRIVATE ${AXIS_PCH_HEADERS})
  add_executable(axis_pch_test ${main})
  set_target_properties(axis_pch_test PROPERTIES
                        RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/CMakeFiles/axis_pch_test)
  target_link_libraries(axis_pch_test PRIVATE ${AXIS_PCH_LIBRARIES} GTest::gtest)
  target_compile_definitions(axis_pch_test PRIVATE
    PROJECT_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
    BINARY_DIR="${CMAKE_BINARY_DIR}/bin")
  axis_test_optimization(axis_pch_test)  # the tests' level, which their header must match
  target_precompile_headers(axis_pch_test PRIVATE ${AXIS_PCH_HEADERS} <gtest/gtest.h>)
endfunction()

# axis_test_optimization(TARGET): TARGET's sources at AXIS_TEST_OPTIMIZATION
# (CMakeLists.txt) in a Release build, after the build type's flags so that
# it is the level in force.
function(axis_test_optimization target)
  if(AXIS_TEST_OPTIMIZATION)
    target_compile_options(${target} PRIVATE "$<$<CONFIG:Release>:${AXIS_TEST_OPTIMIZATION}>")
  endif()
endfunction()

# axis_use_pch(TARGET KIND): TARGET's sources include the precompiled header
# of KIND (library or test) first.
function(axis_use_pch target kind)
  if(AXIS_PCH)
    target_link_libraries(${target} PRIVATE ${AXIS_PCH_LIBRARIES})
    target_precompile_headers(${target} REUSE_FROM axis_pch_${kind})
  endif()
endfunction()
