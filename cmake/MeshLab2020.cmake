# MeshLab2020.cmake -- build MeshLab 2020.09 plugins against an *installed*
# MeshLab (Debian 12 package `meshlab`), which ships no headers.
#
# Input : MESHLAB_SOURCE_DIR  top of the matching 2020.09 source tree (holds src/
#                             and, in the Debian dfsg tarball, vcglib/)
#         VCGDIR              optional, defaults to ${MESHLAB_SOURCE_DIR}/vcglib
#         MESHLAB_LIB_DIR     optional, dir holding libmeshlab-common.so
# Output: meshlab_common_2020            IMPORTED target: link it and you have
#                                        headers, defines, Qt, GLEW/GL, the lib
#         MESHLAB_PLUGIN_INSTALL_DIR     absolute plugin dir of that MeshLab
#         MESHLAB_PLUGIN_INSTALL_RELDIR  same, relative to an install prefix
#                                        (for a private prefix: bin/ + this)
#
# Usage:  set(CMAKE_AUTOMOC ON)   # plugins are QObjects with Q_PLUGIN_METADATA
#         include(MeshLab2020)
#         add_library(filter_x MODULE x.cpp x.h)
#         target_link_libraries(filter_x PRIVATE meshlab_common_2020)

include_guard(GLOBAL)

if(NOT MESHLAB_SOURCE_DIR OR NOT EXISTS "${MESHLAB_SOURCE_DIR}/src/common/interfaces.h")
  message(FATAL_ERROR "MeshLab2020: set MESHLAB_SOURCE_DIR to the MeshLab 2020.09 "
                      "source tree (the folder holding src/common/interfaces.h)")
endif()
set(VCGDIR "${MESHLAB_SOURCE_DIR}/vcglib" CACHE PATH "vcglib matching MeshLab 2020.09")
if(NOT EXISTS "${VCGDIR}/vcg/complex/complex.h")
  message(FATAL_ERROR "MeshLab2020: vcglib not found at VCGDIR=${VCGDIR}")
endif()

# The plugin ABI is the layout of classes in these headers: a header tree of
# another release would compile fine and crash at load/run time, so check it.
if(EXISTS "${MESHLAB_SOURCE_DIR}/ML_VERSION")
  file(STRINGS "${MESHLAB_SOURCE_DIR}/ML_VERSION" _ml_ver LIMIT_COUNT 1)
  if(NOT _ml_ver STREQUAL "2020.09")
    message(WARNING "MeshLab2020: source tree is version '${_ml_ver}', not 2020.09")
  endif()
endif()

# Headers pull in QApplication/QAction/QMessageBox (Widgets), QGLContext and
# QGLWidget (OpenGL), QDomElement (Xml).  XmlPatterns is linked by MeshLab's own
# build but no installed header uses it, so it is not needed here.
find_package(Qt5 5.9 REQUIRED COMPONENTS Core Gui Widgets OpenGL Xml)
# meshmodel.h / ml_shared_data_context.h include <GL/glew.h> first thing, and
# vcglib's wrap/gl code referenced by them calls GL: Debian's MeshLab uses the
# system GLEW (not the bundled static one, so no GLEW_STATIC define).
set(OpenGL_GL_PREFERENCE GLVND)
find_package(OpenGL REQUIRED)
find_package(GLEW REQUIRED)
# vcglib includes <Eigen/...>.  The dfsg tarball drops vcglib/eigenlib, and the
# Debian build used system Eigen (-DALLOW_BUNDLED_EIGEN=OFF): use the same.
find_package(Eigen3 3.3 QUIET NO_MODULE)
if(NOT TARGET Eigen3::Eigen AND NOT EXISTS "${VCGDIR}/eigenlib/Eigen/Core")
  message(FATAL_ERROR "MeshLab2020: need Eigen3 (apt install libeigen3-dev)")
endif()

set(MESHLAB_LIB_DIR "/usr/lib/${CMAKE_LIBRARY_ARCHITECTURE}/meshlab"
    CACHE PATH "Directory of the installed libmeshlab-common.so")
# Unversioned private lib outside the linker path: search only where told.
find_library(MESHLAB_COMMON_LIBRARY NAMES meshlab-common
             HINTS "${MESHLAB_LIB_DIR}" NO_DEFAULT_PATH)
if(NOT MESHLAB_COMMON_LIBRARY)
  message(FATAL_ERROR "MeshLab2020: libmeshlab-common.so not found in ${MESHLAB_LIB_DIR} "
                      "(apt install meshlab, or set MESHLAB_LIB_DIR)")
endif()
get_filename_component(_ml_libdir "${MESHLAB_COMMON_LIBRARY}" DIRECTORY)

add_library(meshlab_common_2020 SHARED IMPORTED GLOBAL)
set_target_properties(meshlab_common_2020 PROPERTIES
  IMPORTED_LOCATION "${MESHLAB_COMMON_LIBRARY}")   # SONAME libmeshlab-common.so
# src/ so that "#include <common/interfaces.h>" works like in MeshLab's tree;
# vcglib for <vcg/...> and <wrap/...>.  IMPORTED => treated as -isystem, which
# keeps vcglib's many warnings out of our build.
target_include_directories(meshlab_common_2020 INTERFACE
  "${MESHLAB_SOURCE_DIR}/src" "${VCGDIR}")
if(TARGET Eigen3::Eigen)
  target_link_libraries(meshlab_common_2020 INTERFACE Eigen3::Eigen)
else()
  target_include_directories(meshlab_common_2020 INTERFACE "${VCGDIR}/eigenlib")
endif()
# MESHLAB_SCALAR picks CMeshO's scalar type (float vs double): it changes the
# layout of every mesh class, so it must match the installed lib (float).
# Nothing else in MeshLab's defines reaches the headers on Linux (NOMINMAX and
# GLEW_STATIC are Windows/bundled-GLEW only; MESHLAB_VERSION is private to lib).
target_compile_definitions(meshlab_common_2020 INTERFACE MESHLAB_SCALAR=float)
# Debian compiled MeshLab as gnu++14; the headers also build as C++17.
target_compile_features(meshlab_common_2020 INTERFACE cxx_std_14)
target_link_libraries(meshlab_common_2020 INTERFACE
  Qt5::Core Qt5::Gui Qt5::Widgets Qt5::OpenGL Qt5::Xml GLEW::GLEW OpenGL::GL)

# Where the installed MeshLab looks for plugins: <bin>/../<libdir>/meshlab/plugins
# (Debian patch 22_find-plugins).  The RELDIR form is for a private prefix that
# holds a copy of meshlab/meshlabserver in <prefix>/bin.
set(MESHLAB_PLUGIN_INSTALL_DIR "${_ml_libdir}/plugins"
    CACHE PATH "Plugin directory of the installed MeshLab")
set(MESHLAB_PLUGIN_INSTALL_RELDIR "lib/${CMAKE_LIBRARY_ARCHITECTURE}/meshlab/plugins")
