#pragma once
// Finds the framed, checksummed records in bytes read from a library file, and says what lies
// between them that is not a record (damage, or an incomplete last record).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace mwb {

/// A record found in bytes read from a library file; its payload points into those bytes. With
/// `skipped` set it stands for bytes that are not a record and holds the warning about them (kept
/// in line with the records, so a reader reports in file order).
struct FramedRecord {
    uint64_t offset = 0;  ///< of the record header (or of the skipped bytes) in the file
    uint32_t type = 0;
    uint32_t version = 0;
    const uint8_t* payload = nullptr;
    uint32_t size = 0;
    std::string skipped;
};

/// The records in `size` bytes read at file offset `base_offset` of `path`, in file order. Damaged
/// bytes are skipped up to the next valid record. An incomplete last record ends the list; it is
/// reported only with `report_incomplete_end` (a file being opened: when following a file, a
/// writer may still be writing it). `consumed`: bytes taken by the records and skipped damage.
std::vector<FramedRecord> frame_records(const uint8_t* bytes, size_t size, uint64_t base_offset,
                                        const std::string& path, bool report_incomplete_end, size_t& consumed);

}  // namespace mwb
