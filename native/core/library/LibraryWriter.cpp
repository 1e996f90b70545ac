#include "library/LibraryWriter.h"

#include <fcntl.h>
#include <sys/stat.h>
#ifdef _WIN32
#include <io.h>
#define WIN32_LEAN_AND_MEAN
#include <windows.h>
#else
#include <sys/file.h>
#include <unistd.h>
#endif

#include <algorithm>
#include <chrono>
#include <cerrno>
#include <cstring>

#include "library/ByteIO.h"
#include "library/FileBytes.h"
#include "library/LibraryFormat.h"
#include "library/LibraryReader.h"
#include "library/WorldRecordEncoder.h"
#include "scene/SceneJson.h"

namespace mwb {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what) {
    throw LibraryError(path + ": " + what + " (" + std::strerror(errno) + ")");
}

// The few file operations that differ between POSIX and Windows (MinGW-w64's C runtime).
#ifdef _WIN32
bool holds_bytes(const std::string& path) {
    struct _stati64 info{};
    return ::_stati64(path.c_str(), &info) == 0 && info.st_size > 0;
}

int open_for_writing(const std::string& path) {
    return ::_open(path.c_str(), _O_WRONLY | _O_CREAT | _O_BINARY | _O_NOINHERIT, _S_IREAD | _S_IWRITE);
}

// Windows locks are mandatory: a lock on the records would stop readers (a viewer following the
// file). One byte far beyond the end of any library is locked instead, which only writers ask for.
bool lock_for_writing(int fd) {
    OVERLAPPED far_byte{};
    far_byte.Offset = 0xfffffffeu;
    far_byte.OffsetHigh = 0x7fffffffu;
    return ::LockFileEx(reinterpret_cast<HANDLE>(::_get_osfhandle(fd)), LOCKFILE_EXCLUSIVE_LOCK | LOCKFILE_FAIL_IMMEDIATELY,
                        0, 1, 0, &far_byte) != 0;
}

bool cut_at(int fd, uint64_t size) { return ::_chsize_s(fd, static_cast<__int64>(size)) == 0; }
bool seek_to_end(int fd) { return ::_lseeki64(fd, 0, SEEK_END) >= 0; }
bool flush_to_disk(int fd) { return ::_commit(fd) == 0; }
#else
bool holds_bytes(const std::string& path) {
    struct stat info{};
    return ::stat(path.c_str(), &info) == 0 && info.st_size > 0;
}

int open_for_writing(const std::string& path) { return ::open(path.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC, 0644); }
bool lock_for_writing(int fd) { return ::flock(fd, LOCK_EX | LOCK_NB) == 0; }
bool cut_at(int fd, uint64_t size) { return ::ftruncate(fd, static_cast<off_t>(size)) == 0; }
bool seek_to_end(int fd) { return ::lseek(fd, 0, SEEK_END) >= 0; }
bool flush_to_disk(int fd) { return ::fdatasync(fd) == 0; }
#endif

void write_all(int fd, const std::vector<uint8_t>& bytes, const std::string& path) {
    size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) fail(path, "write failed");
        done += static_cast<size_t>(n);
    }
}

std::vector<uint8_t> file_prologue(const RunHeader& header) {
    const std::string json = run_header_to_json(header);
    ByteWriter out;
    out.put_bytes(reinterpret_cast<const uint8_t*>(kLibraryMagic), sizeof kLibraryMagic);
    out.put(kLibraryFormatVersion);
    out.put(static_cast<uint32_t>(json.size()));
    out.put_bytes(reinterpret_cast<const uint8_t*>(json.data()), json.size());
    out.put(crc32_of(reinterpret_cast<const uint8_t*>(json.data()), json.size()));
    return std::move(out.bytes());
}

}  // namespace

LibraryWriter::LibraryWriter(const std::string& path, const RunHeader& header)
    : LibraryWriter(path, header, scene_from_json(header.scene_json).world.gravity) {}

LibraryWriter::LibraryWriter(const std::string& path, const RunHeader& header, const Vec3& gravity)
    : path_(path), header_(header), gravity_(gravity) {
    const bool exists = holds_bytes(path);
    uint64_t intact_end = 0;
    if (exists) {
        LibraryReader existing(path);
        if (run_hash(existing.header()) != run_hash(header))
            throw OtherRunError(path + ": holds another run (different scene, parameters, codec bounds or base seed; run " +
                               run_hash(existing.header()) + ", expected " + run_hash(header) + ")");
        header_.engine_build = existing.header().engine_build;
        for (const StoredWorld& w : existing.worlds()) existing_.push_back(w.world_index);
        for (const StoredRejection& r : existing.rejections()) existing_.push_back(r.world_index);
        std::sort(existing_.begin(), existing_.end());
        intact_end = existing.file_size() - existing.pending_tail_bytes();
        if (existing.pending_tail_bytes() > 0)
            repairs_.push_back(path + ": cut off an incomplete last record of " +
                               std::to_string(existing.pending_tail_bytes()) + " bytes at byte " + std::to_string(intact_end));
    }
    fd_ = open_for_writing(path);
    if (fd_ < 0) fail(path, "cannot open for writing");
    // One writer per file: a second one would interleave records.
    if (!lock_for_writing(fd_)) {
        ::close(fd_);
        fd_ = -1;
        throw LibraryError(path + ": another process is writing this library");
    }
    if (exists) {
        if (!cut_at(fd_, intact_end)) fail(path, "cannot cut off the torn record");
    } else {
        write_all(fd_, file_prologue(header), path);
        if (!flush_to_disk(fd_)) fail(path, "flush failed");
    }
    if (!seek_to_end(fd_)) fail(path, "seek failed");
}

LibraryWriter::~LibraryWriter() {
    if (fd_ >= 0) {
        flush_to_disk(fd_);
        ::close(fd_);
    }
}

void LibraryWriter::append(const WorldResult& world) {
    if (world.status == WorldStatus::Ok) {
        append_record(kRecordTypeWorld, kWorldRecordVersion, encode_world_record(world, header_.bounds, gravity_));
    } else if (world.status == WorldStatus::Rejected) {
        append_record(kRecordTypeRejection, kRejectionRecordVersion, encode_rejection_record(world));
    }
}

void LibraryWriter::append_record(uint32_t type, uint32_t version, const std::vector<uint8_t>& payload) {
    if (payload.size() > kMaxRecordPayloadBytes) throw LibraryError(path_ + ": record too large");
    ByteWriter out;
    out.put(kRecordMagic);
    out.put(type);
    out.put(version);
    out.put(static_cast<uint32_t>(payload.size()));
    const uint32_t crc = crc32_of(payload.data(), payload.size(), crc32_of(out.bytes().data() + 4, 12));
    out.put(crc);
    out.put_bytes(payload.data(), payload.size());
    // One write per record: killing the process leaves at most this record incomplete (the
    // kernel keeps what was written). Flushing to the disk, against power loss, costs
    // milliseconds, so it happens at most once a second and when the writer closes.
    write_all(fd_, out.bytes(), path_);
    const auto now = std::chrono::steady_clock::now();
    if (now - last_sync_ >= std::chrono::seconds(1)) {
        if (!flush_to_disk(fd_)) fail(path_, "flush failed");
        last_sync_ = now;
    }
}

}  // namespace mwb
