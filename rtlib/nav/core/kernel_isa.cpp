#include "nav/core/kernel_isa.hpp"

namespace nav {

bool kernel_isa_available(KernelIsa isa) noexcept {
  switch (isa) {
    case KernelIsa::best:
    case KernelIsa::baseline:
      return true;
#if NAV_KERNEL_ISA_X86
    case KernelIsa::avx2:
      return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    case KernelIsa::avx512:
      return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
             __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("fma");
#else
    case KernelIsa::avx2:
    case KernelIsa::avx512:
      return false;
#endif
  }
  return false;
}

KernelIsa resolve_kernel_isa(KernelIsa isa) noexcept {
  if (isa != KernelIsa::best) return isa;
  for (KernelIsa widest : {KernelIsa::avx512, KernelIsa::avx2})
    if (kernel_isa_available(widest)) return widest;
  return KernelIsa::baseline;
}

std::string_view kernel_isa_name(KernelIsa isa) noexcept {
  switch (isa) {
    case KernelIsa::best:
      return "best";
    case KernelIsa::baseline:
      return "baseline";
    case KernelIsa::avx2:
      return "avx2";
    case KernelIsa::avx512:
      return "avx512";
  }
  return "unknown";
}

}  // namespace nav
