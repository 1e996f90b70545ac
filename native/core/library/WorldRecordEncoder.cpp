#include "library/WorldRecordEncoder.h"

#include <array>
#include <cstring>
#include <map>
#include <mutex>
#include <utility>

#include "codec/PositionEncoder.h"
#include "codec/RotationEncoder.h"
#include "library/ByteIO.h"
#include "library/CheckpointBlock.h"

namespace mwb {
namespace {

void put_body_list(ByteWriter& out, const std::vector<uint32_t>& bodies) {
    out.put(static_cast<uint32_t>(bodies.size()));
    for (uint32_t b : bodies) out.put(b);
}

// The encoded tracks of bodies that stay exactly where they are for a whole world: the scenery a
// scene keeps as passive bodies (treads, strings, walls, pegs) is the same in every world, and
// searching its tracks' segments anew took a seventh of each sampled staircase world's time (99
// of its 110 bodies). Each such pair of tracks is encoded once per process; a track that moves by
// a single bit anywhere is encoded as usual.
class StillTrackCache {
public:
    using Tracks = std::pair<std::vector<uint8_t>, std::vector<uint8_t>>;

    Tracks encode(const double* xyz_m, const double* wxyz, uint32_t frame_count, double frame_dt_s,
                  const Vec3& gravity, const CodecBounds& bounds) {
        if (frame_count < 2 || !still(xyz_m, 3, frame_count) || !still(wxyz, 4, frame_count))
            return {encode_position_track(xyz_m, frame_count, frame_dt_s, gravity, bounds.position_error_max_m),
                    encode_rotation_track(wxyz, frame_count, bounds.rotation_error_max_rad)};
        // Everything the two encoders read, bit for bit.
        Key key{};
        size_t k = 0;
        for (int i = 0; i < 3; ++i) key[k++] = bits(xyz_m[i]);
        for (int i = 0; i < 4; ++i) key[k++] = bits(wxyz[i]);
        for (int i = 0; i < 3; ++i) key[k++] = bits(gravity[i]);
        key[k++] = frame_count;
        key[k++] = bits(frame_dt_s);
        key[k++] = bits(bounds.position_error_max_m);
        key[k++] = bits(bounds.rotation_error_max_rad);
        {
            const std::lock_guard<std::mutex> lock(mutex_);
            const auto it = cache_.find(key);
            if (it != cache_.end()) return it->second;
        }
        Tracks tracks{encode_position_track(xyz_m, frame_count, frame_dt_s, gravity, bounds.position_error_max_m),
                      encode_rotation_track(wxyz, frame_count, bounds.rotation_error_max_rad)};
        const std::lock_guard<std::mutex> lock(mutex_);
        // A bound on memory for a process that goes through many scenes: start over.
        if (cache_.size() >= kMaxEntries) cache_.clear();
        cache_.emplace(key, tracks);
        return tracks;
    }

private:
    static constexpr size_t kMaxEntries = 4096;
    using Key = std::array<uint64_t, 14>;

    static uint64_t bits(double value) {
        uint64_t b;
        std::memcpy(&b, &value, sizeof b);
        return b;
    }

    // Whether every frame's `width` values equal the first frame's, bit for bit.
    static bool still(const double* values, size_t width, uint32_t frame_count) {
        for (uint32_t f = 1; f < frame_count; ++f)
            if (std::memcmp(values + f * width, values, width * sizeof(double)) != 0) return false;
        return true;
    }

    std::mutex mutex_;
    std::map<Key, Tracks> cache_;
};

StillTrackCache& still_tracks() {
    static StillTrackCache cache;
    return cache;
}

}  // namespace

std::vector<uint8_t> encode_world_record(const WorldResult& world, const CodecBounds& bounds, const Vec3& gravity) {
    // A refined world stores only the bodies that moved differently from its parent.
    std::vector<uint32_t> stored, absent;
    for (uint32_t b = 0; b < world.body_count; ++b) {
        if (b < world.present.size() && !world.present[b]) absent.push_back(b);
        else if (world.lineage.empty() || (b < world.changed.size() && world.changed[b])) stored.push_back(b);
    }
    const int64_t parent = world.lineage.empty() ? -1
                           : world.lineage.size() == 1 ? static_cast<int64_t>(world.root_world)
                                                       : static_cast<int64_t>(world.lineage[world.lineage.size() - 2].world_index);
    ByteWriter out;
    out.put(world.world_index);
    out.put(world.seed);
    out.put(parent);
    out.put(world.lineage.empty() ? 0.0 : static_cast<double>(world.lineage.back().branch_step) / world.step_hz);
    out.put(world.record_hz);
    out.put(world.step_hz);
    out.put(world.first_frame);
    out.put(world.frame_count);
    out.put(world.body_count);
    out.put(world.simulated_time_s);
    out.put(world.impacts_perturbed);
    out.put(static_cast<uint32_t>(stored.size()));
    const size_t frames = world.frame_count;
    for (uint32_t b : stored) {
        out.put(b);
        const StillTrackCache::Tracks tracks =
            still_tracks().encode(&world.positions_m[b * frames * 3], &world.orientations[b * frames * 4],
                                  world.frame_count, 1.0 / world.record_hz, gravity, bounds);
        out.put_blob(tracks.first);
        out.put_blob(tracks.second);
        out.put(world.rest_time_s[b]);
    }
    out.put(static_cast<uint32_t>(world.contacts.size()));
    for (const ContactEvent& e : world.contacts) {
        out.put(e.time_s);
        out.put(e.body);
        out.put(e.other);
        out.put(e.impulse_ns);
    }
    const uint32_t joint_count = world.checkpoints.empty() ? 0u : static_cast<uint32_t>(world.checkpoints[0].joint_broken.size());
    write_checkpoints(out, world.checkpoints, world.body_count, joint_count);
    const std::vector<MetricValues> metrics = compute_body_metrics(world);
    out.put(static_cast<uint32_t>(metrics.size()));
    for (const MetricValues& m : metrics) {
        out.put_string(m.name);
        out.put(static_cast<uint32_t>(stored.size()));
        for (uint32_t b : stored) out.put(m.per_body[b]);
    }
    out.put(world.root_world);
    out.put(static_cast<uint32_t>(world.lineage.size()));
    for (const RefineStep& step : world.lineage) {
        out.put(step.branch_step);
        out.put(step.world_index);
        put_body_list(out, step.bodies);
        put_body_list(out, step.added);
        put_body_list(out, step.removed);
    }
    put_body_list(out, absent);
    return std::move(out.bytes());
}

std::vector<uint8_t> encode_rejection_record(const WorldResult& world) {
    ByteWriter out;
    out.put(world.world_index);
    out.put(world.seed);
    out.put_string(world.reject_reason);
    return std::move(out.bytes());
}

}  // namespace mwb
