// How a low-level stage rejects its Param: the error code it returns, and the detail that
// pfxGetLastErrorDetail() reads back (pfx_error_detail.h), naming the stage, the field and
// why, e.g. "pfxDetectCollision: PfxDetectCollisionParam::offsetCollidables is null, but
// numContactPairs is 12".
#pragma once

#include <initializer_list>

#include "pfx/base_level/base/pfx_common.h"
#include "pfx/base_level/base/pfx_sort_data.h"

namespace pfx {

// The stage and its parameter struct, as every detail of the stage names them.
struct PfxParamNames {
  const char* stage;  // "pfxSolveConstraints"
  const char* param;  // "PfxSolveConstraintsParam", or "" for a stage that takes arguments
};

// Writes the detail (printf format) and returns errorCode, so that a check reads
// `return pfxRejectParam(PFX_ERR_..., "...", ...);`. Only a call being rejected writes it;
// it allocates nothing.
PfxInt32 pfxRejectParam(PfxInt32 errorCode, const char* format, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

// PFX_ERR_NULL_POINTER: "<stage>: <param>::<field> is null, but <countField> is <count>".
PfxInt32 pfxRejectNull(const PfxParamNames& at, const char* field, const char* countField,
                       PfxUInt64 count);

// An array the stage needs whenever `count` of something is not zero.
struct PfxRequiredPointer {
  const void* pointer;
  const char* field;
};

// PFX_OK when count is 0 or every pointer is set, else pfxRejectNull for the first null one.
PfxInt32 pfxCheckRequired(const PfxParamNames& at,
                          std::initializer_list<PfxRequiredPointer> pointers,
                          const char* countField, PfxUInt64 count);

// PFX_OK when `valid`, else PFX_ERR_INVALID_VALUE:
// "<stage>: <param>::<field> is <value>; it must be <requirement>".
PfxInt32 pfxCheckValue(const PfxParamNames& at, const char* field, double value, bool valid,
                       const char* requirement);

// pfxCheckValue for a stage's timeStep, which must be positive and finite.
PfxInt32 pfxCheckTimeStep(const PfxParamNames& at, PfxFloat timeStep);

// PFX_OK when every pair names bodies below numRigidBodies and, when numConstraints is
// given (not 0), a manifold or joint below it; PFX_ERR_OUT_OF_RANGE naming the first pair
// that does not. A count of 0 means the caller did not give the length of the array: the
// pair's id then indexes it unchecked, one manifold or joint per pair as the seed's
// programs lay them out.
PfxInt32 pfxCheckPairsInRange(const PfxParamNames& at, const char* pairsField,
                              const PfxSortData16* pairs, PfxUInt32 numPairs,
                              PfxUInt32 numRigidBodies, const char* countField,
                              PfxUInt32 numConstraints);

}  // namespace pfx
