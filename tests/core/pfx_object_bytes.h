// The bytes of an object where it lies, to prove that a rejected call wrote nothing to it.
// Comparing against a copy would not do: copying a struct need not copy its padding, and in
// the double build structs such as PfxJoint have padding between their members, so a copy
// can differ bytewise from an object nobody touched.
#pragma once

#include <cstring>
#include <vector>

namespace pfx_test {

template <typename T>
std::vector<unsigned char> objectBytes(const T& object) {
  const auto* bytes = reinterpret_cast<const unsigned char*>(&object);
  return std::vector<unsigned char>(bytes, bytes + sizeof(T));
}

template <typename T>
bool sameBytes(const std::vector<unsigned char>& before, const T& object) {
  return before.size() == sizeof(T) && std::memcmp(before.data(), &object, sizeof(T)) == 0;
}

}  // namespace pfx_test
