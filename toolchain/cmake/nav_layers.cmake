# The layers of the project, checked at configure time: apps -> drivers -> calibration -> rtlib,
# and inside rtlib each area above the ones it lists (rtlib/CMakeLists.txt). A source that
# includes a header of a layer it may not use stops the configuration, naming both.
set(NAV_RTLIB_AREAS core mesh mesher tissue reduced connective needle fusion loop)

# Checks every .hpp and .cpp under `folder`: each `#include "nav/<area>/..."` must name one of
# the areas after `folder` (the layer's own and those below it).
function(nav_check_includes folder)
  set(allowed ${ARGN})
  set(depends CONFIGURE_DEPENDS)
  if(CMAKE_SCRIPT_MODE_FILE)
    set(depends "")  # the layer tests run it as a script
  endif()
  file(GLOB_RECURSE files ${depends} ${folder}/*.hpp ${folder}/*.cpp)
  foreach(file IN LISTS files)
    file(STRINGS ${file} includes REGEX "^#include \"nav/[a-z_]+/")
    foreach(include IN LISTS includes)
      string(REGEX REPLACE "^#include \"nav/([a-z_]+)/.*" "\\1" included ${include})
      if(NOT included IN_LIST allowed)
        message(FATAL_ERROR "${file}: ${include}: the files of ${folder} may include only nav/{${allowed}} "
                            "(toolchain/cmake/nav_layers.cmake)")
      endif()
    endforeach()
  endforeach()
endfunction()
