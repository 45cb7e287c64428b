# Package configuration for find_package(navrt): imports nav::rtlib and its dependencies.
include(CMakeFindDependencyMacro)
find_dependency(Eigen3 3.3 NO_MODULE)
find_dependency(Threads)
include(${CMAKE_CURRENT_LIST_DIR}/navrtTargets.cmake)
