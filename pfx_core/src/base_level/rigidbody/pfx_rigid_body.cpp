#include "pfx/base_level/rigidbody/pfx_rigid_body.h"

#include <Eigen/Eigenvalues>
#include <cstring>

namespace pfx {

void PfxRigidBody::reset() {
  std::memset(static_cast<void*>(this), 0, sizeof(*this));
  m_mass = 1;
  m_massInv = 1;
  m_inertia.setIdentity();
  m_inertiaInv.setIdentity();
  m_friction = 0.6f;
  m_restitution = 0;
}

void PfxRigidBody::setMass(PfxFloat mass) {
  m_mass = mass;
  m_massInv = (mass > 0 && pfxIsFinite(mass)) ? PfxFloat(1) / mass : PfxFloat(0);
}

void PfxRigidBody::setInertia(const PfxMatrix3& inertia) {
  m_inertia = inertia;
  const Eigen::FullPivLU<PfxMatrix3> lu(inertia);
  m_inertiaInv = (inertia.allFinite() && lu.isInvertible()) ? PfxMatrix3(lu.inverse())
                                                              : PfxMatrix3::Zero();
}

const char* PfxRigidBody::problem() const {
  if (!(m_mass >= kPfxMinMass && m_mass <= kPfxMaxMass)) {
    return "mass outside [kPfxMinMass, kPfxMaxMass] (1e-12 to 1e12 kg)";
  }
  if (!m_inertia.allFinite()) return "inertia not finite";
  if ((m_inertia - m_inertia.transpose()).cwiseAbs().maxCoeff() >
      PfxFloat(1e-4) * m_inertia.cwiseAbs().maxCoeff()) {
    return "inertia not symmetric";
  }
  const Eigen::SelfAdjointEigenSolver<PfxMatrix3> eig(m_inertia, Eigen::EigenvaluesOnly);
  // Eigen gives the eigenvalues in increasing order.
  const PfxVector3 moments = eig.eigenvalues();
  if (!(moments[0] > 0)) return "inertia not positive definite";
  if (!(moments[0] >= kPfxMinMoment && moments[2] <= kPfxMaxMoment)) {
    return "a principal moment of inertia outside [kPfxMinMoment, kPfxMaxMoment] (1e-18 to "
           "1e18 kg m^2)";
  }
  if (!(moments[2] - (moments[0] + moments[1]) <= moments[2] * kPfxMomentSumTolerance)) {
    return "principal moments of inertia of no rigid body: the largest exceeds the sum of the "
           "other two by more than kPfxMomentSumTolerance (1e-2) of it";
  }
  // The inverse of a moment lost in rounding (7e37 for the 1.4e-38 of a fuzzed saved file)
  // sent the solver's impulses to infinity.
  if (!(moments[0] >= moments[2] * kPfxMinMomentRatio)) {
    return "smallest principal moment of inertia below kPfxMinMomentRatio (8 epsilon) of the "
           "largest";
  }
  if (!(m_friction >= 0 && pfxIsFinite(m_friction))) return "friction negative or not finite";
  if (!(m_restitution >= 0 && m_restitution <= 1)) return "restitution outside [0, 1]";
  return nullptr;
}

}  // namespace pfx
