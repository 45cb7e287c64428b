#pragma once
// The instruction sets rtlib's lane kernels are compiled for. A kernel source named *.isa.cpp
// is compiled once per instruction set (rtlib/CMakeLists.txt): plain loops over lanes, sums in
// an order written in the code, and a multiply-add fused only where the code says so
// (__builtin_fma; the compiler fuses nothing itself, -ffp-contract=off). A fused one is rounded
// once on every instruction set (the FMA unit of AVX2, AVX-512 and NEON; on the x86-64 baseline,
// libm's correctly rounded fma, slow, for CPUs without AVX2 and FMA), so every variant
// computes the same bits; a wider one only does more lanes per instruction. Models pick one at
// init (`best`: the widest this CPU runs).
#include <cstdint>
#include <string_view>

namespace nav {

/// An instruction set of the lane kernels.
enum class KernelIsa : std::uint8_t {
  best,      ///< the widest one compiled in and supported by this CPU
  baseline,  ///< the target's base instruction set (x86-64: SSE2; aarch64: NEON)
  avx2,      ///< x86-64 with AVX2 and FMA (4 doubles a vector)
  avx512,    ///< x86-64 with AVX-512 F/DQ/VL (8 doubles a vector)
};

/// True when `isa` is compiled into this build and this CPU runs it (`best` always is).
bool kernel_isa_available(KernelIsa isa) noexcept;

/// `best` resolved to the widest available instruction set; any other value unchanged.
KernelIsa resolve_kernel_isa(KernelIsa isa) noexcept;

/// "best", "baseline", "avx2", "avx512".
std::string_view kernel_isa_name(KernelIsa isa) noexcept;

}  // namespace nav
