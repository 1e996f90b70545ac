#include "library/CheckpointBlock.h"

#include <cstring>
#include <memory>

#include <zlib.h>

namespace mwb {
namespace {

// Far above any real block (a 1000-body world checkpointed every 0.5 s for 10 min is ~150 MB);
// refuses absurd sizes from corrupted headers before allocating.
constexpr uint64_t kMaxInflatedBytes = uint64_t{1} << 30;
constexpr size_t kBodyStateBytes = 14 * sizeof(double) + sizeof(int32_t);

void put_vec(ByteWriter& out, const double* v, int n) {
    for (int k = 0; k < n; ++k) out.put(v[k]);
}

void get_vec(ByteReader& in, double* v, int n) {
    for (int k = 0; k < n; ++k) v[k] = in.get<double>();
}

}  // namespace

void write_checkpoints(ByteWriter& out, const std::vector<Checkpoint>& checkpoints, uint32_t body_count,
                       uint32_t joint_count) {
    ByteWriter raw;
    raw.put(static_cast<uint32_t>(checkpoints.size()));
    raw.put(body_count);
    raw.put(joint_count);
    for (const Checkpoint& c : checkpoints) {
        raw.put(c.step_index);
        raw.put(c.ode_random_state);
        for (uint64_t word : c.perturbation_random_state) raw.put(word);
        for (uint32_t i = 0; i < body_count; ++i) {
            const BodyState& s = c.bodies[i];
            put_vec(raw, s.position_m.data(), 3);
            put_vec(raw, s.orientation.data(), 4);
            put_vec(raw, s.linear_velocity.data(), 3);
            put_vec(raw, s.angular_velocity.data(), 3);
            raw.put(c.body_rest_since_s[i]);
            raw.put(c.body_impact_partner[i]);
            raw.put(i < c.body_quiet_since_s.size() ? c.body_quiet_since_s[i] : -1.0);
        }
        for (uint32_t j = 0; j < joint_count; ++j) raw.put(c.joint_broken[j]);
    }
    const std::vector<uint8_t>& plain = raw.bytes();
    uLongf packed_size = compressBound(plain.size());
    std::vector<uint8_t> packed(packed_size);
    if (compress2(packed.data(), &packed_size, plain.data(), plain.size(), 6) != Z_OK)
        throw LibraryError("checkpoint compression failed");
    packed.resize(packed_size);
    out.put(static_cast<uint64_t>(plain.size()));
    out.put_blob(packed);
}

namespace {

void check_claimed_size(const ByteReader& in, uint64_t plain_size, size_t packed_size) {
    // Deflate cannot expand data more than 1032:1; a larger claim is corruption, refused before
    // allocating for it.
    if (plain_size > kMaxInflatedBytes || plain_size > uint64_t{packed_size} * 1032 + 64)
        in.fail("checkpoint block claims " + std::to_string(plain_size) + " bytes");
}

std::vector<Checkpoint> inflate(ByteReader& in, uint32_t record_version, uint64_t plain_size, const uint8_t* packed,
                                size_t packed_size) {
    // Version 4 added each body's quiet time (sleeping); earlier worlds never slept.
    const bool has_quiet = record_version >= 4;
    const size_t body_bytes = kBodyStateBytes + (has_quiet ? sizeof(double) : 0);
    check_claimed_size(in, plain_size, packed_size);
    // Not zeroed first: inflating writes every byte.
    const std::unique_ptr<uint8_t[]> plain(new uint8_t[plain_size > 0 ? plain_size : 1]);
    uLongf out_size = plain_size;
    if (uncompress(plain.get(), &out_size, packed, packed_size) != Z_OK || out_size != plain_size)
        in.fail("checkpoint block does not inflate");
    ByteReader raw(plain.get(), plain_size, "checkpoint block");
    const size_t count = raw.get_count(1);
    const auto body_count = raw.get<uint32_t>();
    const auto joint_count = raw.get<uint32_t>();
    const uint64_t per_checkpoint = 6 * 8 + uint64_t{body_count} * body_bytes + joint_count;
    if (count * per_checkpoint > raw.remaining()) raw.fail("checkpoint counts exceed the block");
    std::vector<Checkpoint> checkpoints(count);
    for (Checkpoint& c : checkpoints) {
        c.step_index = raw.get<uint64_t>();
        c.ode_random_state = raw.get<uint64_t>();
        for (uint64_t& word : c.perturbation_random_state) word = raw.get<uint64_t>();
        c.bodies.resize(body_count);
        c.body_rest_since_s.resize(body_count);
        c.body_impact_partner.resize(body_count);
        c.body_quiet_since_s.assign(body_count, -1.0);
        for (uint32_t i = 0; i < body_count; ++i) {
            BodyState& s = c.bodies[i];
            get_vec(raw, s.position_m.data(), 3);
            get_vec(raw, s.orientation.data(), 4);
            get_vec(raw, s.linear_velocity.data(), 3);
            get_vec(raw, s.angular_velocity.data(), 3);
            c.body_rest_since_s[i] = raw.get<double>();
            c.body_impact_partner[i] = raw.get<int32_t>();
            if (has_quiet) c.body_quiet_since_s[i] = raw.get<double>();
        }
        c.joint_broken.resize(joint_count);
        for (uint32_t j = 0; j < joint_count; ++j) c.joint_broken[j] = raw.get<uint8_t>();
    }
    return checkpoints;
}

}  // namespace

PackedCheckpoints read_packed_checkpoints(ByteReader& in, uint32_t record_version) {
    PackedCheckpoints block;
    block.record_version = record_version;
    block.plain_size = in.get<uint64_t>();
    const auto [packed, packed_size] = in.get_blob();
    check_claimed_size(in, block.plain_size, packed_size);
    block.packed.assign(packed, packed + packed_size);
    return block;
}

size_t checkpoint_count(const PackedCheckpoints& block) {
    // The count is the block's first word: inflate that much of the stream and stop.
    uint8_t head[4];
    z_stream stream{};
    stream.next_in = const_cast<Bytef*>(block.packed.data());
    stream.avail_in = static_cast<uInt>(block.packed.size());
    stream.next_out = head;
    stream.avail_out = sizeof head;
    if (inflateInit(&stream) != Z_OK) return 0;
    const int status = inflate(&stream, Z_SYNC_FLUSH);
    const bool whole = (status == Z_OK || status == Z_STREAM_END) && stream.avail_out == 0;
    inflateEnd(&stream);
    if (!whole) return 0;
    uint32_t count;
    std::memcpy(&count, head, sizeof count);
    return count;
}

std::vector<Checkpoint> inflate_checkpoints(const PackedCheckpoints& block, const std::string& what) {
    ByteReader in(block.packed.data(), block.packed.size(), what);
    return inflate(in, block.record_version, block.plain_size, block.packed.data(), block.packed.size());
}

}  // namespace mwb
