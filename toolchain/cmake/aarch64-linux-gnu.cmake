# Cross compiling for 64-bit ARM Linux with Debian's cross compiler (g++-aarch64-linux-gnu);
# test programs run under qemu user emulation (qemu-user), so ctest works as on the host.
# Install both with toolchain/install-deps.sh --cross; use it through the aarch64 preset.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)

set(NAV_CROSS_TRIPLE aarch64-linux-gnu)
set(CMAKE_C_COMPILER ${NAV_CROSS_TRIPLE}-gcc)
set(CMAKE_CXX_COMPILER ${NAV_CROSS_TRIPLE}-g++)

# The target's libraries and headers; Eigen is header-only, so the host's package serves.
set(NAV_CROSS_SYSROOT /usr/${NAV_CROSS_TRIPLE})
set(CMAKE_FIND_ROOT_PATH ${NAV_CROSS_SYSROOT})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
set(Eigen3_DIR /usr/share/eigen3/cmake CACHE PATH "Eigen's CMake package (header-only, host copy)")

set(CMAKE_CROSSCOMPILING_EMULATOR qemu-aarch64 -L ${NAV_CROSS_SYSROOT})
