# FindSPNG: libspng, the fast PNG decoder (Debian: libspng-dev), which ships a pkg-config file but
# no CMake config. Defines SPNG_FOUND, SPNG_INCLUDE_DIR, SPNG_LIBRARY and the imported target
# SPNG::SPNG. Only tests/bench/vision_opencv_bench uses it, to time it beside libpng
# (docs/performance.md: not faster on our frames, so vision/ keeps libpng).
find_path(SPNG_INCLUDE_DIR spng.h)
find_library(SPNG_LIBRARY NAMES spng)
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(SPNG REQUIRED_VARS SPNG_LIBRARY SPNG_INCLUDE_DIR)
if(SPNG_FOUND AND NOT TARGET SPNG::SPNG)
  add_library(SPNG::SPNG UNKNOWN IMPORTED)
  set_target_properties(SPNG::SPNG PROPERTIES
                        IMPORTED_LOCATION "${SPNG_LIBRARY}"
                        INTERFACE_INCLUDE_DIRECTORIES "${SPNG_INCLUDE_DIR}")
endif()
mark_as_advanced(SPNG_INCLUDE_DIR SPNG_LIBRARY)
