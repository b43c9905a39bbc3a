// Shock propagation (Guendelman, Bridson and Fedkiw 2003, "Nonconvex rigid bodies with
// stacking"): after the iterations, one more pass over the contacts that hold bodies up,
// from the ground upwards, each contact solved as if its lower body could not move. Sweeps
// pass a pile's weight down one body per sweep; a pile 20 boxes high, its columns joined
// in loops that the contacts' direct solve does not take, sank into itself at 4
// iterations and was then thrown back up by the warm-started impulses. After the pass no
// body moves into the one under it, whatever the loops, so the pile no longer sinks,
// while the iterations' impulses, which the pass leaves alone, go on converging from step
// to step through the warm start. The pass only pushes (its own impulse is kept at zero or
// above) and holds no friction: holding the upper body's slip too made the pile worse
// (contacts 12 cm deep and boxes at 1.9 m/s within 2 s). Run on the velocity changes and on the split impulses' push.
#pragma once

#include <cstddef>

#include "pfx/base_level/broadphase/pfx_broadphase_pair.h"
#include "pfx/base_level/collision/pfx_contact_manifold.h"
#include "pfx/base_level/rigidbody/pfx_rigid_state.h"
#include "pfx/base_level/solver/pfx_solver_body.h"

namespace pfx {

class PfxShockPropagation {
 public:
  static std::size_t getWorkBytes(PfxUInt32 numContactPairs);

  // Picks the contacts whose normal lies within 45 degrees of `up` (zero picks none) and
  // orders them by the height of their lower body, fixed bodies first. The work buffer
  // must hold getWorkBytes(numContactPairs).
  void build(void* workBuff, const PfxConstraintPair* contactPairs, PfxUInt32 numContactPairs,
             PfxContactManifold* manifolds, const PfxRigidState* states,
             PfxSolverBody* solverBodies, const PfxVector3& up);

  // One pass in that order over the solved velocity changes, or over the push velocities
  // of the split impulses: each contact's upper body is given what keeps it from moving
  // into the lower one, the lower body left as it is. The contacts' stored impulses are
  // not changed, so the next step's warm start is the iterations' own.
  void propagate(bool push) const;

 private:
  struct Contact {
    PfxFloat upperHeight;
    PfxUInt32 upper;
    PfxUInt32 pair;
    bool lowerIsA;
    PfxFloat impulse[PFX_NUM_CONTACTS_PER_MANIFOLD];  // the pass's own, per point
  };
  void solveContact(Contact& contact, bool push) const;
  Contact* m_contacts = nullptr;
  PfxUInt32 m_numContacts = 0;
  const PfxConstraintPair* m_pairs = nullptr;
  PfxContactManifold* m_manifolds = nullptr;
  PfxSolverBody* m_solverBodies = nullptr;
};

}  // namespace pfx
