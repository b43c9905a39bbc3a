#include "pfx/base_level/base/pfx_common.h"

namespace pfx {

const char* pfxErrorString(PfxInt32 errorCode) {
  switch (errorCode) {
    case PFX_OK: return "ok";
    case PFX_ERR_INVALID_VALUE: return "invalid value (NaN, infinite, negative or out of range)";
    case PFX_ERR_INVALID_ALIGNMENT: return "buffer is not 16-byte aligned";
    case PFX_ERR_OUT_OF_BUFFER: return "buffer is missing or too small";
    case PFX_ERR_OUT_OF_WORLD: return "body lies outside the world bounds";
    case PFX_ERR_OUT_OF_MAX_PAIRS: return "more pairs than the pair buffer holds";
    case PFX_ERR_INVALID_FLAG: return "unknown flag or type";
    case PFX_ERR_NOT_CONVEX: return "mesh is not convex or not closed";
    case PFX_ERR_OUT_OF_RANGE: return "index or count out of range";
    case PFX_ERR_DEGENERATE: return "degenerate geometry (zero size, area or length)";
    case PFX_ERR_NULL_POINTER: return "required pointer is null";
    default: return "unknown error";
  }
}

}  // namespace pfx
