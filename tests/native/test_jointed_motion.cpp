// Stored motion of jointed bodies and of older libraries: a swinging chain decodes within the
// codec bounds and gives the same bytes on any thread count; a library written before codec
// format 2 (world record version 4) still reads, also once newer worlds are appended to it or one
// of its worlds is refined; a track damaged inside an intact record is reported, never decoded
// into garbage silently.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>

#include "TestFolder.h"
#include "codec/CodecError.h"
#include "library/ByteIO.h"
#include "library/FileBytes.h"
#include "library/LibraryFormat.h"
#include "library/LibraryReader.h"
#include "library/LibraryWriter.h"
#include "library/WorldDecoding.h"
#include "refine/StoredWorldRefinement.h"
#include "sampler/Sampler.h"
#include "scene/SceneJson.h"
#include "sim/WorldSimulator.h"

namespace mwb {
namespace {

namespace fs = std::filesystem;

const std::string kDataDir = MWB_TEST_DATA_DIR;
// Written by the build before codec format 2: `mwb-engine sample --scene tests/bench/chain.json
// --count 1 --duration 0.5 --seed 9`.
const std::string kVersion4Library = kDataDir + "/native/data/chain_record_v4.mwb";

struct WorstError {
    double position_m = 0;
    double angle_rad = 0;
};

// Worst distance between a stored world's decoded motion and the motion as simulated, over every
// body and frame.
WorstError worst_error(const StoredWorld& stored, const WorldResult& simulated) {
    EXPECT_EQ(stored.frame_count, simulated.frame_count);
    const std::vector<double> positions = decode_world_positions(stored);
    const std::vector<double> orientations = decode_world_orientations(stored);
    EXPECT_EQ(positions.size(), simulated.positions_m.size());
    WorstError worst;
    for (size_t k = 0; k < positions.size() / 3 && k < simulated.positions_m.size() / 3; ++k) {
        const double* a = &positions[3 * k];
        const double* b = &simulated.positions_m[3 * k];
        worst.position_m = std::max(worst.position_m, norm(Vec3{a[0] - b[0], a[1] - b[1], a[2] - b[2]}));
        const double* p = &orientations[4 * k];
        const double* q = &simulated.orientations[4 * k];
        worst.angle_rad = std::max(worst.angle_rad, quat_angle_between({p[0], p[1], p[2], p[3]}, {q[0], q[1], q[2], q[3]}));
    }
    return worst;
}

std::vector<uint8_t> read_all(const std::string& file) {
    std::ifstream in(file, std::ios::binary);
    return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), {});
}

