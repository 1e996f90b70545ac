#include "library/LibraryReader.h"

#include <algorithm>
#include <cstring>
#include <exception>
#include <optional>

#include <nlohmann/json.hpp>

#include "library/ByteIO.h"
#include "library/FileBytes.h"
#include "library/LibraryFormat.h"
#include "library/RecordFraming.h"
#include "library/SceneRevision.h"
#include "scene/SceneJson.h"
#include "library/WorldDecoding.h"
#include "codec/CodecError.h"
#include "common/QuantizedPolyline.h"

namespace mwb {
namespace {

bool is_world_record(uint32_t type, uint32_t version) {
    return type == kRecordTypeWorld && version >= kOldestWorldRecordVersion && version <= kWorldRecordVersion;
}

// Runs `read`; returns "" or the warning for a record it could not read.
template <typename Read>
std::string warning_from(const std::string& where, Read&& read) {
    try {
        read();
    } catch (const LibraryError& error) {
        return std::string(error.what()) + "; skipped";
    } catch (const CodecError& error) {
        return where + ": " + error.what() + "; skipped";
    } catch (const SceneError& error) {
        return where + ": scene revision: " + error.what() + "; skipped";
    }
    return "";
}

// The file's magic, format version and run header (its length, JSON text and checksum);
// `end` is the offset after them, where the records begin.
RunHeader parse_run_header_block(const std::vector<uint8_t>& bytes, const std::string& path, size_t& end) {
    if (bytes.size() < sizeof kLibraryMagic || std::memcmp(bytes.data(), kLibraryMagic, sizeof kLibraryMagic) != 0)
        throw LibraryError(path + ": not a Many-Worlds library file (bad magic at byte 0)");
    ByteReader in(bytes.data(), bytes.size(), path);
    in.get<uint64_t>();
    const auto version = in.get<uint32_t>();
    if (version != kLibraryFormatVersion)
        throw LibraryError(path + ": library format version " + std::to_string(version) +
                           " is not supported (this build reads version " + std::to_string(kLibraryFormatVersion) + ")");
    const auto size = in.get<uint32_t>();
    if (size > kMaxHeaderBytes || size + 4 > in.remaining())
        throw LibraryError(path + ", byte 12: run header is truncated");
    const uint8_t* text = bytes.data() + in.offset();
    uint32_t crc;
    std::memcpy(&crc, text + size, 4);
    if (crc32_of(text, size) != crc) throw LibraryError(path + ", byte 16: run header checksum mismatch");
    end = in.offset() + size + 4;
    return run_header_from_json(std::string(reinterpret_cast<const char*>(text), size), path);
}

}  // namespace

// A world record as far as it was read on its own: no world if its payload did not decode; an
// error from decoding or from completing it, rethrown when it is accepted in file order.
struct LibraryReader::DecodedWorld {
    std::optional<StoredWorld> world;
    std::exception_ptr error;
    /// A refined world's polyline blocks for the tracks it stores itself, by body (empty for the
    /// others), and the error deriving them: its parent's tracks are only there once it is accepted.
    std::vector<std::vector<uint16_t>> own_blocks;
    std::exception_ptr polyline_error;
};

LibraryReader::LibraryReader(std::string path, const ReaderOptions& options) : path_(std::move(path)), options_(options) {
    load(read_file_from(path_, 0));
}

LibraryReader::LibraryReader(std::string name, const std::vector<uint8_t>& bytes) : path_(std::move(name)) {
    load(bytes);
}

void LibraryReader::load(const std::vector<uint8_t>& bytes) {
    file_size_ = bytes.size();
    read_header(bytes);
    parse_records(bytes.data() + offset_, bytes.size() - offset_, offset_, true);
}

RunHeader read_run_header(const std::string& path) {
    constexpr size_t kLeadBytes = sizeof kLibraryMagic + 8;  // magic, format version, header length
    std::vector<uint8_t> bytes = read_file_prefix(path, kLeadBytes);
    if (bytes.size() == kLeadBytes) {
        uint32_t size;
        std::memcpy(&size, bytes.data() + kLeadBytes - 4, 4);
        if (size <= kMaxHeaderBytes) bytes = read_file_prefix(path, kLeadBytes + size + 4);
    }
    size_t end = 0;
    return parse_run_header_block(bytes, path, end);
}

uint64_t LibraryReader::next_world_index() const {
    uint64_t next = 0;
    for (const StoredWorld& w : worlds_) next = std::max(next, w.world_index + 1);
    for (const StoredRejection& r : rejections_) next = std::max(next, r.world_index + 1);
    return next;
}

void LibraryReader::read_header(const std::vector<uint8_t>& bytes) {
    size_t header_end = 0;
    header_ = parse_run_header_block(bytes, path_, header_end);
    scene_json_ = header_.scene_json;
    try {
        const nlohmann::json scene = nlohmann::json::parse(scene_json_);
        for (const auto& body : scene.at("bodies")) body_names_.push_back(body.at("name").get<std::string>());
        WorldSettings world;
        if (scene.contains("world")) {
            const nlohmann::json& w = scene.at("world");
            world.frame_start = w.value("frame_start", world.frame_start);
            world.frame_end = w.value("frame_end", world.frame_end);
            world.fps = w.value("fps", world.fps);
        }
        const double duration_s = run_duration_s(header_.parameters, world);
        if (!(duration_s >= 0 && duration_s * header_.parameters.record_hz < 1e9))
            throw LibraryError(path_ + ", byte 16: the run header's frame range or duration is not usable");
        run_last_frame_ = mwb::run_last_frame(header_.parameters, world);
    } catch (const nlohmann::json::exception& error) {
        throw LibraryError(path_ + ", byte 16: the run header's scene has no readable body list (" + error.what() + ")");
    }
    offset_ = header_end;
}

void LibraryReader::parse_records(const uint8_t* bytes, size_t size, uint64_t base_offset, bool at_open) {
    size_t consumed = 0;
    const std::vector<FramedRecord> records = frame_records(bytes, size, base_offset, path_, at_open, consumed);
    offset_ = base_offset + consumed;
    std::vector<DecodedWorld> decoded(records.size());
    const auto count = static_cast<std::ptrdiff_t>(records.size());
    // Decoding world records (and a sampled world's polyline) is most of the reading, and each
    // needs only its own bytes: on all cores. Accepting them keeps file order.
#pragma omp parallel for schedule(dynamic, 16)
    for (std::ptrdiff_t k = 0; k < count; ++k) decoded[static_cast<size_t>(k)] = decode_world(records[static_cast<size_t>(k)]);
    for (size_t k = 0; k < records.size(); ++k) accept_record(records[k], std::move(decoded[k]));
}

LibraryReader::DecodedWorld LibraryReader::decode_world(const FramedRecord& record) const {
    DecodedWorld out;
    if (!record.skipped.empty() || !is_world_record(record.type, record.version)) return out;
    const std::string where = path_ + ", record at byte " + std::to_string(record.offset);
    try {
        out.world = decode_world_record(record.payload, record.size, record.version, where);
        // A refined world takes unchanged tracks from its parent: completed once that is accepted.
        if (out.world->parent_world < 0) {
            complete_tracks(*out.world, where);
            derive_world_polyline(*out.world);
        } else {
            derive_own_blocks(out);
        }
    } catch (...) {
        out.error = std::current_exception();
    }
    return out;
}

// The blocks of the tracks a refined world stores (in a search, all of its re-simulated bodies'):
// most of its polyline, and derived here on all cores rather than one by one as it is accepted.
void LibraryReader::derive_own_blocks(DecodedWorld& decoded) const {
    if (options_.polyline_hz <= 0) return;
    const StoredWorld& world = *decoded.world;
    try {
        const PolylineLayout layout = polyline_layout(world, options_.polyline_hz);
        for (const StoredTrack& track : world.tracks) {
            if (!track.present) continue;
            if (track.body >= decoded.own_blocks.size()) decoded.own_blocks.resize(size_t{track.body} + 1);
            decoded.own_blocks[track.body] = track_polyline(track, world.frame_count, layout);
        }
    } catch (...) {
        decoded.polyline_error = std::current_exception();
    }
}

void LibraryReader::accept_record(const FramedRecord& record, DecodedWorld&& decoded) {
    if (!record.skipped.empty()) {
        warnings_.push_back(record.skipped);
        return;
    }
    const std::string where = path_ + ", record at byte " + std::to_string(record.offset);
    bool understood = true;
    const std::string warning = warning_from(where, [&] {
        if (is_world_record(record.type, record.version)) {
            accept_world(std::move(decoded), where);
        } else if (record.type == kRecordTypeSceneRevision && record.version == kSceneRevisionRecordVersion) {
            accept_scene_revision(record.payload, record.size, where);
        } else if (record.type == kRecordTypeRejection && record.version == kRejectionRecordVersion) {
            rejections_.push_back(decode_rejection_record(record.payload, record.size, where));
        } else {
            understood = false;
        }
    });
    if (!understood) {
        warnings_.push_back(where + ": record type " + std::to_string(record.type) + " version " +
                            std::to_string(record.version) + " is not understood by this build; skipped");
        return;
    }
    if (!warning.empty()) {
        warnings_.push_back(warning);
        return;
    }
    if (options_.keep_raw_records)
        raw_.push_back({record.offset, record.type, record.version,
                        std::vector<uint8_t>(record.payload, record.payload + record.size)});
}

void LibraryReader::accept_world(DecodedWorld&& decoded, const std::string& where) {
    if (!decoded.world) std::rethrow_exception(decoded.error);
    StoredWorld& world = *decoded.world;
    if (world.scene_body_count > body_names_.size())
        throw LibraryError(where + ": world " + std::to_string(world.world_index) + " has " +
                           std::to_string(world.scene_body_count) + " bodies, the library's scene " +
                           std::to_string(body_names_.size()) + " (a scene revision is missing)");
    if (decoded.error) std::rethrow_exception(decoded.error);
    if (world.parent_world >= 0) {
        complete_tracks(world, where);
        if (decoded.polyline_error) std::rethrow_exception(decoded.polyline_error);
        if (options_.polyline_hz > 0) {
            // Unchanged tracks of a parent as long have its blocks; the rest were derived already.
            std::vector<std::vector<uint16_t>> known = std::move(decoded.own_blocks);
            known.resize(world.tracks.size());
            const StoredWorld& parent = worlds_[positions_.at(static_cast<uint64_t>(world.parent_world))];
            const PolylineLayout layout = polyline_layout(world, options_.polyline_hz);
            const size_t words = quantized::block_words(layout.points);
            const bool same_layout = parent.frame_count == world.frame_count &&
                                     parent.polyline_points == layout.points && parent.polyline_stride == layout.stride;
            for (size_t t = 0; t < world.tracks.size(); ++t)
                if (known[t].empty() && same_layout && world.tracks[t].inherited && (t + 1) * words <= parent.polyline.size())
                    known[t].assign(parent.polyline.begin() + static_cast<std::ptrdiff_t>(t * words),
                                    parent.polyline.begin() + static_cast<std::ptrdiff_t>((t + 1) * words));
            derive_polyline(world, options_.polyline_hz, known);
        }
    }
    positions_[world.world_index] = worlds_.size();
    worlds_.push_back(std::move(world));
}

void LibraryReader::derive_world_polyline(StoredWorld& world) const {
    if (options_.polyline_hz > 0) derive_polyline(world, options_.polyline_hz);
}

void LibraryReader::accept_scene_revision(const uint8_t* payload, size_t size, const std::string& where) {
    const SceneRevision revision = decode_scene_revision(payload, size, where);
    if (revision.revision != scene_revision_ + 1)
        throw LibraryError(where + ": scene revision " + std::to_string(revision.revision) + " follows revision " +
                           std::to_string(scene_revision_));
    std::vector<std::string> names = scene_body_names(revision.scene_json);
    if (names.size() < body_names_.size() || !std::equal(body_names_.begin(), body_names_.end(), names.begin()))
        throw LibraryError(where + ": scene revision " + std::to_string(revision.revision) +
                           " does not keep the earlier bodies in their order");
    scene_json_ = revision.scene_json;
    body_names_ = std::move(names);
    scene_revision_ = revision.revision;
}

// Completes a world's tracks to one per scene body: its own, absent ones (empty), and for a
// refined world the unchanged ones of its parent, read earlier.
void LibraryReader::complete_tracks(StoredWorld& world, const std::string& where) const {
    const StoredWorld* parent = nullptr;
    if (world.parent_world >= 0) {
        const auto it = positions_.find(static_cast<uint64_t>(world.parent_world));
        if (it == positions_.end())
            throw LibraryError(where + ": its parent world " + std::to_string(world.parent_world) + " is not in this file");
        parent = &worlds_[it->second];
    } else if (world.absent.empty()) {
        return;
    }
    std::vector<StoredTrack> tracks;
    std::vector<MetricValues> metrics = world.metrics;
    for (MetricValues& m : metrics) m.per_body.clear();
    size_t own = 0;
    for (uint32_t body = 0; body < world.scene_body_count; ++body) {
        if (own < world.tracks.size() && world.tracks[own].body == body) {
            tracks.push_back(std::move(world.tracks[own]));
            for (size_t m = 0; m < metrics.size(); ++m) metrics[m].per_body.push_back(world.metrics[m].per_body[own]);
            ++own;
            continue;
        }
        if (std::find(world.absent.begin(), world.absent.end(), body) != world.absent.end()) {
            StoredTrack absent;
            absent.body = body;
            absent.present = false;
            tracks.push_back(std::move(absent));
            for (MetricValues& m : metrics) m.per_body.push_back(0.0);
            continue;
        }
        if (!parent) throw LibraryError(where + ": no track for body " + std::to_string(body));
        if (body >= parent->tracks.size() || !parent->tracks[body].present)
            throw LibraryError(where + ": its parent lacks body " + std::to_string(body));
        StoredTrack inherited = parent->tracks[body];
        inherited.inherited = true;
        tracks.push_back(std::move(inherited));
        for (size_t m = 0; m < metrics.size(); ++m) {
            const auto& parent_metrics = parent->metrics;
            const bool found = m < parent_metrics.size() && parent_metrics[m].name == metrics[m].name;
            metrics[m].per_body.push_back(found ? parent_metrics[m].per_body[body] : 0.0);
        }
    }
    if (own != world.tracks.size()) throw LibraryError(where + ": tracks out of body order");
    world.tracks = std::move(tracks);
    world.metrics = std::move(metrics);
}

size_t LibraryReader::poll() {
    const size_t before = worlds_.size();
    const std::vector<uint8_t> bytes = read_file_from(path_, offset_);
    file_size_ = offset_ + bytes.size();
    parse_records(bytes.data(), bytes.size(), offset_, false);
    return worlds_.size() - before;
}

}  // namespace mwb
