cmake_minimum_required(VERSION 3.22)
# A case of the configure-time layer check (toolchain/cmake/nav_layers.cmake), run by ctest as
# `cmake -DNAV_SOURCE_DIR=... -DNAV_SCRATCH=... -DNAV_INCLUDE=nav/<area>/<file> -P` on a scratch
# tissue area holding one source with that include: below tissue it passes, above it stops.
include(${NAV_SOURCE_DIR}/toolchain/cmake/nav_layers.cmake)
set(folder ${NAV_SCRATCH}/tissue)
file(REMOVE_RECURSE ${folder})
file(MAKE_DIRECTORY ${folder})
file(WRITE ${folder}/layer_case.cpp "#include \"${NAV_INCLUDE}\"\n")
nav_check_includes(${folder} tissue core mesh mesher)
message(STATUS "layers kept: ${NAV_INCLUDE}")
