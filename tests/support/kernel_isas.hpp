#pragma once
// The lane-kernel instruction sets this build and CPU run (nav/core/kernel_isa.hpp), for tests
// that compare every variant with the baseline.
#include <vector>

#include "nav/core/kernel_isa.hpp"

namespace nav::testing {

/// baseline first, then every wider variant available here.
inline std::vector<KernelIsa> available_kernel_isas() {
  std::vector<KernelIsa> out;
  for (KernelIsa isa : {KernelIsa::baseline, KernelIsa::avx2, KernelIsa::avx512})
    if (kernel_isa_available(isa)) out.push_back(isa);
  return out;
}

}  // namespace nav::testing
