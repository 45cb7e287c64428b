# OpenCV's per-module Debian packages (libopencv-core-dev, libopencv-imgproc-dev, ...) ship no
# CMake config (see ../shared/reference/dependencies.md), so their imported targets are
# declared here: nav_import_opencv(core imgproc ...) gives opencv_core, opencv_imgproc, ...
function(nav_import_opencv)
  find_path(NAV_OPENCV_INCLUDE_DIR opencv2/core.hpp PATH_SUFFIXES opencv4 REQUIRED)
  foreach(module IN LISTS ARGN)
    if(NOT TARGET opencv_${module})
      find_library(NAV_OPENCV_${module}_LIBRARY opencv_${module} REQUIRED)
      add_library(opencv_${module} UNKNOWN IMPORTED GLOBAL)
      set_target_properties(opencv_${module} PROPERTIES
        IMPORTED_LOCATION ${NAV_OPENCV_${module}_LIBRARY}
        INTERFACE_SYSTEM_INCLUDE_DIRECTORIES ${NAV_OPENCV_INCLUDE_DIR}
        INTERFACE_INCLUDE_DIRECTORIES ${NAV_OPENCV_INCLUDE_DIR})
    endif()
  endforeach()
endfunction()
