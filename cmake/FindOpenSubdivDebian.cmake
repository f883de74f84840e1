# Finds OpenSubdiv's CPU library (libosdCPU) on Debian and wraps it in the
# IMPORTED target OpenSubdiv::osdCPU.
#
# Why not find_package(OpenSubdiv): Debian's OpenSubdivConfig.cmake names
# libosdCPU.a, which libosd-dev does not ship, so the config fails
# (docs/design.md, "Debian dependencies"). libosdCPU.so pulls in libgomp by itself and
# needs no GL.
#
# Result: OpenSubdivDebian_FOUND, OpenSubdiv_INCLUDE_DIR, OpenSubdiv_CPU_LIBRARY
# and the target OpenSubdiv::osdCPU. Its headers are SYSTEM: they raise
# -Wunused-parameter and similar under the project's -Wall -Wextra -Werror.

find_path(OpenSubdiv_INCLUDE_DIR opensubdiv/far/topologyRefiner.h)
find_library(OpenSubdiv_CPU_LIBRARY NAMES osdCPU)

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(OpenSubdivDebian
  REQUIRED_VARS OpenSubdiv_CPU_LIBRARY OpenSubdiv_INCLUDE_DIR)
mark_as_advanced(OpenSubdiv_INCLUDE_DIR OpenSubdiv_CPU_LIBRARY)

if(OpenSubdivDebian_FOUND AND NOT TARGET OpenSubdiv::osdCPU)
  add_library(OpenSubdiv::osdCPU UNKNOWN IMPORTED)
  set_target_properties(OpenSubdiv::osdCPU PROPERTIES
    IMPORTED_LOCATION "${OpenSubdiv_CPU_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${OpenSubdiv_INCLUDE_DIR}"
    INTERFACE_SYSTEM_INCLUDE_DIRECTORIES "${OpenSubdiv_INCLUDE_DIR}")
endif()
