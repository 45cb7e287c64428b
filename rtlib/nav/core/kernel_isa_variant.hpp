#pragma once
// Included first by a kernel source compiled once per instruction set (*.isa.cpp; see
// kernel_isa.hpp): NAV_KERNEL_ISA names the variant being compiled (baseline, avx2, avx512).
// Such a source keeps everything it defines in NAV_KERNEL_ISA_NAMESPACE (an anonymous
// namespace inside it) except its exported table, named with NAV_KERNEL_ISA_NAME(prefix), and
// includes no header with inline functions of its own (no Eigen, no standard containers):
// the linker must never pick a wider variant's copy of a shared inline function.
#ifndef NAV_KERNEL_ISA
#error "compile kernel sources through rtlib/CMakeLists.txt, which defines NAV_KERNEL_ISA"
#endif

#define NAV_KERNEL_ISA_JOIN2(a, b) a##b
#define NAV_KERNEL_ISA_JOIN(a, b) NAV_KERNEL_ISA_JOIN2(a, b)
#define NAV_KERNEL_ISA_NAMESPACE NAV_KERNEL_ISA_JOIN(isa_, NAV_KERNEL_ISA)
#define NAV_KERNEL_ISA_NAME(prefix) NAV_KERNEL_ISA_JOIN(prefix, NAV_KERNEL_ISA)
