# MeshLab2022.cmake -- build plugins for the FilterPlugin API (MeshLab 2022.02 and later:
# 2023.12, 2025.07, and the MeshLab inside pymeshlab) against an EXISTING build of
# libmeshlab-common: headers from the source tree, the library from the build.
#
# Input : MESHLAB_SOURCE_DIR          top of the MeshLab source tree (holds src/ and ML_VERSION)
#         MESHLAB_BUILD_DIR           folder where that tree's meshlab-common was built
#         MESHLAB2022_COMMON_LIBRARY  optional: libmeshlab-common.so given directly (e.g. the
#                                     one inside a pymeshlab wheel); found in the build otherwise
#         GEOFILTER_MESHLAB_SCALAR    optional: float | double; read from the build otherwise
#         GEOFILTER_MESHLAB_VERSION   optional: the MESHLAB_VERSION string the library was
#                                     built with (e.g. 2025.07d); read from the build otherwise
# Output: meshlab_common_2022         IMPORTED target: headers, defines, Qt, GLEW/GL, the lib
#         MESHLAB_2022_COMMON_LIBRARY the library linked
#         MESHLAB_2022_VERSION        the MESHLAB_VERSION string used
#         MESHLAB_2022_SCALAR         float or double
#         MESHLAB_2022_PLUGIN_DIR     the build's plugin folder (distrib/plugins), if found
#         MESHLAB_2022_DISTRIB_DIR    the build's distrib folder (executable, lib), if found
#
# Why the defines matter: MESHLAB_SCALAR is CMeshO's scalar type, so it sets the layout of
# every mesh class; MESHLAB_VERSION is compiled into the plugin (meshlab::meshlabVersion()
# is inline on purpose) and PluginManager::checkPlugin refuses a plugin whose version or
# precision differs from the running MeshLab's.

include_guard(GLOBAL)

if(NOT MESHLAB_SOURCE_DIR OR NOT EXISTS "${MESHLAB_SOURCE_DIR}/src/common/plugins/interfaces/filter_plugin.h")
  message(FATAL_ERROR "MeshLab2022: set MESHLAB_SOURCE_DIR to a MeshLab 2022.02+ source tree "
                      "(the folder holding src/common/plugins/interfaces/filter_plugin.h)")
endif()

set(MESHLAB_BUILD_DIR "" CACHE PATH "Folder where MESHLAB_SOURCE_DIR's meshlab-common was built")
set(MESHLAB2022_COMMON_LIBRARY "" CACHE FILEPATH
    "libmeshlab-common.so of that MeshLab (default: found in MESHLAB_BUILD_DIR)")
set(GEOFILTER_MESHLAB_SCALAR "" CACHE STRING "MeshLab's scalar type: float, double, or empty to read it from the build")
set_property(CACHE GEOFILTER_MESHLAB_SCALAR PROPERTY STRINGS "" float double)
set(GEOFILTER_MESHLAB_VERSION "" CACHE STRING "MESHLAB_VERSION of that MeshLab, or empty to read it from the build")

# --- What the build was configured with -----------------------------------------------------
# First choice: the exact compile definitions of meshlab-common (Makefile or Ninja builds,
# MeshLab built on its own or as a subproject, as pymeshlab does).
set(_ml_flags_scalar "")
set(_ml_flags_version "")
set(_ml_flags_nightly OFF)
if(MESHLAB_BUILD_DIR)
  if(NOT IS_DIRECTORY "${MESHLAB_BUILD_DIR}")
    message(FATAL_ERROR "MeshLab2022: MESHLAB_BUILD_DIR=${MESHLAB_BUILD_DIR} is not a folder")
  endif()
  file(GLOB_RECURSE _ml_flag_files "${MESHLAB_BUILD_DIR}/*/meshlab-common.dir/flags.make")
  if(EXISTS "${MESHLAB_BUILD_DIR}/build.ninja")
    list(APPEND _ml_flag_files "${MESHLAB_BUILD_DIR}/build.ninja")
  endif()
  foreach(_f IN LISTS _ml_flag_files)
    file(STRINGS "${_f}" _defs REGEX "MESHLAB_SCALAR=")
    foreach(_d IN LISTS _defs)
      if(_d MATCHES "-DMESHLAB_SCALAR=([a-z]+)")
        set(_ml_flags_scalar "${CMAKE_MATCH_1}")
      endif()
      if(_d MATCHES "-DMESHLAB_VERSION=([^ ]+)")
        set(_ml_flags_version "${CMAKE_MATCH_1}")
      endif()
      if(_d MATCHES "-DMESHLAB_IS_NIGHTLY( |$)")
        set(_ml_flags_nightly ON)
      endif()
    endforeach()
    if(_ml_flags_scalar)
      break()
    endif()
  endforeach()
  # Second choice: the option in its cache (named BUILD_WITH_DOUBLE_SCALAR in 2022.02,
  # MESHLAB_BUILD_WITH_DOUBLE_SCALAR from 2023.12).
  set(_ml_cache_double "")
  if(EXISTS "${MESHLAB_BUILD_DIR}/CMakeCache.txt")
    file(STRINGS "${MESHLAB_BUILD_DIR}/CMakeCache.txt" _cache REGEX
         "^(MESHLAB_)?BUILD_WITH_DOUBLE_SCALAR:BOOL=|^MeshLab_SOURCE_DIR:STATIC=")
    foreach(_l IN LISTS _cache)
      if(_l MATCHES "DOUBLE_SCALAR:BOOL=(.*)$")
        set(_ml_cache_double "${CMAKE_MATCH_1}")
      elseif(_l MATCHES "^MeshLab_SOURCE_DIR:STATIC=(.*)$")
        # The project is src/ in 2022.02 and the top folder from 2023.12 on.
        get_filename_component(_built_from "${CMAKE_MATCH_1}" REALPATH)
        get_filename_component(_given "${MESHLAB_SOURCE_DIR}" REALPATH)
        if(NOT _built_from STREQUAL _given AND NOT _built_from STREQUAL "${_given}/src")
          message(WARNING "MeshLab2022: ${MESHLAB_BUILD_DIR} was built from ${_built_from}, "
                          "not from MESHLAB_SOURCE_DIR=${MESHLAB_SOURCE_DIR}: the headers must match the library")
        endif()
      endif()
    endforeach()
  endif()
