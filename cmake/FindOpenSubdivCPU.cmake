# Finds OpenSubdiv's CPU library (Far, Sdc, Vtr, Bfr, Osd CPU) and defines the
# imported target OpenSubdiv::osdCPU.
#
# Debian's libosd-dev ships a CMake config that names static libraries it does not
# install, so find_package(OpenSubdiv CONFIG) fails there; we look for the header
# and the shared library directly instead.
find_path(OpenSubdivCPU_INCLUDE_DIR opensubdiv/far/topologyRefiner.h)
find_library(OpenSubdivCPU_LIBRARY osdCPU)
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(OpenSubdivCPU
  REQUIRED_VARS OpenSubdivCPU_LIBRARY OpenSubdivCPU_INCLUDE_DIR)
if(OpenSubdivCPU_FOUND AND NOT TARGET OpenSubdiv::osdCPU)
  add_library(OpenSubdiv::osdCPU UNKNOWN IMPORTED)
  set_target_properties(OpenSubdiv::osdCPU PROPERTIES
    IMPORTED_LOCATION "${OpenSubdivCPU_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${OpenSubdivCPU_INCLUDE_DIR}")
endif()
mark_as_advanced(OpenSubdivCPU_INCLUDE_DIR OpenSubdivCPU_LIBRARY)
