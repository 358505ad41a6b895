# cmake -P script: lay out a private MeshLab prefix next to the freshly built plugin.
#   PREFIX, PLUGIN_RELDIR, SYSTEM_PLUGIN_DIR, MESHLAB_COMMON_LIBRARY,
#   EXECUTABLES (paths separated by |), OWN_PLUGIN (file name of our plugin)
#
# Why this shape:
# - the executables are COPIES: MeshLab finds its plugins relative to
#   /proc/self/exe, which resolves symlinks, so a symlinked meshlabserver would
#   load the system plugin folder (and maybe an older installed GeoFilter);
# - their RUNPATH is $ORIGIN/../lib/<arch>/meshlab, hence the libmeshlab-common.so link;
# - system plugins are linked, not copied, and ours is skipped so that an
#   installed GeoFilter never shadows the one just built.

foreach(v PREFIX PLUGIN_RELDIR SYSTEM_PLUGIN_DIR MESHLAB_COMMON_LIBRARY EXECUTABLES OWN_PLUGIN)
  if(NOT DEFINED ${v} OR "${${v}}" STREQUAL "")
    message(FATAL_ERROR "make_prefix.cmake: ${v} not set")
  endif()
endforeach()

set(plugin_dir "${PREFIX}/${PLUGIN_RELDIR}")
get_filename_component(lib_dir "${plugin_dir}" DIRECTORY)
file(MAKE_DIRECTORY "${PREFIX}/bin" "${plugin_dir}")

string(REPLACE "|" ";" exes "${EXECUTABLES}")
foreach(exe IN LISTS exes)
  get_filename_component(name "${exe}" NAME)
  # copy_if_different keeps the time stamp when nothing changed (no needless rewrites).
  execute_process(COMMAND "${CMAKE_COMMAND}" -E copy_if_different "${exe}" "${PREFIX}/bin/${name}"
                  RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "make_prefix.cmake: cannot copy ${exe}")
  endif()
endforeach()

function(link_to target link)
  if(IS_SYMLINK "${link}")
    file(READ_SYMLINK "${link}" current)
    if(current STREQUAL target)
      return()
    endif()
    file(REMOVE "${link}")
  elseif(EXISTS "${link}")
    message(FATAL_ERROR "make_prefix.cmake: ${link} exists and is not a symlink; remove it")
  endif()
  file(CREATE_LINK "${target}" "${link}" SYMBOLIC)
endfunction()

get_filename_component(common_name "${MESHLAB_COMMON_LIBRARY}" NAME)
link_to("${MESHLAB_COMMON_LIBRARY}" "${lib_dir}/${common_name}")

# Links left by an earlier run whose system plugin is gone would make MeshLab
# print load errors: drop dangling links (only links; never the built plugin).
file(GLOB existing LIST_DIRECTORIES false "${plugin_dir}/*")
foreach(f IN LISTS existing)
  if(IS_SYMLINK "${f}" AND NOT EXISTS "${f}")
    file(REMOVE "${f}")
  endif()
endforeach()

file(GLOB system_plugins LIST_DIRECTORIES false "${SYSTEM_PLUGIN_DIR}/*.so")
if(NOT system_plugins)
  message(FATAL_ERROR "make_prefix.cmake: no plugins in ${SYSTEM_PLUGIN_DIR} (is meshlab installed?)")
endif()
foreach(p IN LISTS system_plugins)
  get_filename_component(name "${p}" NAME)
  if(name STREQUAL "${OWN_PLUGIN}")
    continue()
  endif()
  link_to("${p}" "${plugin_dir}/${name}")
endforeach()
