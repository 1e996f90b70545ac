#include "library/WorldRecordEncoder.h"

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
        out.put_blob(encode_position_track(&world.positions_m[b * frames * 3], world.frame_count, 1.0 / world.record_hz,
                                           gravity, bounds.position_error_max_m));
        out.put_blob(encode_rotation_track(&world.orientations[b * frames * 4], world.frame_count,
                                           bounds.rotation_error_max_rad));
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
