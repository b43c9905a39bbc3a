// What the constraint solver needs of one rigid body, copied out before the iterations so
// that they touch as little memory as possible (seed chapter 2, "Solver Body"). The solver
// accumulates velocity changes here; pfxSolveConstraints adds them to the states at the end.
// Overlaps are pushed out by split impulses: "push" velocities that move the body during
// the solve's position correction but are then forgotten, so that pushing bodies apart
// never adds kinetic energy (which would make stacks rock and topple).
#pragma once

#include "pfx/base_level/base/pfx_vec_math.h"

namespace pfx {

struct PfxSolverBody {
  PfxVector3 m_deltaLinearVelocity;
  PfxVector3 m_deltaAngularVelocity;
  PfxVector3 m_pushLinearVelocity;
  PfxVector3 m_pushAngularVelocity;
  PfxMatrix3 m_inertiaInv;  // world frame
  PfxFloat m_massInv;
  PfxUInt32 m_motionType;
  // The inertia the joints' geometric stiffness added about every axis (kg m^2), already in
  // m_inertiaInv; zero until pfxSetupJointConstraints adds it.
  PfxFloat m_stiffnessInertia;
};

// Whether an impulse changes the body's velocities (`receives` is 0 or 1, as the pair
// says). The solver writes only to such bodies; the others are only read, so that
// constraints solved at the same time may share them (a floor under many bodies).
inline bool pfxTakesImpulse(const PfxSolverBody& body, PfxFloat receives) {
  return receives != 0 && body.m_massInv != 0;
}

}  // namespace pfx
