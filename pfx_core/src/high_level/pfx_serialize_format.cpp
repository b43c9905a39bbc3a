#include "high_level/pfx_serialize_format.h"

#include <cmath>
#include <cstring>
#include <limits>

namespace pfx {

PfxUInt64 pfxSerializeChecksum(const PfxUInt8* bytes, std::size_t count) {
  constexpr PfxUInt64 kPrime = 0x100000001b3ull;
  PfxUInt64 hash = 0xcbf29ce484222325ull;
  std::size_t i = 0;
  for (; i + 8 <= count; i += 8) {
    hash ^= pfxLoadLittle<PfxUInt64>(bytes + i);
    hash *= kPrime;
  }
  for (; i < count; ++i) {
    hash ^= bytes[i];
    hash *= kPrime;
  }
  return hash;
}

std::string PfxSerializeError::describe() const {
  std::string text;
  for (std::size_t i = 0; i < tags.size(); ++i) {
    if (i > 0) text += '/';
    text += tags[i];
  }
  return text.empty() ? reason : text + ": " + reason;
}

void PfxByteWriter::vec3(const PfxVector3& v) {
  for (int i = 0; i < 3; ++i) real(v[i]);
}

void PfxByteWriter::quat(const PfxQuat& q) {
  real(q.x());
  real(q.y());
  real(q.z());
  real(q.w());
}

void PfxByteWriter::mat3(const PfxMatrix3& m) {
  for (int c = 0; c < 3; ++c) {
    for (int r = 0; r < 3; ++r) real(m(r, c));
  }
}

void PfxByteWriter::row(const PfxConstraintRow& row) {
  vec3(row.m_normal);
  real(row.m_rhs);
  real(row.m_jacDiagInv);
  real(row.m_lowerLimit);
  real(row.m_upperLimit);
  real(row.m_accumImpulse);
}

std::size_t PfxByteWriter::beginSection(const char* tag) {
  for (int i = 0; i < 4; ++i) u8(static_cast<PfxUInt8>(tag[i]));
  const std::size_t start = m_bytes.size();
  u64(0);
  return start;
}

void PfxByteWriter::endSection(std::size_t start) { patchU64(start, m_bytes.size() - start - 8); }

void PfxByteWriter::patchU64(std::size_t at, PfxUInt64 v) {
  pfxStoreLittle(m_bytes.data() + at, v);
}

bool PfxByteReader::fail(PfxInt32 code, const char* field, const std::string& reason) {
  if (!ok()) return false;
  m_error.code = code;
  m_error.tags = m_tags;
  if (field) m_error.tags.emplace_back(field);
  m_error.reason = reason;
  return false;
}

void PfxByteReader::shortOf(std::size_t n, const char* field) {
  fail(PFX_ERR_OUT_OF_BUFFER, field,
       "the data ends " + std::to_string(n - remaining()) + " bytes short of it");
}

double PfxByteReader::f64(const char* field) {
  const double v = little<double>(field);
  if (!std::isfinite(v)) {
    fail(PFX_ERR_INVALID_VALUE, field, "is " + std::to_string(v) + "; it must be finite");
    return 0;
  }
  return v;
}

PfxFloat PfxByteReader::real(const char* field) {
  const double v = m_realBytes == 4 ? double(little<float>(field)) : little<double>(field);
  if (!std::isfinite(v)) {
    fail(PFX_ERR_INVALID_VALUE, field, "is " + std::to_string(v) + "; it must be finite");
    return 0;
  }
  constexpr double kLargest = std::numeric_limits<PfxFloat>::max();
  if (std::abs(v) > kLargest) return static_cast<PfxFloat>(std::copysign(kLargest, v));
  return static_cast<PfxFloat>(v);
}

PfxVector3 PfxByteReader::vec3(const char* field) {
  PfxVector3 v;
  for (int i = 0; i < 3; ++i) v[i] = real(field);
  return v;
}

PfxQuat PfxByteReader::quat(const char* field) {
  const PfxFloat x = real(field), y = real(field), z = real(field), w = real(field);
  return PfxQuat(w, x, y, z);
}

PfxMatrix3 PfxByteReader::mat3(const char* field) {
  PfxMatrix3 m;
  for (int c = 0; c < 3; ++c) {
    for (int r = 0; r < 3; ++r) m(r, c) = real(field);
  }
  return m;
}

PfxConstraintRow PfxByteReader::row(const char* field) {
  PfxConstraintRow row;
  row.m_normal = vec3(field);
  row.m_rhs = real(field);
  row.m_jacDiagInv = real(field);
  row.m_lowerLimit = real(field);
  row.m_upperLimit = real(field);
  row.m_accumImpulse = real(field);
  // The impulse the next step warm starts with, held to the rule of body velocities
  // (PfxRigidState::isValid): no step leaves one whose square overflows, and one of 1e200
  // N s made its bodies' velocities infinite in the first step.
  if (ok() && !pfxIsFinite(row.m_accumImpulse * row.m_accumImpulse)) {
    fail(PFX_ERR_INVALID_VALUE, field,
         "has an impulse of " + std::to_string(row.m_accumImpulse) +
             " N s, whose square overflows");
  }
  return row;
}

PfxUInt32 PfxByteReader::count(const char* field, std::size_t minBytesEach) {
  const PfxUInt32 n = u32(field);
  if (!ok()) return 0;
  if (PfxUInt64(n) * minBytesEach > remaining()) {
    fail(PFX_ERR_OUT_OF_RANGE, field,
         "is " + std::to_string(n) + ", more than the " + std::to_string(remaining()) +
             " bytes left can hold");
    return 0;
  }
  return n;
}

bool PfxByteReader::section(const char* tag, PfxByteReader& inner) {
  const PfxUInt8* found = take(4, "section tag");
  if (!found) return false;
  if (std::memcmp(found, tag, 4) != 0) {
    return fail(PFX_ERR_INVALID_FLAG, "section tag",
                "is '" + std::string(reinterpret_cast<const char*>(found), 4) + "', expected '" +
                    std::string(tag, 4) + "'");
  }
  const PfxUInt64 length = u64("section length");
  if (!ok()) return false;
  if (length > remaining()) {
    return fail(PFX_ERR_OUT_OF_BUFFER, "section length",
                "is " + std::to_string(length) + " bytes, but only " + std::to_string(remaining()) +
                    " are left");
  }
  inner.m_data = m_data + m_at;
  inner.m_size = static_cast<std::size_t>(length);
  inner.m_at = 0;
  inner.m_realBytes = m_realBytes;
  m_at += static_cast<std::size_t>(length);
  return true;
}

bool PfxByteReader::finish(const char* what) {
  if (!ok()) return false;
  if (remaining() != 0) {
    return fail(PFX_ERR_OUT_OF_RANGE, what,
                std::to_string(remaining()) + " bytes are left over after it");
  }
  return true;
}

}  // namespace pfx
