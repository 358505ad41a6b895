# CHOLMOD from Debian's libsuitesparse-dev ships no CMake config: find it by hand and
# expose an imported target `cholmod::cholmod`.
include_guard(GLOBAL)
find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)
find_library(CHOLMOD_LIBRARY cholmod)
find_library(SUITESPARSE_CONFIG_LIBRARY suitesparseconfig)
if(NOT CHOLMOD_INCLUDE_DIR OR NOT CHOLMOD_LIBRARY OR NOT SUITESPARSE_CONFIG_LIBRARY)
  message(FATAL_ERROR "CHOLMOD not found: apt-get install libsuitesparse-dev")
endif()
add_library(cholmod::cholmod INTERFACE IMPORTED)
target_include_directories(cholmod::cholmod INTERFACE "${CHOLMOD_INCLUDE_DIR}")
target_link_libraries(cholmod::cholmod INTERFACE "${CHOLMOD_LIBRARY}" "${SUITESPARSE_CONFIG_LIBRARY}")