endif()

if(GEOFILTER_MESHLAB_SCALAR)
  set(MESHLAB_2022_SCALAR "${GEOFILTER_MESHLAB_SCALAR}")
elseif(_ml_flags_scalar)
  set(MESHLAB_2022_SCALAR "${_ml_flags_scalar}")
elseif(NOT _ml_cache_double STREQUAL "")
  if(_ml_cache_double)
    set(MESHLAB_2022_SCALAR double)
  else()
    set(MESHLAB_2022_SCALAR float)
  endif()
else()
  set(MESHLAB_2022_SCALAR float)
  message(WARNING "MeshLab2022: could not read MeshLab's scalar type from MESHLAB_BUILD_DIR; assuming float. "
                  "Give -DGEOFILTER_MESHLAB_SCALAR=double for a double-precision MeshLab (pymeshlab 2025.7).")
endif()
if(NOT MESHLAB_2022_SCALAR MATCHES "^(float|double)$")
  message(FATAL_ERROR "MeshLab2022: GEOFILTER_MESHLAB_SCALAR must be float or double (got '${MESHLAB_2022_SCALAR}')")
endif()
if(_ml_flags_scalar AND NOT _ml_flags_scalar STREQUAL MESHLAB_2022_SCALAR)
  message(WARNING "MeshLab2022: GEOFILTER_MESHLAB_SCALAR=${MESHLAB_2022_SCALAR} but ${MESHLAB_BUILD_DIR} "
                  "was built with ${_ml_flags_scalar}: MeshLab will refuse the plugin")
endif()

if(GEOFILTER_MESHLAB_VERSION)
  set(MESHLAB_2022_VERSION "${GEOFILTER_MESHLAB_VERSION}")
elseif(_ml_flags_version)
  set(MESHLAB_2022_VERSION "${_ml_flags_version}")
else()
  # What MeshLab's own CMake does: ML_VERSION, with a "d" for double precision.
  file(STRINGS "${MESHLAB_SOURCE_DIR}/ML_VERSION" MESHLAB_2022_VERSION LIMIT_COUNT 1)
  string(STRIP "${MESHLAB_2022_VERSION}" MESHLAB_2022_VERSION)
  if(MESHLAB_2022_SCALAR STREQUAL "double")
    string(APPEND MESHLAB_2022_VERSION "d")
  endif()
endif()

# --- The library ------------------------------------------------------------------------
# Not cached when found: a later -DMESHLAB_BUILD_DIR=<another build> must find that one.
set(MESHLAB_2022_COMMON_LIBRARY "${MESHLAB2022_COMMON_LIBRARY}")
if(NOT MESHLAB_2022_COMMON_LIBRARY)
  if(NOT MESHLAB_BUILD_DIR)
    message(FATAL_ERROR "MeshLab2022: give -DMESHLAB_BUILD_DIR=<folder where ${MESHLAB_SOURCE_DIR} was built> "
                        "(scripts/build-meshlab-source.sh makes one), or -DMESHLAB2022_COMMON_LIBRARY=<libmeshlab-common.so>")
  endif()
  # distrib/ is where MeshLab's own build puts it; lib*/ covers an install prefix.
  foreach(_d distrib . src/distrib lib/meshlab lib lib64/meshlab)
    if(EXISTS "${MESHLAB_BUILD_DIR}/${_d}/libmeshlab-common.so")
      get_filename_component(MESHLAB_2022_COMMON_LIBRARY "${MESHLAB_BUILD_DIR}/${_d}/libmeshlab-common.so" ABSOLUTE)
      break()
    endif()
  endforeach()
  if(NOT MESHLAB_2022_COMMON_LIBRARY)
    message(FATAL_ERROR "MeshLab2022: no libmeshlab-common.so under ${MESHLAB_BUILD_DIR} (build its "
                        "meshlab-common target, or give -DMESHLAB2022_COMMON_LIBRARY)")
  endif()
