#include "pfx/low_level/collision/pfx_refresh_contacts.h"

namespace pfx {

PfxInt32 pfxRefreshContacts(const PfxRefreshContactsParam& param) {
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
  for (PfxUInt32 i = 0; i < param.numContactPairs; ++i) {
    PfxConstraintPair& pair = param.contactPairs[i];
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
  return PFX_OK;
}

}  // namespace pfx
