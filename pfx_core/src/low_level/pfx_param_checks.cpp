#include "low_level/pfx_param_checks.h"

#include <cstdarg>
#include <cstdio>

#include "low_level/pfx_buffer_checks.h"
#include "pfx/base_level/base/pfx_vec_math.h"
#include "pfx/base_level/broadphase/pfx_broadphase_pair.h"
#include "pfx/low_level/pfx_error_detail.h"

namespace pfx {

namespace {

// Long enough for a stage, a struct, a field and the numbers that explain them.
constexpr int kDetailChars = 320;
thread_local char t_lastErrorDetail[kDetailChars] = "";

// "Param::" before a field of a parameter struct, nothing before an argument's name.
const char* scope(const PfxParamNames& at) { return at.param[0] ? "::" : ""; }

}  // namespace

const char* pfxGetLastErrorDetail() { return t_lastErrorDetail; }

PfxInt32 pfxRejectParam(PfxInt32 errorCode, const char* format, ...) {
  va_list args;
  va_start(args, format);
  std::vsnprintf(t_lastErrorDetail, kDetailChars, format, args);
  va_end(args);
  return errorCode;
}

PfxInt32 pfxRejectNull(const PfxParamNames& at, const char* field, const char* countField,
                       PfxUInt64 count) {
  return pfxRejectParam(PFX_ERR_NULL_POINTER, "%s: %s%s%s is null, but %s is %llu", at.stage,
                        at.param, scope(at), field, countField,
                        static_cast<unsigned long long>(count));
}

PfxInt32 pfxCheckRequired(const PfxParamNames& at,
                          std::initializer_list<PfxRequiredPointer> pointers,
                          const char* countField, PfxUInt64 count) {
  if (count == 0) return PFX_OK;
  for (const PfxRequiredPointer& required : pointers) {
    if (!required.pointer) return pfxRejectNull(at, required.field, countField, count);
  }
  return PFX_OK;
}

PfxInt32 pfxCheckValue(const PfxParamNames& at, const char* field, double value, bool valid,
                       const char* requirement) {
  if (valid) return PFX_OK;
  return pfxRejectParam(PFX_ERR_INVALID_VALUE, "%s: %s%s%s is %g; it must be %s", at.stage,
                        at.param, scope(at), field, value, requirement);
}

PfxInt32 pfxCheckTimeStep(const PfxParamNames& at, PfxFloat timeStep) {
  return pfxCheckValue(at, "timeStep", timeStep, timeStep > 0 && pfxIsFinite(timeStep),
                       "positive and finite");
}

PfxInt32 pfxCheckPairsInRange(const PfxParamNames& at, const char* pairsField,
                              const PfxSortData16* pairs, PfxUInt32 numPairs,
                              PfxUInt32 numRigidBodies, const char* countField,
                              PfxUInt32 numConstraints) {
  for (PfxUInt32 i = 0; i < numPairs; ++i) {
    const PfxUInt32 idA = pfxGetObjectIdA(pairs[i]);
    const PfxUInt32 idB = pfxGetObjectIdB(pairs[i]);
    if (idA >= numRigidBodies || idB >= numRigidBodies) {
      return pfxRejectParam(PFX_ERR_OUT_OF_RANGE,
                            "%s: %s%s%s[%u] names bodies %u and %u, but numRigidBodies is %u",
                            at.stage, at.param, scope(at), pairsField, i, idA, idB, numRigidBodies);
    }
    const PfxUInt32 id = pfxGetConstraintId(pairs[i]);
    if (numConstraints > 0 && id >= numConstraints) {
      return pfxRejectParam(PFX_ERR_OUT_OF_RANGE, "%s: %s%s%s[%u] names entry %u, but %s is %u",
                            at.stage, at.param, scope(at), pairsField, i, id, countField,
                            numConstraints);
    }
  }
  return PFX_OK;
}

PfxInt32 pfxCheckBuffer(const PfxParamNames& at, const char* buffField, const void* buff,
                        PfxUInt64 bytes, PfxUInt64 requiredBytes) {
  const auto bytesOf = [](PfxUInt64 n) { return static_cast<unsigned long long>(n); };
  // A call with nothing to hold (no body, no pair) needs no buffer, and an empty
  // std::vector's data() is null.
  if (!buff && requiredBytes > 0) {
    return pfxRejectParam(PFX_ERR_OUT_OF_BUFFER, "%s: %s%s%s is null; it needs %llu bytes",
                          at.stage, at.param, scope(at), buffField, bytesOf(requiredBytes));
  }
  if (!pfxIsAligned(buff)) {
    return pfxRejectParam(PFX_ERR_INVALID_ALIGNMENT, "%s: %s%s%s is not 16-byte aligned", at.stage,
                          at.param, scope(at), buffField);
  }
  if (bytes < requiredBytes) {
    return pfxRejectParam(PFX_ERR_OUT_OF_BUFFER, "%s: %s%s%s holds %llu bytes; it needs %llu",
                          at.stage, at.param, scope(at), buffField, bytesOf(bytes),
                          bytesOf(requiredBytes));
  }
  return PFX_OK;
}

}  // namespace pfx
