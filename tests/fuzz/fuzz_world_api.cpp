// The world's API driven call by call on one thread (pfx_fuzz_world_calls.h): every call
// either succeeds and leaves finite states, or is refused and leaves the world as it was.
#include "pfx_fuzz_world_calls.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  pfx_fuzz::ByteReader in(data, size);
  pfx_fuzz::Driver(in, 1).run();
  return 0;
}
