#pragma once
// Which engine build made a library: the version and what decides a world's bits (compiler, ODE
// build, floating-point flags). Written into every new library's run header and shown by `info`,
// so a world that does not reproduce can name both builds.
#include <string>

namespace mwb {

/// For example "many-worlds 0.1.0; gcc 12.2.0; ODE 0.16.2 + libccd 2.1 (Debian source), per-thread
/// random, portable math, -O2 -ffp-contract=off; x86-64 SSE2".
const std::string& engine_build();

/// A recorded build for messages: the text itself, or what an empty record means.
std::string describe_build(const std::string& recorded);

}  // namespace mwb
