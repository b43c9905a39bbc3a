// Shock propagation (Guendelman, Bridson and Fedkiw 2003, "Nonconvex rigid bodies with
// stacking"): after the iterations, one more pass over the contacts that hold bodies up,
// from the ground upwards, each contact solved as if its lower body could not move. Sweeps
// pass a pile's weight down one body per sweep; a pile 20 boxes high, its columns joined
// in loops that the contacts' direct solve does not take, sank into itself at 4
// iterations and was then thrown back up by the warm-started impulses. After the pass no
// body moves into the one under it, whatever the loops, so the pile no longer sinks,
// while the iterations' impulses, which the pass leaves alone, go on converging from step
// to step through the warm start. Run on the velocity changes and on the split impulses'
// push. On the velocities the pass also takes back what the iterations pushed where a body
// leaves the one under it (never more: the contact's impulse stays at zero or above), and
// then holds the body on what carries it (holdUpperBody): its centre takes the carrying
// bodies' velocity within the friction their load allows, and, when its centre lies over
// its support, their turn within the moment the load can hold at the support's edge.
// Without these a pile's residues of the iterations (turns from pushes at the edges of
// diagonal neighbours, slides that sweeps pass down one body per sweep, columns thrown up
// by the warm start) went on from step to step: the outer columns of a 5 x 5 x 20 pile slid
// out to the walls and its corner columns hopped. Holding each point's slip instead, with
// the pass only pushing, made the pile worse (contacts 12 cm deep and boxes at 1.9 m/s
// within 2 s); so did taking back alone (the pile slid apart within 7 s instead of 15).
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
  // into the lower one, the lower body left as it is, and, on the velocities, is then held
  // on the bodies under it. The contacts' stored impulses are not changed, so the next
  // step's warm start is the iterations' own.
  void propagate(bool push) const;

 private:
  struct Contact {
    PfxFloat upperHeight;
    PfxUInt32 upper;
    PfxUInt32 pair;
    bool lowerIsA;
    // Per point: on the velocities the iterations' impulse and the pass's; on the push,
    // the pass's own.
    PfxFloat impulse[PFX_NUM_CONTACTS_PER_MANIFOLD];
  };
  void solveContact(Contact& contact, bool push) const;
  void holdUpperBody(const Contact* begin, const Contact* end) const;
  Contact* m_contacts = nullptr;
  PfxUInt32 m_numContacts = 0;
  const PfxConstraintPair* m_pairs = nullptr;
  PfxContactManifold* m_manifolds = nullptr;
  const PfxRigidState* m_states = nullptr;
  PfxSolverBody* m_solverBodies = nullptr;
  PfxVector3 m_up = PfxVector3::Zero();
};

}  // namespace pfx
