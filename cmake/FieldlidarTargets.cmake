# Helpers shared by every module's CMakeLists.txt.

# Warnings and sanitizers for one of our own targets.
function(fieldlidar_target_options target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wno-psabi)
  if(FIELDLIDAR_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
  if(FIELDLIDAR_SANITIZE)
    target_compile_options(${target} PRIVATE -fsanitize=address,undefined -fno-omit-frame-pointer
                                             -fno-sanitize-recover=undefined)
    target_link_options(${target} PRIVATE -fsanitize=address,undefined)
  endif()
endfunction()

# fieldlidar_add_module(NAME SOURCES ... [PUBLIC_DEPS ...] [PRIVATE_DEPS ...])
# Defines library fieldlidar_<NAME> with alias fieldlidar::<NAME>, public headers from include/,
# and installs it into the fieldlidarTargets export set.
function(fieldlidar_add_module name)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  add_library(fieldlidar_${name} ${ARG_SOURCES})
  add_library(fieldlidar::${name} ALIAS fieldlidar_${name})
  target_include_directories(fieldlidar_${name} PUBLIC
    $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(fieldlidar_${name} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
  set_target_properties(fieldlidar_${name} PROPERTIES EXPORT_NAME ${name}
    OUTPUT_NAME fieldlidar_${name} VERSION ${PROJECT_VERSION} SOVERSION ${PROJECT_VERSION_MAJOR}
    INSTALL_RPATH "$ORIGIN")
  fieldlidar_target_options(fieldlidar_${name})
  if(FIELDLIDAR_PCH)
    target_precompile_headers(fieldlidar_${name} REUSE_FROM fieldlidar_pch_library)
  endif()
  fieldlidar_unity(fieldlidar_${name})
  install(TARGETS fieldlidar_${name} EXPORT fieldlidarTargets
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endfunction()

# fieldlidar_add_test(NAME SOURCES ... LIBS ... [LABELS ...] [SLOW Suite.Test ...] [COST N])
# A GoogleTest executable whose tests are registered with CTest. Tests that read real data get
# FIELDLIDAR_DATA_DIR as an environment variable and skip with a message when it is absent.
# SLOW names single tests of the executable (gtest filter patterns) that get the "slow" label
# instead: whole-recording runs that take minutes under the sanitizers and run in Release only.
# With FIELDLIDAR_BUILD_SLOW_TESTS=OFF an executable labelled "slow" as a whole is left out of the
# default build and registers no tests (the sanitizer stage of scripts/test.sh, which does not
# run them). COST N (about the seconds one of its tests takes in Release) goes to every test of
# the executable.
function(fieldlidar_add_test name)
  cmake_parse_arguments(ARG "" "COST" "SOURCES;LIBS;LABELS;SLOW" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_LIBS} fieldlidar_test_support GTest::gtest_main)
  fieldlidar_target_options(${name})
  if(FIELDLIDAR_PCH)
    target_precompile_headers(${name} REUSE_FROM fieldlidar_pch_test)
  endif()
  # The data folder is compiled in as the default (FIELDLIDAR_DATA_DIR in the environment still
  # overrides it), so a test finds the data however it is started.
  target_compile_definitions(${name} PRIVATE
    FIELDLIDAR_TEST_DATA_DIR="${FIELDLIDAR_DATA_DIR}")
  # One label per test executable ("unit" unless the caller names one such as "slow" or "cli"):
  # gtest_discover_tests passes PROPERTIES on as a flat list, which cannot carry a list value.
  set(label unit)
  if(ARG_LABELS)
    list(GET ARG_LABELS 0 label)
  endif()
  if(label STREQUAL "slow" AND NOT FIELDLIDAR_BUILD_SLOW_TESTS)
    set_target_properties(${name} PROPERTIES EXCLUDE_FROM_ALL TRUE)
    return()
  endif()
  set(filter "")
  if(ARG_SLOW)
    list(JOIN ARG_SLOW ":" slow_tests)
    gtest_discover_tests(${name} TEST_FILTER "${slow_tests}"
      PROPERTIES ENVIRONMENT "FIELDLIDAR_DATA_DIR=${FIELDLIDAR_DATA_DIR}" LABELS slow
      DISCOVERY_TIMEOUT 60)
    set(filter TEST_FILTER "-${slow_tests}")
  endif()
  # COST: ctest starts costlier tests first when it has no timings of an earlier run (a clean
  # checkout), so that minutes-long tests do not start last and run alone at the end.
  set(cost "")
  if(ARG_COST)
    set(cost COST ${ARG_COST})
  endif()
  gtest_discover_tests(${name} ${filter}
    PROPERTIES ENVIRONMENT "FIELDLIDAR_DATA_DIR=${FIELDLIDAR_DATA_DIR}" LABELS "${label}" ${cost}
    DISCOVERY_TIMEOUT 60)
endfunction()

# fieldlidar_assert_not_linked(TARGET FORBIDDEN): stops the configuration when TARGET links
# FORBIDDEN, directly or through any of its dependencies (DESIGN.md: a pipeline never depends on
# sim/). Generator expressions such as $<BUILD_INTERFACE:x> are looked through.
function(fieldlidar_assert_not_linked target forbidden)
  set(queue ${target})
  set(seen "")
  while(queue)
    list(POP_FRONT queue current)
    if(current IN_LIST seen OR NOT TARGET ${current})
      continue()
    endif()
    list(APPEND seen ${current})
    get_target_property(aliased ${current} ALIASED_TARGET)
    if(aliased)
      list(APPEND queue ${aliased})
      continue()
    endif()
    if(current STREQUAL forbidden)
      message(FATAL_ERROR "${target} links ${forbidden}, directly or through its dependencies; "
                          "it must not (DESIGN.md: one direction of dependency)")
    endif()
    get_target_property(type ${current} TYPE)
    set(libs "")
    if(NOT type STREQUAL "INTERFACE_LIBRARY")
      get_target_property(direct ${current} LINK_LIBRARIES)
      if(direct)
        list(APPEND libs ${direct})
      endif()
    endif()
    get_target_property(interface ${current} INTERFACE_LINK_LIBRARIES)
    if(interface)
      list(APPEND libs ${interface})
    endif()
    foreach(lib IN LISTS libs)
      string(REGEX REPLACE "^\\$<[A-Z_]+:(.*)>$" "\\1" lib "${lib}")
      list(APPEND queue ${lib})
    endforeach()
  endwhile()
endfunction()
