#pragma once
// Appends worlds to a library file so that killing the writer at any instant loses at most the
// world being written. Not thread-safe: one writer per file, one thread at a time.
#include <chrono>
#include <string>
#include <vector>

#include "library/RunHeader.h"
#include "sim/WorldResult.h"

namespace mwb {

class LibraryWriter {
public:
    /// Creates `path` with `header`, or, if it exists, opens it for appending after checking that
    /// it holds the same run (its run hash) and cutting off a torn last record left by a crash.
    /// Throws LibraryError with the path and reason otherwise.
    LibraryWriter(const std::string& path, const RunHeader& header);
    /// The same, for a caller that has the header's scene already: `gravity` is its gravity
    /// (the writer needs nothing else of it, and the scene JSON is not parsed again).
    LibraryWriter(const std::string& path, const RunHeader& header, const Vec3& gravity);
    ~LibraryWriter();
    LibraryWriter(const LibraryWriter&) = delete;
    LibraryWriter& operator=(const LibraryWriter&) = delete;

    /// Stores an Ok world as a world record or a Rejected one as a rejection record; ignores
    /// Cancelled worlds. Returns after the record reached the file (a killed process cannot lose
    /// it); the disk is flushed at most once a second and when the writer closes.
    void append(const WorldResult& world);
    /// Appends a record exactly as given (merging copies records byte for byte).
    void append_record(uint32_t type, uint32_t version, const std::vector<uint8_t>& payload);

    /// Worlds already in the file when it was opened (for appending more later).
    const std::vector<uint64_t>& existing_world_indices() const { return existing_; }
    /// The run header as in the file (an existing file keeps the engine build that sampled it).
    const RunHeader& header() const { return header_; }
    /// What opening an existing file had to repair (a torn last record), for the user.
    const std::vector<std::string>& repairs() const { return repairs_; }

private:
    std::string path_;
    RunHeader header_;
    Vec3 gravity_;
    int fd_ = -1;
    std::chrono::steady_clock::time_point last_sync_ = std::chrono::steady_clock::now();
    std::vector<uint64_t> existing_;
    std::vector<std::string> repairs_;
};

}  // namespace mwb