void write_all(const std::string& file, const std::vector<uint8_t>& bytes) {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

class JointedMotion : public ::testing::Test {
protected:
    std::string path(const std::string& name) const { return folder_.path(name); }

    // Samples worlds [0, count) of the bench chain into `file` on `threads` threads.
    static std::map<uint64_t, WorldResult> sample_chain(const std::string& file, uint64_t count, int threads) {
        const Scene scene = load_scene_file(kDataDir + "/bench/chain.json");
        const RunHeader header{scene_to_json(scene), SimulationParameters{}, CodecBounds{}, 9, ""};
        CompiledScene compiled(scene, header.parameters);
        LibraryWriter writer(file, header);
        std::map<uint64_t, WorldResult> worlds;
        sample_worlds(compiled, header.base_seed, 0, count, threads, [&](WorldResult&& w) {
            writer.append(w);
            worlds.emplace(w.world_index, std::move(w));
        });
        return worlds;
    }

    fixtures::TestFolder folder_{"mwb_jointed_test"};
};

TEST_F(JointedMotion, ASwingingChainDecodesWithinTheBoundsAndGivesTheSameBytesOnAnyThreadCount) {
    const auto simulated = sample_chain(path("one.mwb"), 4, 1);
    sample_chain(path("two.mwb"), 4, 2);
    const LibraryReader one(path("one.mwb"), ReaderOptions{true, 0});
    const LibraryReader two(path("two.mwb"), ReaderOptions{true, 0});
    ASSERT_EQ(one.worlds().size(), 4u);
    EXPECT_TRUE(one.warnings().empty());
    const CodecBounds bounds = one.header().bounds;
    for (const StoredWorld& stored : one.worlds()) {
        const WorstError worst = worst_error(stored, simulated.at(stored.world_index));
        EXPECT_LE(worst.position_m, bounds.position_error_max_m) << "world " << stored.world_index;
        EXPECT_LE(worst.angle_rad, bounds.rotation_error_max_rad) << "world " << stored.world_index;
        EXPECT_GT(worst.position_m, 0.0) << "lossy coding actually happened";
    }
    // Two threads finish worlds in any order; each world's record must still be the same bytes.
    std::map<uint64_t, std::vector<uint8_t>> payloads;
    for (size_t k = 0; k < one.raw_records().size(); ++k) payloads[one.worlds()[k].world_index] = one.raw_records()[k].payload;
    ASSERT_EQ(two.raw_records().size(), 4u);
    for (size_t k = 0; k < two.raw_records().size(); ++k) {
        EXPECT_EQ(two.raw_records()[k].version, kWorldRecordVersion);
        EXPECT_EQ(two.raw_records()[k].payload, payloads.at(two.worlds()[k].world_index)) << "world " << two.worlds()[k].world_index;
    }
}

TEST_F(JointedMotion, ALibraryWrittenBeforeCodecFormat2StillReadsWithinTheBounds) {
    const LibraryReader reader(kVersion4Library, ReaderOptions{true, 10});
    EXPECT_TRUE(reader.warnings().empty());
    ASSERT_EQ(reader.worlds().size(), 1u);
    ASSERT_EQ(reader.raw_records().size(), 1u);
    ASSERT_EQ(reader.raw_records()[0].version, 4u) << "the fixture must stay a version 4 record";
    // The run header says how the world was made; simulating it again gives the motion stored.
    const RunHeader& header = reader.header();
    const CompiledScene compiled(scene_from_json(header.scene_json), header.parameters);
    const StoredWorld& stored = reader.worlds()[0];
    const WorstError worst = worst_error(stored, simulate_world(compiled, header.base_seed, stored.world_index));
    EXPECT_LE(worst.position_m, header.bounds.position_error_max_m);
    EXPECT_LE(worst.angle_rad, header.bounds.rotation_error_max_rad);
    EXPECT_GT(stored.polyline_points, 0u) << "the paths to draw were derived on load";
}

TEST_F(JointedMotion, NewWorldsAppendedToAnOldLibraryReadAlongsideItsOldOnes) {
    const std::string file = path("grown.mwb");
    fs::copy_file(kVersion4Library, file);
    const RunHeader header = LibraryReader(file).header();
    const CompiledScene compiled(scene_from_json(header.scene_json), header.parameters);
    const WorldResult added = simulate_world(compiled, header.base_seed, 1);
    {
        LibraryWriter writer(file, header);
        writer.append(added);
    }
    const LibraryReader reader(file, ReaderOptions{true, 10});
    EXPECT_TRUE(reader.warnings().empty());
    ASSERT_EQ(reader.worlds().size(), 2u);
    EXPECT_EQ(reader.raw_records()[0].version, 4u);
    EXPECT_EQ(reader.raw_records()[1].version, kWorldRecordVersion);
    for (const StoredWorld& stored : reader.worlds()) {
        const WorstError worst = worst_error(stored, simulate_world(compiled, header.base_seed, stored.world_index));
        EXPECT_LE(worst.position_m, header.bounds.position_error_max_m) << "world " << stored.world_index;
        EXPECT_LE(worst.angle_rad, header.bounds.rotation_error_max_rad) << "world " << stored.world_index;
    }
}

TEST_F(JointedMotion, RefiningAWorldOfAnOldLibraryKeepsItsOldTracksBesideTheNewOnes) {
    const std::string file = path("refined.mwb");
    fs::copy_file(kVersion4Library, file);
    std::vector<WorldResult> children;
    {
        const LibraryReader reader(file);
        LibraryWriter writer(file, reader.header());
        RefineRequest request;
        request.bodies = {10};  // the chain's last link
        request.branch_time_s = 0.25;
        refine_stored_world(reader, request, writer, [&](WorldResult&& child) { children.push_back(std::move(child)); });
    }
    ASSERT_EQ(children.size(), 1u);
    const LibraryReader reader(file, ReaderOptions{true, 10});
    EXPECT_TRUE(reader.warnings().empty());
    ASSERT_EQ(reader.worlds().size(), 2u);
    EXPECT_EQ(reader.raw_records()[1].version, kWorldRecordVersion);
    const StoredWorld& child = reader.worlds()[1];
    ASSERT_EQ(child.parent_world, 0);
    const size_t inherited = std::count_if(child.tracks.begin(), child.tracks.end(), [](const StoredTrack& t) { return t.inherited; });
    EXPECT_GT(inherited, 0u) << "the child stores only what it changed";
    EXPECT_LT(inherited, child.tracks.size());
    const WorstError worst = worst_error(child, children[0]);
    EXPECT_LE(worst.position_m, reader.header().bounds.position_error_max_m);
    EXPECT_LE(worst.angle_rad, reader.header().bounds.rotation_error_max_rad);
}

// Offset, within a world record's payload, of the first byte of track `track`'s position blob
// (the layout of WorldRecordEncoder: 72 bytes of world fields, the track count, then per track
// the body index, the position and rotation blobs, each after its size, and the rest time).
size_t position_track_offset(const StoredWorld& world, size_t track) {
    size_t offset = 8 + 8 + 8 + 8 + 8 + 8 + 4 + 4 + 4 + 8 + 4 + 4;
    for (size_t t = 0; t < track; ++t) offset += 4 + 4 + world.tracks[t].position.size() + 4 + world.tracks[t].rotation.size() + 8;
    return offset + 4 + 4;
}

// The library image with world record `record` given `payload`, its checksum recomputed, as a
// writer that stored damaged tracks would leave it.
std::vector<uint8_t> with_payload(std::vector<uint8_t> bytes, const RawRecord& record, const std::vector<uint8_t>& payload) {
    const size_t at = record.offset + kRecordHeaderBytes;
    std::copy(payload.begin(), payload.end(), bytes.begin() + static_cast<std::ptrdiff_t>(at));
    const uint32_t crc = crc32_of(payload.data(), payload.size(), crc32_of(&bytes[record.offset + 4], 12));
    std::copy_n(reinterpret_cast<const uint8_t*>(&crc), 4, bytes.begin() + static_cast<std::ptrdiff_t>(record.offset + 16));
    return bytes;
}

TEST_F(JointedMotion, ATrackDamagedInsideAnIntactRecordIsReportedWithItsPlace) {
    const std::string file = path("chain.mwb");
    sample_chain(file, 1, 1);
    const std::vector<uint8_t> bytes = read_all(file);
    const LibraryReader intact(file, ReaderOptions{true, 0});
    const RawRecord& record = intact.raw_records().at(0);
    // Track 1 is the first link's (track 0 is the anchor's, which never moves).
    const size_t track = position_track_offset(intact.worlds().at(0), 1);
    const size_t track_bytes = intact.worlds()[0].tracks[1].position.size();
    ASSERT_EQ(std::vector<uint8_t>(record.payload.begin() + static_cast<std::ptrdiff_t>(track),
                                   record.payload.begin() + static_cast<std::ptrdiff_t>(track + track_bytes)),
              intact.worlds()[0].tracks[1].position);

    // A track format this build does not know: the world is skipped with a message on load...
    std::vector<uint8_t> payload = record.payload;
    payload[track] = 0x5F;
    const std::string damaged = path("damaged.mwb");
    write_all(damaged, with_payload(bytes, record, payload));
    const LibraryReader skipping(damaged, ReaderOptions{false, 10});
    EXPECT_TRUE(skipping.worlds().empty());
    ASSERT_EQ(skipping.warnings().size(), 1u);
    const std::string& warning = skipping.warnings()[0];
    EXPECT_NE(warning.find(damaged), std::string::npos) << warning;
    EXPECT_NE(warning.find("record at byte " + std::to_string(record.offset)), std::string::npos) << warning;
    EXPECT_NE(warning.find("format version"), std::string::npos) << warning;
    // ...and decoding it on demand throws the codec's error instead of returning motion.
    const LibraryReader lazy(damaged);
    ASSERT_EQ(lazy.worlds().size(), 1u);
    EXPECT_THROW(decode_world_positions(lazy.worlds()[0]), CodecError);

    // Flipped bits anywhere in the track: skipped with a codec message or decoded to finite
    // motion (a flipped residual is indistinguishable from other motion); never a crash.
    for (size_t bit = 0; bit < 8 * track_bytes; bit += 3) {
        std::vector<uint8_t> flipped = record.payload;
        flipped[track + bit / 8] ^= static_cast<uint8_t>(1u << (bit % 8));
        write_all(damaged, with_payload(bytes, record, flipped));
        const LibraryReader reader(damaged, ReaderOptions{false, 10});
        if (reader.worlds().empty()) {
            ASSERT_EQ(reader.warnings().size(), 1u);
            EXPECT_NE(reader.warnings()[0].find("codec: "), std::string::npos) << reader.warnings()[0];
            continue;
        }
        for (double value : decode_world_positions(reader.worlds()[0])) {
            ASSERT_FALSE(std::isinf(value)) << "bit " << bit;
        }
    }
}

}  // namespace
}  // namespace mwb
