# GoogleTest for the test programs: the installed package on the host; when cross compiling,
# built for the target from the sources libgtest-dev ships (the host's libraries would not
# link). Test discovery then runs the programs (under CMAKE_CROSSCOMPILING_EMULATOR) when
# ctest starts rather than after each build.
if(CMAKE_CROSSCOMPILING)
  set(NAV_GOOGLETEST_SOURCE_DIR /usr/src/googletest CACHE PATH "GoogleTest sources to build for the target")
  if(NOT EXISTS ${NAV_GOOGLETEST_SOURCE_DIR}/CMakeLists.txt)
    message(FATAL_ERROR "no GoogleTest sources in ${NAV_GOOGLETEST_SOURCE_DIR} (apt-get install libgtest-dev)")
  endif()
  set(BUILD_GMOCK OFF)
  set(INSTALL_GTEST OFF)
  add_subdirectory(${NAV_GOOGLETEST_SOURCE_DIR} ${CMAKE_BINARY_DIR}/googletest EXCLUDE_FROM_ALL SYSTEM)
  set(CMAKE_GTEST_DISCOVER_TESTS_DISCOVERY_MODE PRE_TEST)
else()
  find_package(GTest REQUIRED)
endif()
