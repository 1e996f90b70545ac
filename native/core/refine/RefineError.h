#pragma once
// Why a refinement cannot be made.
#include <stdexcept>

namespace mwb {

/// A request that does not fit the library (no such world, a body it lacks, a world that does not
/// reproduce); the message is one line.
struct RefineError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// A stored world that does not come out as stored when simulated again: the library was made by
/// another engine build (or is damaged). No refinement of that library can succeed, so callers
/// that try several requests (the goal search) stop on it.
struct WorldNotReproduced : RefineError {
    using RefineError::RefineError;
};

}  // namespace mwb
