#include "pfx/base_level/collision/pfx_mass_properties.h"

#include "pfx/base_level/collision/pfx_shape.h"

namespace pfx {

namespace {

// Volume, centre of mass and second moment ∫ x xᵀ dV of a solid convex mesh, all in the
// mesh frame. Each outward triangle (a, b, c) closes a tetrahedron with a reference point
// o; the signed volumes and moments of these tetrahedra add up to the solid's (divergence
// theorem), whatever side of a face o lies on.
struct MeshIntegrals {
  double volume = 0;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  Eigen::Matrix3d secondMomentAboutCentroid = Eigen::Matrix3d::Zero();
};

MeshIntegrals integrateConvexMesh(const PfxConvexMesh& mesh) {
  // o at the middle of the bounds keeps the products small, so the cancellation in the
  // final shift to the centroid loses little precision.
  const Eigen::Vector3d origin = mesh.m_aabbCenter.cast<double>();

  // ∫ x xᵀ over the tetrahedron (0, e1, e2, e3) is (1/120)(ones + identity); a tetrahedron
  // (0, a, b, c) is its image under A = [a b c], so its moment is det(A) A C Aᵀ.
  const Eigen::Matrix3d canonical =
      (Eigen::Matrix3d::Ones() + Eigen::Matrix3d::Identity()) / 120.0;

  double sixVolume = 0;
  Eigen::Vector3d weightedCentroid = Eigen::Vector3d::Zero();
  Eigen::Matrix3d secondMoment = Eigen::Matrix3d::Zero();
  for (PfxUInt32 t = 0; t < mesh.m_numFacets; ++t) {
    Eigen::Matrix3d corners;
    for (int k = 0; k < 3; ++k) {
      corners.col(k) = mesh.m_verts[mesh.m_facetVertIds[t][k]].cast<double>() - origin;
    }
    const double det = corners.determinant();  // six times the signed volume
    sixVolume += det;
    weightedCentroid += det * corners.rowwise().sum() / 4.0;
    secondMoment += det * corners * canonical * corners.transpose();
  }

  MeshIntegrals result;
  if (sixVolume <= 0) return result;
  result.volume = sixVolume / 6.0;
  const Eigen::Vector3d centroidFromOrigin = weightedCentroid / sixVolume;
  result.centroid = origin + centroidFromOrigin;
  result.secondMomentAboutCentroid =
      secondMoment - result.volume * centroidFromOrigin * centroidFromOrigin.transpose();
  return result;
}

// Inertia from the second moment S = ∫ x xᵀ dm: I = tr(S) E - S.
PfxMatrix3 inertiaFromSecondMoment(const Eigen::Matrix3d& secondMoment) {
  const Eigen::Matrix3d inertia =
      secondMoment.trace() * Eigen::Matrix3d::Identity() - secondMoment;
  return inertia.cast<PfxFloat>();
}

PfxMatrix3 diagonalMatrix(PfxFloat xx, PfxFloat yy, PfxFloat zz) {
  return PfxVector3(xx, yy, zz).asDiagonal().toDenseMatrix();
}

PfxFloat sphereVolume(PfxFloat radius) {
  return PfxFloat(4) / PfxFloat(3) * PFX_PI * radius * radius * radius;
}

PfxFloat cylinderVolume(PfxFloat halfLength, PfxFloat radius) {
  return PFX_PI * radius * radius * PfxFloat(2) * halfLength;
}

}  // namespace

PfxMatrix3 pfxCalcInertiaSphere(PfxFloat radius, PfxFloat mass) {
  return PfxMatrix3::Identity() * (PfxFloat(2) / PfxFloat(5) * mass * radius * radius);
}

PfxMatrix3 pfxCalcInertiaBox(const PfxVector3& halfExtent, PfxFloat mass) {
  // m (b² + c²) / 12 with full extents b = 2 hy, c = 2 hz is m (hy² + hz²) / 3.
  const PfxVector3 sq = halfExtent.cwiseProduct(halfExtent);
  const PfxFloat third = mass / PfxFloat(3);
  return diagonalMatrix(third * (sq[1] + sq[2]), third * (sq[0] + sq[2]), third * (sq[0] + sq[1]));
}

PfxMatrix3 pfxCalcInertiaCylinder(PfxFloat halfLength, PfxFloat radius, PfxFloat mass) {
  // Axial m r²/2; transverse m (3 r² + L²)/12 with L = 2 h.
  const PfxFloat axial = mass * radius * radius / PfxFloat(2);
  const PfxFloat transverse =
      mass * (radius * radius / PfxFloat(4) + halfLength * halfLength / PfxFloat(3));
  return diagonalMatrix(axial, transverse, transverse);
}

PfxMatrix3 pfxCalcInertiaCapsule(PfxFloat halfLength, PfxFloat radius, PfxFloat mass) {
  // Mass splits by volume between the cylinder (π r² 2h) and the two caps (4/3 π r³);
  // π r² cancels, which keeps a zero-radius capsule (a rod) well defined.
  const PfxFloat cylinderShare = PfxFloat(3) * halfLength;
  const PfxFloat capsShare = PfxFloat(2) * radius;
  if (cylinderShare + capsShare <= 0) return PfxMatrix3::Zero();
  const PfxFloat cylinderMass = mass * cylinderShare / (cylinderShare + capsShare);
  const PfxFloat capsMass = mass - cylinderMass;

  // A hemisphere's centroid lies 3r/8 from its flat face. About an axis through the flat
  // face's centre its transverse inertia is (2/5) m r², as for the full sphere; moving it to
  // the hemisphere's own centroid subtracts m (3r/8)², and moving it on to the capsule's
  // centre, h + 3r/8 away, adds m (h + 3r/8)². Together: m (2r²/5 + h² + 3hr/4).
  const PfxFloat r2 = radius * radius;
  const PfxFloat capsAxial = PfxFloat(2) / PfxFloat(5) * capsMass * r2;
  const PfxFloat capsTransverse =
      capsMass * (PfxFloat(2) / PfxFloat(5) * r2 + halfLength * halfLength +
                  PfxFloat(3) / PfxFloat(4) * halfLength * radius);
  return pfxCalcInertiaCylinder(halfLength, radius, cylinderMass) +
         diagonalMatrix(capsAxial, capsTransverse, capsTransverse);
}

PfxMatrix3 pfxMassTranslate(PfxFloat mass, const PfxMatrix3& inertia, const PfxVector3& offset) {
  return inertia +
         mass * (offset.squaredNorm() * PfxMatrix3::Identity() - offset * offset.transpose());
}

PfxFloat pfxCalcVolume(const PfxShape& shape) {
  switch (shape.getType()) {
    case kPfxShapeSphere: return sphereVolume(shape.getSphere().m_radius);
    case kPfxShapeBox: {
      const PfxVector3& half = shape.getBox().m_half;
      return PfxFloat(8) * half[0] * half[1] * half[2];
    }
    case kPfxShapeCapsule: {
      const PfxCapsule capsule = shape.getCapsule();
      return cylinderVolume(capsule.m_halfLen, capsule.m_radius) + sphereVolume(capsule.m_radius);
    }
    case kPfxShapeCylinder: {
      const PfxCylinder cylinder = shape.getCylinder();
      return cylinderVolume(cylinder.m_halfLen, cylinder.m_radius);
    }
    case kPfxShapeConvexMesh: {
      const PfxConvexMesh* mesh = shape.getConvexMesh();
      return mesh ? static_cast<PfxFloat>(integrateConvexMesh(*mesh).volume) : PfxFloat(0);
    }
    // A large mesh is an open surface for static ground: it encloses nothing.
    default: return 0;
  }
}

PfxMassProperties pfxCalcMassPropertiesConvexMesh(const PfxConvexMesh& mesh, PfxFloat density) {
  const MeshIntegrals integrals = integrateConvexMesh(mesh);
  PfxMassProperties result;
  result.mass = static_cast<PfxFloat>(density * integrals.volume);
  result.centerOfMass = integrals.centroid.cast<PfxFloat>();
  result.inertia = inertiaFromSecondMoment(double(density) * integrals.secondMomentAboutCentroid);
  return result;
}

PfxMassProperties pfxCalcMassProperties(const PfxShape& shape, PfxFloat density) {
  PfxMassProperties local;
  local.centerOfMass.setZero();
  local.inertia.setZero();
  local.mass = density * pfxCalcVolume(shape);
  switch (shape.getType()) {
    case kPfxShapeSphere:
      local.inertia = pfxCalcInertiaSphere(shape.getSphere().m_radius, local.mass);
      break;
    case kPfxShapeBox: local.inertia = pfxCalcInertiaBox(shape.getBox().m_half, local.mass); break;
    case kPfxShapeCapsule: {
      const PfxCapsule capsule = shape.getCapsule();
      local.inertia = pfxCalcInertiaCapsule(capsule.m_halfLen, capsule.m_radius, local.mass);
      break;
    }
    case kPfxShapeCylinder: {
      const PfxCylinder cylinder = shape.getCylinder();
      local.inertia = pfxCalcInertiaCylinder(cylinder.m_halfLen, cylinder.m_radius, local.mass);
      break;
    }
    case kPfxShapeConvexMesh:
      if (shape.getConvexMesh()) {
        local = pfxCalcMassPropertiesConvexMesh(*shape.getConvexMesh(), density);
      }
      break;
    default: local.mass = 0; break;
  }

  // The inertia stays about the shape's own centre of mass; only its axes turn into the body
  // frame. Moving it to another point is the compound's job.
  const PfxMatrix3 rotation = shape.getOffsetOrientation().toRotationMatrix();
  PfxMassProperties result;
  result.mass = local.mass;
  result.centerOfMass = shape.getOffsetPosition() + rotation * local.centerOfMass;
  result.inertia = pfxRotateInertia(rotation, local.inertia);
  return result;
}

PfxMassProperties pfxCalcMassPropertiesCompound(const PfxShape* shapes, const PfxFloat* densities,
                                                PfxUInt32 numShapes) {
  PfxMassProperties result;
  result.mass = 0;
  result.centerOfMass.setZero();
  result.inertia.setZero();
  if (!shapes || !densities) return result;

  // Two passes: the common centre must be known before any part's inertia can be moved to it.
  PfxVector3 weightedCenter = PfxVector3::Zero();
  for (PfxUInt32 i = 0; i < numShapes; ++i) {
    const PfxMassProperties part = pfxCalcMassProperties(shapes[i], densities[i]);
    result.mass += part.mass;
    weightedCenter += part.mass * part.centerOfMass;
  }
  if (result.mass <= 0) {
    result.mass = 0;
    return result;
  }
  result.centerOfMass = weightedCenter / result.mass;
  for (PfxUInt32 i = 0; i < numShapes; ++i) {
    const PfxMassProperties part = pfxCalcMassProperties(shapes[i], densities[i]);
    result.inertia +=
        pfxMassTranslate(part.mass, part.inertia, part.centerOfMass - result.centerOfMass);
  }
  return result;
}

}  // namespace pfx
