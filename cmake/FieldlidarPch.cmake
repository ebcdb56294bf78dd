# Precompiled headers: the headers that nearly every translation unit parses (Eigen, the core types,
# GoogleTest, the standard library) compiled once per build instead of once per file. In the
# Debug+ASan build these headers alone take ~2-3 s of CPU per file.
#
# A precompiled header is usable only by compilations with the same flags (PIC vs PIE, debug info,
# sanitizers) and without macros the header was not built with, so one is built per kind of
# target and shared (REUSE_FROM) by every target of that kind:
#   fieldlidar_pch_library: the module libraries (src/<module>), compiled as an object library
#                           with their flags;
#   fieldlidar_pch_test:    the GoogleTest executables (tests/), an empty executable with theirs;
#   the CLI (apps/fieldlidar) has its own, with CLI11, fmt and nlohmann-json added.
# A compilation that cannot use the header (-Winvalid-pch, an error under FIELDLIDAR_WERROR)
# says so instead of silently parsing everything again.
#
# On by default only where it is safe and pays: builds without a compiler launcher (ccache does
# not cache compilations that use a precompiled header unless told to with
# sloppiness=pch_defines,time_macros, so a developer build with ccache keeps its cache hits), of
# type Debug (the sanitizer stage of scripts/test.sh). Not in optimised builds: GCC 12 at -O2 then
# reports libstdc++'s inlined std::string code (-Warray-bounds in char_traits::copy, through
# tests/support/run_cli.hpp) that it does not report without the precompiled header, which
# FIELDLIDAR_WERROR turns into an error. Not in the fuzz build: its clang flags differ per library
# (libFuzzer instrumentation on core and io only) and it compiles few files.
set(fieldlidar_pch_default OFF)
if(CMAKE_BUILD_TYPE STREQUAL "Debug" AND NOT CMAKE_CXX_COMPILER_LAUNCHER
   AND NOT DEFINED ENV{CMAKE_CXX_COMPILER_LAUNCHER} AND NOT FIELDLIDAR_FUZZ)
  set(fieldlidar_pch_default ON)
endif()
option(FIELDLIDAR_PCH "Precompile the widely included headers (Eigen, core, GoogleTest, std)"
       ${fieldlidar_pch_default})

# Headers of the libraries' precompiled header: the standard library parts most files use, Eigen
# and the core types every module builds on.
set(FIELDLIDAR_PCH_STD_HEADERS
  <algorithm> <array> <cmath> <cstddef> <cstdint> <cstdio> <cstring> <functional> <limits> <map>
  <memory> <numbers> <optional> <span> <sstream> <stdexcept> <string> <utility> <vector>)
set(FIELDLIDAR_PCH_LIBRARY_HEADERS ${FIELDLIDAR_PCH_STD_HEADERS}
  <Eigen/Core> <Eigen/Geometry>
  <fieldlidar/core/error.hpp> <fieldlidar/core/labels.hpp> <fieldlidar/core/point_cloud.hpp>
  <fieldlidar/core/pose.hpp> <fieldlidar/core/sensor_model.hpp>)
# The tests' adds GoogleTest and what tests read and write files with.
set(FIELDLIDAR_PCH_TEST_HEADERS <gtest/gtest.h> ${FIELDLIDAR_PCH_LIBRARY_HEADERS}
  <filesystem> <fstream> <random>)

# fieldlidar_pch_library_host(): the object library whose precompiled header every module reuses.
function(fieldlidar_pch_library_host)
  add_library(fieldlidar_pch_library OBJECT ${PROJECT_SOURCE_DIR}/cmake/pch_host.cpp)
  target_include_directories(fieldlidar_pch_library PRIVATE ${PROJECT_SOURCE_DIR}/include)
  target_link_libraries(fieldlidar_pch_library PRIVATE Eigen3::Eigen)
  fieldlidar_target_options(fieldlidar_pch_library)
  target_precompile_headers(fieldlidar_pch_library PRIVATE ${FIELDLIDAR_PCH_LIBRARY_HEADERS})
endfunction()

# fieldlidar_pch_test_host(): the executable whose precompiled header every test reuses; it has
# the flags and definitions fieldlidar_add_test gives a test.
function(fieldlidar_pch_test_host)
  add_executable(fieldlidar_pch_test ${PROJECT_SOURCE_DIR}/cmake/pch_host_main.cpp)
  target_include_directories(fieldlidar_pch_test PRIVATE ${PROJECT_SOURCE_DIR}/include)
  target_link_libraries(fieldlidar_pch_test PRIVATE Eigen3::Eigen GTest::gtest)
  fieldlidar_target_options(fieldlidar_pch_test)
  target_compile_definitions(fieldlidar_pch_test PRIVATE
    FIELDLIDAR_TEST_DATA_DIR="${FIELDLIDAR_DATA_DIR}")
  target_precompile_headers(fieldlidar_pch_test PRIVATE ${FIELDLIDAR_PCH_TEST_HEADERS})
endfunction()
