#pragma once
// The one exception every codec read path throws on malformed input, so callers can tell a
// corrupted or truncated buffer apart from a programming error.
#include <stdexcept>
#include <string>

namespace mwb {

/// Thrown when a compressed buffer is truncated, corrupted, or of an unknown format version.
class CodecError : public std::runtime_error {
public:
    explicit CodecError(const std::string& message) : std::runtime_error("codec: " + message) {}
};

}  // namespace mwb
