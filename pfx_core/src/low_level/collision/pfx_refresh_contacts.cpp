#include "pfx/low_level/collision/pfx_refresh_contacts.h"

namespace pfx {

namespace {

constexpr PfxUInt32 kPairsPerTask = 128;

void refreshPair(const PfxRefreshContactsParam& param, PfxConstraintPair& pair) {
  PfxContactManifold& manifold = param.offsetContactManifolds[pfxGetContactId(pair)];
  if (param.offsetCollidables) {
    manifold.carryMeshContacts(param.offsetCollidables[pfxGetObjectIdA(pair)],
                               param.offsetCollidables[pfxGetObjectIdB(pair)]);
  }
  manifold.refresh(param.offsetRigidStates[pfxGetObjectIdA(pair)].getTransform(),
                   param.offsetRigidStates[pfxGetObjectIdB(pair)].getTransform(),
                   param.breakDistance);
  pfxSetNumConstraints(pair, manifold.getNumContacts());
}

}  // namespace

PfxInt32 pfxRefreshContacts(const PfxRefreshContactsParam& param, PfxTaskManager* taskManager) {
  if (param.numContactPairs > 0 &&
      (!param.contactPairs || !param.offsetContactManifolds || !param.offsetRigidStates)) {
    return PFX_ERR_NULL_POINTER;
  }
  if (!(param.breakDistance >= 0) || !pfxIsFinite(param.breakDistance)) {
    return PFX_ERR_INVALID_VALUE;
  }
  if (!pfxPairsInRange(param.contactPairs, param.numContactPairs, param.numRigidBodies,
                       param.numContactManifolds)) {
    return PFX_ERR_OUT_OF_RANGE;
  }
  pfxParallelFor(taskManager, param.numContactPairs, kPairsPerTask,
                 [&](PfxUInt32 begin, PfxUInt32 end) {
                   for (PfxUInt32 i = begin; i < end; ++i) refreshPair(param, param.contactPairs[i]);
                 });
  return PFX_OK;
}

}  // namespace pfx