endif()
if(NOT EXISTS "${MESHLAB_2022_COMMON_LIBRARY}")
  message(FATAL_ERROR "MeshLab2022: ${MESHLAB_2022_COMMON_LIBRARY} does not exist")
endif()
get_filename_component(MESHLAB_2022_DISTRIB_DIR "${MESHLAB_2022_COMMON_LIBRARY}" DIRECTORY)
set(MESHLAB_2022_PLUGIN_DIR "")
if(IS_DIRECTORY "${MESHLAB_2022_DISTRIB_DIR}/plugins")
  set(MESHLAB_2022_PLUGIN_DIR "${MESHLAB_2022_DISTRIB_DIR}/plugins")
endif()

# --- Headers and what they pull in --------------------------------------------------------
set(_ml_src "${MESHLAB_SOURCE_DIR}/src")
set(MESHLAB_2022_VCGDIR "${_ml_src}/vcglib")
if(NOT EXISTS "${MESHLAB_2022_VCGDIR}/vcg/complex/complex.h")
  message(FATAL_ERROR "MeshLab2022: vcglib not found at ${MESHLAB_2022_VCGDIR} (a git checkout needs "
                      "`git submodule update --init`)")
endif()

# meshlab-common's public link interface: Qt Core/OpenGL/Widgets/Xml/Network; the headers
# include <GL/glew.h> (mesh_model.h) and vcglib includes <Eigen/...>.
find_package(Qt5 5.15 REQUIRED COMPONENTS Core Gui Widgets OpenGL Xml Network)
set(OpenGL_GL_PREFERENCE GLVND)
find_package(OpenGL REQUIRED)
find_package(GLEW QUIET)
find_package(Eigen3 3.3 REQUIRED NO_MODULE)

add_library(meshlab_common_2022 SHARED IMPORTED GLOBAL)
set_target_properties(meshlab_common_2022 PROPERTIES IMPORTED_LOCATION "${MESHLAB_2022_COMMON_LIBRARY}")
# IMPORTED => -isystem: vcglib's and MeshLab's warnings stay out of our build.
target_include_directories(meshlab_common_2022 INTERFACE "${_ml_src}" "${MESHLAB_2022_VCGDIR}")
if(TARGET GLEW::GLEW)
  target_link_libraries(meshlab_common_2022 INTERFACE GLEW::GLEW)
elseif(EXISTS "${_ml_src}/external/glew-2.1.0/include/GL/glew.h")
  # A MeshLab built with its bundled GLEW (Windows, macOS, pymeshlab wheels): only the
  # header is needed, the plugin calls no GL function itself.
  target_include_directories(meshlab_common_2022 INTERFACE "${_ml_src}/external/glew-2.1.0/include")
else()
  message(FATAL_ERROR "MeshLab2022: GLEW headers not found (apt install libglew-dev)")
endif()
set(_ml_defs MESHLAB_SCALAR=${MESHLAB_2022_SCALAR} MESHLAB_VERSION=${MESHLAB_2022_VERSION})
if(_ml_flags_nightly)
  list(APPEND _ml_defs MESHLAB_IS_NIGHTLY)
endif()
target_compile_definitions(meshlab_common_2022 INTERFACE ${_ml_defs})
target_compile_features(meshlab_common_2022 INTERFACE cxx_std_14)
target_link_libraries(meshlab_common_2022 INTERFACE
  Eigen3::Eigen Qt5::Core Qt5::Gui Qt5::Widgets Qt5::OpenGL Qt5::Xml Qt5::Network OpenGL::GL)

# Outputs as INTERNAL cache entries (recomputed every configure): tests/ needs them too and
# is not below the directory that includes this file.
foreach(_v MESHLAB_2022_COMMON_LIBRARY MESHLAB_2022_VERSION MESHLAB_2022_SCALAR MESHLAB_2022_PLUGIN_DIR
           MESHLAB_2022_DISTRIB_DIR)
  set(${_v} "${${_v}}" CACHE INTERNAL "computed by cmake/MeshLab2022.cmake")
endforeach()

message(STATUS "MeshLab2022: MeshLab ${MESHLAB_2022_VERSION} (${MESHLAB_2022_SCALAR}) from ${MESHLAB_SOURCE_DIR}, "
               "library ${MESHLAB_2022_COMMON_LIBRARY}")
