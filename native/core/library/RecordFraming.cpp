#include "library/RecordFraming.h"

#include <cstring>

#include "library/FileBytes.h"
#include "library/LibraryFormat.h"

namespace mwb {
namespace {

uint32_t u32_at(const uint8_t* p) {
    uint32_t v;
    std::memcpy(&v, p, 4);
    return v;
}

// A complete, checksummed record starts at `at` of the `size` bytes?
bool valid_record_at(const uint8_t* bytes, size_t size, size_t at) {
    if (size - at < kRecordHeaderBytes) return false;
    const uint8_t* p = bytes + at;
    if (u32_at(p) != kRecordMagic) return false;
    const uint32_t payload = u32_at(p + 12);
    if (payload > kMaxRecordPayloadBytes || size - at - kRecordHeaderBytes < payload) return false;
    const uint32_t crc = crc32_of(p + kRecordHeaderBytes, payload, crc32_of(p + 4, 12));
    return crc == u32_at(p + 16);
}

// First offset after `from` where a valid record starts, or `size`.
size_t find_next_record(const uint8_t* bytes, size_t size, size_t from) {
    for (size_t at = from; at + kRecordHeaderBytes <= size; ++at)
        if (valid_record_at(bytes, size, at)) return at;
    return size;
}

}  // namespace

std::vector<FramedRecord> frame_records(const uint8_t* bytes, size_t size, uint64_t base_offset,
                                        const std::string& path, bool report_incomplete_end, size_t& consumed) {
    std::vector<FramedRecord> records;
    size_t at = 0;
    while (at < size) {
        if (valid_record_at(bytes, size, at)) {
            const uint8_t* p = bytes + at;
            FramedRecord record;
            record.offset = base_offset + at;
            record.type = u32_at(p + 4);
            record.version = u32_at(p + 8);
            record.size = u32_at(p + 12);
            record.payload = p + kRecordHeaderBytes;
            at += kRecordHeaderBytes + record.size;
            records.push_back(std::move(record));
            continue;
        }
        const size_t next = find_next_record(bytes, size, at + 1);
        FramedRecord skipped;
        skipped.offset = base_offset + at;
        if (next == size) {
            // Nothing valid follows: an incomplete last record, perhaps still being written.
            if (report_incomplete_end) {
                skipped.skipped = path + ", byte " + std::to_string(base_offset + at) + ": last record is incomplete (" +
                                  std::to_string(size - at) + " bytes); skipped - the writer was interrupted or is still writing";
                records.push_back(std::move(skipped));
            }
            break;
        }
        skipped.skipped = path + ", byte " + std::to_string(base_offset + at) +
                          ": damaged record (bad magic or checksum); skipped " + std::to_string(next - at) + " bytes";
        records.push_back(std::move(skipped));
        at = next;
    }
    consumed = at;
    return records;
}

}  // namespace mwb
