// The checks every low-level stage makes of the buffers its caller passes in.
#pragma once

#include <cstdint>

#include "low_level/pfx_param_checks.h"
#include "pfx/base_level/base/pfx_common.h"

namespace pfx {

// PFX_OK, or why `buff` cannot serve as `requiredBytes` of scratch or output; the detail
// names the stage and the field `buffField`.
PfxInt32 pfxCheckBuffer(const PfxParamNames& at, const char* buffField, const void* buff,
                        PfxUInt64 bytes, PfxUInt64 requiredBytes);

// A stage that writes one buffer while it reads another gives garbage when they share
// bytes, so such calls are rejected rather than run.
inline bool pfxRangesOverlap(const void* a, PfxUInt64 bytesA, const void* b, PfxUInt64 bytesB) {
  const auto beginA = reinterpret_cast<std::uintptr_t>(a);
  const auto beginB = reinterpret_cast<std::uintptr_t>(b);
  return bytesA > 0 && bytesB > 0 && beginA < beginB + bytesB && beginB < beginA + bytesA;
}

}  // namespace pfx
