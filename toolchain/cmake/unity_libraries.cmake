# NAV_UNITY_BUILD (the CI presets): every static library of the project compiles its sources
# in batches of eight, one translation unit each (CMake's unity build), so that the headers
# they share (Eigen, the standard library, Fast DDS) are parsed and instantiated once per
# batch instead of once per source. Executables and test programs compile source by source.
# A source's internal names (anonymous namespace) must then differ from those of the other
# sources of its library; lane kernels and other sources with options of their own stay apart.

# Turns the unity build on for the static libraries defined in `directory` and below it.
function(nav_unity_libraries directory)
  get_property(targets DIRECTORY ${directory} PROPERTY BUILDSYSTEM_TARGETS)
  foreach(target IN LISTS targets)
    get_target_property(type ${target} TYPE)
    if(type STREQUAL "STATIC_LIBRARY")
      set_target_properties(${target} PROPERTIES UNITY_BUILD ON)
    endif()
  endforeach()
  get_property(subdirectories DIRECTORY ${directory} PROPERTY SUBDIRECTORIES)
  foreach(subdirectory IN LISTS subdirectories)
    nav_unity_libraries(${subdirectory})
  endforeach()
endfunction()
