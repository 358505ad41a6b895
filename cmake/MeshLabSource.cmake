# Debian ships no MeshLab headers, so the plugin (and vcglib, which the benchmark uses)
# need the matching source tree at configure time: given as MESHLAB_SOURCE_DIR, or
# fetched once from Debian's source archive (MeshLab 2020.09 on Debian 12).
#
# Output: GEOFILTER_MESHLAB_API  2020 (MeshFilterInterface, src/common/interfaces.h) or
#                                2022 (FilterPlugin, src/common/plugins/interfaces/filter_plugin.h,
#                                MeshLab 2022.02 and later): which adapter to build
#         GEOFILTER_VCGLIB_DIR   vcglib of that tree
include_guard(GLOBAL)

function(_geofilter_meshlab_api dir out)
  if(EXISTS "${dir}/src/common/plugins/interfaces/filter_plugin.h")
    set(${out} 2022 PARENT_SCOPE)
  elseif(EXISTS "${dir}/src/common/interfaces.h")
    set(${out} 2020 PARENT_SCOPE)
  else()
    set(${out} "" PARENT_SCOPE)
  endif()
endfunction()

set(_ml_api "")
if(MESHLAB_SOURCE_DIR)
  _geofilter_meshlab_api("${MESHLAB_SOURCE_DIR}" _ml_api)
  if(NOT _ml_api AND IS_DIRECTORY "${MESHLAB_SOURCE_DIR}")
    message(FATAL_ERROR "GeoFilter: MESHLAB_SOURCE_DIR=${MESHLAB_SOURCE_DIR} is not a MeshLab source tree "
                        "(it should hold src/common/interfaces.h (2020.09) or "
                        "src/common/plugins/interfaces/filter_plugin.h (2022.02 and later))")
  endif()
endif()

if(NOT _ml_api)
  # Nothing given, or a cached tree that has since been deleted: fetch Debian 12's 2020.09.
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
  set(MESHLAB_SOURCE_DIR "${_ml_tree}" CACHE PATH "MeshLab source tree (2020.09, or 2022.02 and later)" FORCE)
  set(_ml_api 2020)
endif()
set(GEOFILTER_MESHLAB_API "${_ml_api}")
message(STATUS "GeoFilter: MeshLab ${GEOFILTER_MESHLAB_API} API (${MESHLAB_SOURCE_DIR})")

# 2020.09 keeps vcglib next to src/, 2022.02+ inside it (a git submodule).
if(GEOFILTER_MESHLAB_API STREQUAL "2022")
  set(_ml_vcg "${MESHLAB_SOURCE_DIR}/src/vcglib")
else()
  set(_ml_vcg "${MESHLAB_SOURCE_DIR}/vcglib")
endif()
if(NOT EXISTS "${GEOFILTER_VCGLIB_DIR}/vcg/complex/complex.h")
  set(GEOFILTER_VCGLIB_DIR "${_ml_vcg}" CACHE PATH "vcglib (comes with the MeshLab sources)" FORCE)
endif()
