# The Debian package meshlab-geofilter (cpack -G DEB in the build folder, or
# scripts/package.sh): the MeshLab 2020.09 plugin in Debian's MeshLab plugin folder and the
# geofilter tool in /usr/bin. The plugin is only loadable by the exact MeshLab it was built
# against (MeshLab has no stable plugin ABI), so the package depends on that version.
include_guard(GLOBAL)

execute_process(COMMAND dpkg-query -W "-f=\${Version}" meshlab
                OUTPUT_VARIABLE _geofilter_meshlab_version RESULT_VARIABLE _geofilter_dpkg_rc ERROR_QUIET)
if(NOT _geofilter_dpkg_rc EQUAL 0 OR NOT _geofilter_meshlab_version)
  message(FATAL_ERROR "GeoFilter packaging: the meshlab package is not installed, so the version the plugin must"
                      " depend on is unknown (apt install meshlab, or -DGEOFILTER_BUILD_PLUGIN=OFF)")
endif()

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME meshlab-geofilter)
set(CPACK_PACKAGE_VERSION "${PROJECT_VERSION}")
set(CPACK_PACKAGE_CONTACT "GeoFilter developers <geofilter@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "GeoFilter mesh filters for MeshLab (Kim & Rossignac 2005)")
set(CPACK_PACKAGE_DESCRIPTION
    "Filters whose frequencies come from the physical size of a selected feature: lowpass, bandpass, highpass,\n"
    "notch, band exaggeration, custom and pole-zero GeoFilters as a MeshLab plugin (Filters > Smoothing,\n"
    "Fairing and Deformation > GeoFilter) and the command-line tool geofilter.")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION graphics)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "meshlab (= ${_geofilter_meshlab_version})")
# The shared libraries the plugin and the tool link (CHOLMOD, Qt, ...), found by
# dpkg-shlibdeps; libmeshlab-common lives in MeshLab's private folder and comes with meshlab.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS_PRIVATE_DIRS "${MESHLAB_PLUGIN_INSTALL_DIR}/..")
include(CPack)
