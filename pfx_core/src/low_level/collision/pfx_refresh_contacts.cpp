#include "pfx/low_level/collision/pfx_refresh_contacts.h"

#include "low_level/pfx_param_checks.h"

namespace pfx {

namespace {

// A pair's refresh takes tens of nanoseconds: a task of fewer cost more to hand to a thread
// than it saved (the piled ragdolls' 555 pairs, three times slower on two threads at 128).
constexpr PfxUInt32 kRefreshedPairsPerTask = 1024;

void refreshPair(const PfxRefreshContactsParam& param, PfxConstraintPair& pair) {
  PfxContactManifold& manifold = param.offsetContactManifolds[pfxGetContactId(pair)];
  // Nothing to refresh; and a manifold that pairs share (pfxDetectCollision) is only read.
  if (manifold.getNumContacts() == 0) {
    pfxSetNumConstraints(pair, 0);
    return;
  }
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
  const PfxParamNames at{"pfxRefreshContacts", "PfxRefreshContactsParam"};
  // Checked in turn, so that the detail names the first field that is wrong.
  PfxInt32 err = PFX_OK;
  if ((err = pfxCheckRequired(at,
                              {{param.contactPairs, "contactPairs"},
                               {param.offsetContactManifolds, "offsetContactManifolds"},
                               {param.offsetRigidStates, "offsetRigidStates"}},
                              "numContactPairs", param.numContactPairs)) != PFX_OK ||
      (err = pfxCheckValue(at, "breakDistance", param.breakDistance,
                           param.breakDistance >= 0 && pfxIsFinite(param.breakDistance),
                           "finite and not negative")) != PFX_OK ||
      (err = pfxCheckPairsInRange(at, "contactPairs", param.contactPairs, param.numContactPairs,
                                  param.numRigidBodies, "numContactManifolds",
                                  param.numContactManifolds)) != PFX_OK) {
    return err;
  }
  pfxParallelFor(taskManager, param.numContactPairs, kRefreshedPairsPerTask,
                 [&](PfxUInt32 begin, PfxUInt32 end) {
                   for (PfxUInt32 i = begin; i < end; ++i)
                     refreshPair(param, param.contactPairs[i]);
                 });
  return PFX_OK;
}

}  // namespace pfx
