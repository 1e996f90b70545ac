#include "library/WorldRecord.h"

#include <algorithm>
#include <cmath>

#include "library/ByteIO.h"
#include "library/CheckpointBlock.h"

namespace mwb {
namespace {

constexpr size_t kContactBytes = 8 + 4 + 4 + 8;

std::vector<uint8_t> copy_blob(ByteReader& in) {
    const auto [data, size] = in.get_blob();
    return std::vector<uint8_t>(data, data + size);
}

void read_body_list(ByteReader& in, std::vector<uint32_t>& bodies, uint32_t scene_body_count, const char* what) {
    bodies.resize(in.get_count(4));
    for (uint32_t& b : bodies) {
        b = in.get<uint32_t>();
        if (b >= scene_body_count) in.fail(std::string(what) + " body " + std::to_string(b) + " beyond the scene");
    }
}

}  // namespace

StoredWorld decode_world_record(const uint8_t* data, size_t size, uint32_t version, const std::string& where) {
    ByteReader in(data, size, where);
    StoredWorld w;
    w.world_index = in.get<uint64_t>();
    w.seed = in.get<uint64_t>();
    w.parent_world = in.get<int64_t>();
    w.branch_time_s = in.get<double>();
    w.record_hz = in.get<double>();
    w.step_hz = in.get<double>();
    w.first_frame = in.get<uint32_t>();
    w.frame_count = in.get<uint32_t>();
    w.scene_body_count = in.get<uint32_t>();
    w.simulated_time_s = in.get<double>();
    w.impacts_perturbed = in.get<uint32_t>();
    if (!(w.record_hz > 0) || !(w.step_hz > 0) || !std::isfinite(w.simulated_time_s)) in.fail("invalid rates or time");
    const size_t track_count = in.get_count(4 + 4 + 4 + 8);
    w.tracks.resize(track_count);
    for (StoredTrack& t : w.tracks) {
        t.body = in.get<uint32_t>();
        if (t.body >= w.scene_body_count) in.fail("track of body " + std::to_string(t.body) + " beyond the scene");
        t.position = copy_blob(in);
        t.rotation = copy_blob(in);
        t.rest_time_s = in.get<double>();
    }
    const size_t contact_count = in.get_count(kContactBytes);
    w.contacts.resize(contact_count);
    for (ContactEvent& e : w.contacts) {
        e.time_s = in.get<double>();
        e.body = in.get<int32_t>();
        e.other = in.get<int32_t>();
        e.impulse_ns = in.get<double>();
    }
    w.checkpoints = read_packed_checkpoints(in, version);
    const size_t metric_count = in.get_count(4 + 4);
    w.metrics.resize(metric_count);
    for (MetricValues& m : w.metrics) {
        m.name = in.get_string();
        const size_t n = in.get_count(8);
        if (n != track_count) in.fail("metric '" + m.name + "' has " + std::to_string(n) + " values for " +
                                      std::to_string(track_count) + " tracks");
        m.per_body.resize(n);
        for (double& v : m.per_body) v = in.get<double>();
    }
    if (version >= 2) {
        w.root_world = in.get<uint64_t>();
        const size_t steps = in.get_count(8 + 8 + 4);
        w.lineage.resize(steps);
        for (RefineStep& step : w.lineage) {
            step.branch_step = in.get<uint64_t>();
            step.world_index = in.get<uint64_t>();
            read_body_list(in, step.bodies, w.scene_body_count, "refined");
            if (version >= 3) {
                read_body_list(in, step.added, w.scene_body_count, "added");
                read_body_list(in, step.removed, w.scene_body_count, "removed");
            }
        }
        if (!w.lineage.empty() && w.lineage.back().world_index != w.world_index) in.fail("lineage ends at another world");
    }
    if (version >= 3) {
        read_body_list(in, w.absent, w.scene_body_count, "absent");
        for (const StoredTrack& t : w.tracks)
            if (std::find(w.absent.begin(), w.absent.end(), t.body) != w.absent.end())
                in.fail("absent body " + std::to_string(t.body) + " has a track");
    }
    if (in.remaining() != 0) in.fail(std::to_string(in.remaining()) + " unexpected trailing bytes");
    return w;
}

StoredRejection decode_rejection_record(const uint8_t* data, size_t size, const std::string& where) {
    ByteReader in(data, size, where);
    StoredRejection r;
    r.world_index = in.get<uint64_t>();
    r.seed = in.get<uint64_t>();
    r.reason = in.get_string();
    if (in.remaining() != 0) in.fail("unexpected trailing bytes");
    return r;
}

std::vector<Checkpoint> decode_checkpoints(const StoredWorld& world) {
    return inflate_checkpoints(world.checkpoints, "world " + std::to_string(world.world_index) + "'s checkpoints");
}

}  // namespace mwb
