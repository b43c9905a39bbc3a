// Physical attributes of one rigid body: mass, inertia, friction, restitution.
#pragma once

#include "pfx/base_level/base/pfx_vec_math.h"

namespace pfx {

class PfxRigidBody {
 public:
  void reset();

  PfxFloat getMass() const { return m_mass; }
  PfxFloat getMassInv() const { return m_massInv; }
  // Inertia tensor about the centre of mass, in the body frame.
  const PfxMatrix3& getInertia() const { return m_inertia; }
  const PfxMatrix3& getInertiaInv() const { return m_inertiaInv; }
  PfxFloat getFriction() const { return m_friction; }
  PfxFloat getRestitution() const { return m_restitution; }

  // Stores the mass as given; isValid() tells whether it can drive an active body.
  void setMass(PfxFloat mass);
  void setInertia(const PfxMatrix3& inertia);
  void setFriction(PfxFloat friction) { m_friction = friction; }
  void setRestitution(PfxFloat restitution) { m_restitution = restitution; }

  // Positive finite mass, symmetric positive-definite inertia whose smallest principal moment
  // is not lost in rounding beside the largest (at least the largest times epsilon),
  // friction >= 0, 0 <= restitution <= 1.
  bool isValid() const;

 private:
  PfxMatrix3 m_inertia;
  PfxMatrix3 m_inertiaInv;
  PfxFloat m_mass;
  PfxFloat m_massInv;
  PfxFloat m_friction;
  PfxFloat m_restitution;
};

}  // namespace pfx
