#pragma once
// Reads a library file: the run header, every intact world, and a clear account of anything that
// was not (torn last record, checksum mismatch, unknown record versions). Can follow a file that
// is still being written.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "library/RecordFraming.h"
#include "library/RunHeader.h"
#include "library/WorldRecord.h"

namespace mwb {

/// One framed record as found in the file.
struct RawRecord {
    uint64_t offset = 0;  ///< of the record header in the file
    uint32_t type = 0;
    uint32_t version = 0;
    std::vector<uint8_t> payload;
};

struct ReaderOptions {
    bool keep_raw_records = false;  ///< keep every record's bytes (for merging)
    /// > 0: decode each world on load and derive its down-sampled polyline at about this rate;
    /// a world whose tracks do not decode is then skipped with a warning.
    double polyline_hz = 0;
};

/// The run header of the library at `path`, read without its records. Throws LibraryError as
/// LibraryReader does for a file that is not a library or whose header is damaged.
RunHeader read_run_header(const std::string& path);

class LibraryReader {
public:
    /// Opens `path` and reads everything intact. Throws LibraryError (path and offset in the
    /// message) when the file is not a library, is of an unknown format version, or its header is
    /// damaged. Damaged records are skipped and reported in warnings(), never thrown.
    explicit LibraryReader(std::string path, const ReaderOptions& options = {});
    /// Reads a library image already in memory; `name` stands for the file in messages. Such a
    /// reader has no file to poll.
    LibraryReader(std::string name, const std::vector<uint8_t>& bytes);

    const std::string& path() const { return path_; }
    const RunHeader& header() const { return header_; }
    /// The library's scene now: the header's, or the latest scene revision (bodies added later
    /// are appended, so body indices hold across revisions).
    const std::string& scene_json() const { return scene_json_; }
    size_t scene_body_count() const { return body_names_.size(); }
    /// The run's last recorded frame: a world that ends earlier (at rest) holds its final pose up
    /// to this frame, and no world has a pose beyond it.
    uint64_t run_last_frame() const { return run_last_frame_; }
    /// 0 while the scene is the header's.
    uint32_t scene_revision() const { return scene_revision_; }
    const std::vector<StoredWorld>& worlds() const { return worlds_; }
    const std::vector<StoredRejection>& rejections() const { return rejections_; }
    /// First world index after every world, stored or rejected: where a run's new worlds go.
    uint64_t next_world_index() const;
    /// Records as read, when constructed with keep_raw_records (for merging).
    const std::vector<RawRecord>& raw_records() const { return raw_; }
    const std::vector<std::string>& warnings() const { return warnings_; }
    /// Bytes at the end that do not (yet) form a complete record.
    uint64_t pending_tail_bytes() const { return file_size_ - offset_; }
    uint64_t file_size() const { return file_size_; }

    /// Reads records appended since the last read; returns how many new worlds arrived. An
    /// incomplete last record is left for the next poll (a writer may still be writing it).
    size_t poll();

private:
    struct DecodedWorld;

    void load(const std::vector<uint8_t>& bytes);
    void read_header(const std::vector<uint8_t>& bytes);
    /// Reads the records in `size` bytes at file offset `base_offset`: frames them in order, decodes
    /// world records on all cores, then accepts everything in file order.
    void parse_records(const uint8_t* bytes, size_t size, uint64_t base_offset, bool at_open);
    /// The part of reading a world record that needs no other record: decoding it, and for a
    /// sampled world (no parent) completing its tracks and deriving its polyline.
    DecodedWorld decode_world(const FramedRecord& record) const;
    void derive_own_blocks(DecodedWorld& decoded) const;
    void accept_record(const FramedRecord& record, DecodedWorld&& decoded);
    void accept_world(DecodedWorld&& decoded, const std::string& where);
    void derive_world_polyline(StoredWorld& world) const;
    /// One track per scene body of the world: a refined world stores only changed bodies (the rest
    /// come from its parent, read earlier), and bodies it lacks get empty, absent tracks.
    void complete_tracks(StoredWorld& world, const std::string& where) const;
    void accept_scene_revision(const uint8_t* payload, size_t size, const std::string& where);

    std::string path_;
    ReaderOptions options_;
    RunHeader header_;
    std::string scene_json_;
    std::vector<std::string> body_names_;
    uint32_t scene_revision_ = 0;
    uint64_t run_last_frame_ = 0;
    std::vector<StoredWorld> worlds_;
    std::map<uint64_t, size_t> positions_;  ///< world index -> position in worlds_
    std::vector<StoredRejection> rejections_;
    std::vector<RawRecord> raw_;
    std::vector<std::string> warnings_;
    uint64_t offset_ = 0;     ///< first byte not yet consumed
    uint64_t file_size_ = 0;
};

}  // namespace mwb
