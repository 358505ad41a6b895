# Included into MeshLab's own configure (CMAKE_PROJECT_INCLUDE) by build-meshlab-source.sh.
# libmeshlab-common, the largest part of what the tests need, is compiled as a unity build:
# most of its compile time is parsing the same Qt and vcglib headers again for every file.
# Its sources that include GLExtensionsManager.h, a header without an include guard, cannot
# share a unit and compile on their own. The GUI and the plugins build as MeshLab builds them
# (many of them include that header too). Nothing of MeshLab's sources is changed.
get_property(_geofilter_unity_deferred GLOBAL PROPERTY GEOFILTER_UNITY_DEFERRED)
if(NOT _geofilter_unity_deferred)
  set_property(GLOBAL PROPERTY GEOFILTER_UNITY_DEFERRED ON)
  function(_geofilter_unity_build)
    # common/ is in the top folder in 2022.02, in src/ from 2023.12 on.
    set(_common "${CMAKE_SOURCE_DIR}/common")
    if(EXISTS "${CMAKE_SOURCE_DIR}/src/common/CMakeLists.txt")
      set(_common "${CMAKE_SOURCE_DIR}/src/common")
    endif()
    set_target_properties(meshlab-common PROPERTIES UNITY_BUILD ON)
    file(GLOB_RECURSE _sources "${_common}/*.cpp")
    foreach(_source IN LISTS _sources)
      file(READ "${_source}" _text)
      if(_text MATCHES "GLExtensionsManager\\.h")
        set_source_files_properties("${_source}" DIRECTORY "${_common}" PROPERTIES SKIP_UNITY_BUILD_INCLUSION ON)
      endif()
    endforeach()
  endfunction()
  cmake_language(DEFER DIRECTORY "${CMAKE_SOURCE_DIR}" CALL _geofilter_unity_build)
endif()
