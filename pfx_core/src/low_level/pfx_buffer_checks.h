// The checks every low-level stage makes of the buffers its caller passes in.
#pragma once

#include <cstdint>

#include "pfx/base_level/base/pfx_common.h"

namespace pfx {

// PFX_OK, or why `buff` cannot serve as `requiredBytes` of scratch or output.
inline PfxInt32 pfxCheckBuffer(const void* buff, PfxUInt64 bytes, PfxUInt64 requiredBytes) {
  if (!buff) return PFX_ERR_OUT_OF_BUFFER;
  if (!pfxIsAligned(buff)) return PFX_ERR_INVALID_ALIGNMENT;
  if (bytes < requiredBytes) return PFX_ERR_OUT_OF_BUFFER;
  return PFX_OK;
}

// A stage that writes one buffer while it reads another gives garbage when they share
// bytes, so such calls are rejected rather than run.
inline bool pfxRangesOverlap(const void* a, PfxUInt64 bytesA, const void* b, PfxUInt64 bytesB) {
  const auto beginA = reinterpret_cast<std::uintptr_t>(a);
  const auto beginB = reinterpret_cast<std::uintptr_t>(b);
  return bytesA > 0 && bytesB > 0 && beginA < beginB + bytesB && beginB < beginA + bytesA;
}

}  // namespace pfx
