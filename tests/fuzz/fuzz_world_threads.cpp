// The calls of fuzz_world_api (pfx_fuzz_world_calls.h) made on one thread and again on two:
// each call must give the same result, the same ray hits and the same world to the byte.
// On two threads a world of several islands is solved a group of islands at a time
// (pfx_island_groups.h) and every stage splits its work, and none of it may show in the
// results.
#include "pfx_fuzz_world_calls.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using pfx_fuzz::CallRecord;
  std::vector<CallRecord> records[2];
  for (pfx::PfxUInt32 threads = 1; threads <= 2; ++threads) {
    pfx_fuzz::ByteReader in(data, size);
    pfx_fuzz::Driver(in, threads, &records[threads - 1]).run();
  }
  const std::vector<CallRecord>& one = records[0];
  const std::vector<CallRecord>& two = records[1];
  for (std::size_t call = 0; call < one.size() && call < two.size(); ++call) {
    if (!(one[call] == two[call])) {
      pfx_fuzz::fail("two threads gave another result than one, at call",
                     std::to_string(call) + " (" + pfx_fuzz::Driver::opName(one[call].op) + ")");
    }
  }
  if (one.size() != two.size()) pfx_fuzz::fail("two threads made another number of calls");
  return 0;
}
