// Which field of which parameter set a low-level stage rejected, in words.
//
// Every low-level stage validates its Param before touching anything and returns an error
// code (pfx_common.h). The code says what kind of thing went wrong; the detail says where:
//
//   pfxSetupContactConstraints: PfxSetupContactConstraintsParam::timeStep is 0; it must be
//   positive and finite
//
// Serialization (pfx_serialize.h) writes its failures here too, the place in the file as
// its tags:
//
//   pfxSerializeRead: bodies/body 12/state/position: is nan; it must be finite
//
// A rejected call writes its detail to a buffer of the calling thread and nothing else,
// so the detail of a call made on another thread never shows here. A call that succeeds
// leaves the detail as it was (like errno): read it right after the call that failed.
// Writing the detail takes no heap memory.
#pragma once

namespace pfx {

// The detail of the last call that a low-level stage rejected on this thread, or "" when
// none has been rejected.
const char* pfxGetLastErrorDetail();

}  // namespace pfx
