// The byte level of the serialized format (README.md, "Serialization"): little-endian
// integers, reals in the writer's precision, sections with their lengths, and the tags that
// locate an error in a file. The writer and the reader of whole worlds sit on top.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <string>
#include <vector>

#include "pfx/base_level/base/pfx_vec_math.h"
#include "pfx/base_level/solver/pfx_constraint_row.h"

namespace pfx {

constexpr char kPfxSerializeMagic[8] = {'P', 'F', 'X', 'W', 'O', 'R', 'L', 'D'};
// Magic, version, bytes per real, three zero bytes, body length, body checksum.
constexpr std::size_t kPfxSerializeHeaderBytes = 32;
// Tag and length in front of every section.
constexpr std::size_t kPfxSectionHeaderBytes = 12;

template <typename T>
inline void pfxStoreLittle(PfxUInt8* to, T v) {
  PfxUInt8 bytes[sizeof(T)];
  std::memcpy(bytes, &v, sizeof(T));
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
  std::reverse(bytes, bytes + sizeof(T));
#endif
  std::memcpy(to, bytes, sizeof(T));
}

template <typename T>
inline T pfxLoadLittle(const PfxUInt8* from) {
  PfxUInt8 bytes[sizeof(T)];
  std::memcpy(bytes, from, sizeof(T));
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
  std::reverse(bytes, bytes + sizeof(T));
#endif
  T v;
  std::memcpy(&v, bytes, sizeof(T));
  return v;
}

// FNV-1a, 64 bits, over the bytes taken eight at a time as little-endian words (the last
// few one by one): any single changed byte changes it, since every step is a bijection of
// the running value.
PfxUInt64 pfxSerializeChecksum(const PfxUInt8* bytes, std::size_t count);

// Where and why a file (or the data to write) was rejected.
struct PfxSerializeError {
  PfxInt32 code = PFX_OK;
  std::vector<std::string> tags;
  std::string reason;
  // "tag/tag/tag: reason"
  std::string describe() const;
};

class PfxByteWriter {
 public:
  void u8(PfxUInt8 v) { m_bytes.push_back(v); }
  void u16(PfxUInt16 v) { little(v); }
  void u32(PfxUInt32 v) { little(v); }
  void u64(PfxUInt64 v) { little(v); }
  void f64(double v) { little(v); }
  // PfxFloat as it is: 4 bytes in the float build, 8 in the double build.
  void real(PfxFloat v) { little(v); }
  void vec3(const PfxVector3& v);
  void quat(const PfxQuat& q);     // x, y, z, w
  void mat3(const PfxMatrix3& m);  // column by column
  void row(const PfxConstraintRow& row);

  // A section: its four-letter tag, then its length, patched by endSection.
  std::size_t beginSection(const char* tag);
  void endSection(std::size_t start);
  void patchU64(std::size_t at, PfxUInt64 v);

  std::vector<PfxUInt8>& bytes() { return m_bytes; }

 private:
  // A value's bytes, least significant first: copied as they lie on a little-endian
  // machine, turned around on a big-endian one.
  template <typename T>
  void little(T v) {
    PfxUInt8 bytes[sizeof(T)];
    pfxStoreLittle(bytes, v);
    m_bytes.insert(m_bytes.end(), bytes, bytes + sizeof(T));
  }
  std::vector<PfxUInt8> m_bytes;
};

// Reads a span of bytes. The first failure sticks: later reads fail too and give zeros, so
// that a parser may check once after a group of fields, but must check before it uses a
// value as a count or an index.
class PfxByteReader {
 public:
  PfxByteReader(const PfxUInt8* data, std::size_t size, std::size_t realBytes,
                PfxSerializeError& error, std::vector<std::string>& tags)
      : m_data(data), m_size(size), m_realBytes(realBytes), m_error(error), m_tags(tags) {}

  bool ok() const { return m_error.code == PFX_OK; }
  std::size_t remaining() const { return m_size - m_at; }
  std::size_t realBytes() const { return m_realBytes; }

  // Fails (once) when fewer than n bytes are left; else moves past them and returns where
  // they start.
  const PfxUInt8* take(std::size_t n, const char* field) {
    if (!ok()) return nullptr;
    if (remaining() < n) {
      shortOf(n, field);
      return nullptr;
    }
    m_at += n;
    return m_data + m_at - n;
  }
  PfxUInt8 u8(const char* field) { return little<PfxUInt8>(field); }
  PfxUInt16 u16(const char* field) { return little<PfxUInt16>(field); }
  PfxUInt32 u32(const char* field) { return little<PfxUInt32>(field); }
  PfxUInt64 u64(const char* field) { return little<PfxUInt64>(field); }
  double f64(const char* field);
  // Rejects NaN and infinity; a double beyond float's range becomes the largest float.
  PfxFloat real(const char* field);
  PfxVector3 vec3(const char* field);
  PfxQuat quat(const char* field);
  PfxMatrix3 mat3(const char* field);
  PfxConstraintRow row(const char* field);
  // A count of elements of at least `minBytesEach` bytes each, rejected when the rest of
  // the span cannot hold them (nothing is allocated for a count a file cannot back).
  PfxUInt32 count(const char* field, std::size_t minBytesEach);

  // Enters the next section, which must carry `tag`; `inner` (sharing this reader's error
  // and tags) reads its payload.
  bool section(const char* tag, PfxByteReader& inner);
  // Whether the next section carries `tag`, without entering it (the optional sections).
  bool nextSectionIs(const char* tag) const {
    return remaining() >= 4 && std::memcmp(m_data + m_at, tag, 4) == 0;
  }
  // Fails when bytes are left over (a section longer than what it holds).
  bool finish(const char* what);

  // Records the failure with the current tags and `field` (may be null) as the last one.
  bool fail(PfxInt32 code, const char* field, const std::string& reason);

  std::vector<std::string>& tags() { return m_tags; }

 private:
  void shortOf(std::size_t n, const char* field);
  // 0 when the bytes are not there.
  template <typename T>
  T little(const char* field) {
    const PfxUInt8* at = take(sizeof(T), field);
    return at ? pfxLoadLittle<T>(at) : T(0);
  }

  const PfxUInt8* m_data;
  std::size_t m_size;
  std::size_t m_at = 0;
  std::size_t m_realBytes;
  PfxSerializeError& m_error;
  std::vector<std::string>& m_tags;
};

// Pushes a tag for the lifetime of the scope.
class PfxTagScope {
 public:
  PfxTagScope(PfxByteReader& reader, std::string tag) : m_tags(reader.tags()) {
    m_tags.push_back(std::move(tag));
  }
  ~PfxTagScope() { m_tags.pop_back(); }
  PfxTagScope(const PfxTagScope&) = delete;
  PfxTagScope& operator=(const PfxTagScope&) = delete;

 private:
  std::vector<std::string>& m_tags;
};

}  // namespace pfx
