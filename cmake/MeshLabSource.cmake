# Debian ships no MeshLab headers, so the plugin (and vcglib, which the benchmark uses)
# need the matching source tree at configure time: given as MESHLAB_SOURCE_DIR, or
# fetched once from Debian's source archive (MeshLab 2020.09 on Debian 12).
include_guard(GLOBAL)
if(NOT MESHLAB_SOURCE_DIR OR NOT EXISTS "${MESHLAB_SOURCE_DIR}/src/common/interfaces.h")
  set(_ml_fetch_dest "${CMAKE_BINARY_DIR}/meshlab-source")
  message(STATUS "GeoFilter: fetching the MeshLab source package into ${_ml_fetch_dest}")
  execute_process(
    COMMAND "${PROJECT_SOURCE_DIR}/scripts/fetch-debian-source.sh" meshlab native "${_ml_fetch_dest}"
    OUTPUT_VARIABLE _ml_fetch_out
    RESULT_VARIABLE _ml_fetch_rc)
  # The script's progress goes to stderr; its last stdout line is the tree.
  string(STRIP "${_ml_fetch_out}" _ml_fetch_out)
  string(REGEX REPLACE ".*\n" "" _ml_tree "${_ml_fetch_out}")
  if(NOT _ml_fetch_rc EQUAL 0 OR NOT EXISTS "${_ml_tree}/src/common/interfaces.h")
    message(FATAL_ERROR "GeoFilter: could not obtain the MeshLab 2020.09 sources (exit ${_ml_fetch_rc},"
                        " got '${_ml_tree}'). Pass -DMESHLAB_SOURCE_DIR=<tree> or -DGEOFILTER_BUILD_PLUGIN=OFF.")
  endif()
  # Cached (FORCE: an empty or stale cache entry may already exist) so that a
  # re-configure reuses the tree instead of downloading again.
  set(MESHLAB_SOURCE_DIR "${_ml_tree}" CACHE PATH "MeshLab 2020.09 source tree" FORCE)
endif()

set(GEOFILTER_VCGLIB_DIR "${MESHLAB_SOURCE_DIR}/vcglib" CACHE PATH "vcglib (comes with the MeshLab sources)")
