# Unity builds for the sanitizer stage of scripts/test.sh: the sources of a module library (and of
# the CLI) compiled a batch at a time, one translation unit per batch, so that the headers they
# share are parsed, and the inline functions and templates they share are instantiated, optimised
# and given debug information, once per batch instead of once per file. At -O1 with the
# sanitizers the code generation of those shared instantiations is most of a file's compile time.
#
# Off by default: a developer build (ccache, one file edited) rebuilds a whole batch for a one-file
# change. The Release build of scripts/test.sh stays one file at a time, so it still checks that
# every file includes what it uses.
#
# Names local to a file (anonymous namespace, static) that another file of the same module also
# defines clash inside a batch; such a file is listed below and compiled on its own. A new clash
# shows as a "redefinition of" error in the sanitizer stage only: rename, or add the file here.
option(FIELDLIDAR_UNITY "Unity build of the module libraries and the CLI (sanitizer stage)" OFF)
set(FIELDLIDAR_UNITY_BATCH_SIZE 8 CACHE STRING "Source files per unity translation unit")

# Paths relative to the source tree (none today: shared helpers live in a module's internal
# header, file-local ones carry the file's name, e.g. ply_fail / las_fail).
set(FIELDLIDAR_UNITY_SEPARATE)

# fieldlidar_unity(TARGET): a unity build of TARGET when FIELDLIDAR_UNITY is on. Called from the
# directory that defines TARGET (source file properties are per directory).
function(fieldlidar_unity target)
  if(NOT FIELDLIDAR_UNITY)
    return()
  endif()
  set_target_properties(${target} PROPERTIES UNITY_BUILD ON
    UNITY_BUILD_BATCH_SIZE ${FIELDLIDAR_UNITY_BATCH_SIZE})
  get_target_property(sources ${target} SOURCES)
  foreach(source IN LISTS sources)
    get_filename_component(path "${source}" ABSOLUTE)
    file(RELATIVE_PATH relative "${PROJECT_SOURCE_DIR}" "${path}")
    if(relative IN_LIST FIELDLIDAR_UNITY_SEPARATE)
      set_source_files_properties(${source} PROPERTIES SKIP_UNITY_BUILD_INCLUSION ON)
    endif()
  endforeach()
endfunction()
