// The byte level of the serialized format (README.md, "Serialization"): little-endian
// integers, reals in the writer's precision, sections with their lengths, and the tags that
// locate an error in a file. The writer and the reader of whole worlds sit on top.
#pragma once

#include <cstddef>
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

// FNV-1a, 64 bits: any single changed byte changes it, since every step is a bijection of
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
  void u16(PfxUInt16 v) { little(v, 2); }
  void u32(PfxUInt32 v) { little(v, 4); }
  void u64(PfxUInt64 v) { little(v, 8); }
  void f64(double v);
  // PfxFloat as it is: 4 bytes in the float build, 8 in the double build.
  void real(PfxFloat v);
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
  void little(PfxUInt64 v, int numBytes);
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

  PfxUInt8 u8(const char* field);
  PfxUInt16 u16(const char* field);
  PfxUInt32 u32(const char* field);
  PfxUInt64 u64(const char* field);
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
  // Fails when bytes are left over (a section longer than what it holds).
  bool finish(const char* what);

  // Records the failure with the current tags and `field` (may be null) as the last one.
  bool fail(PfxInt32 code, const char* field, const std::string& reason);

  std::vector<std::string>& tags() { return m_tags; }

 private:
  bool take(std::size_t n, const char* field);
  PfxUInt64 little(int numBytes, const char* field);

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
