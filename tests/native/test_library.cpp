#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>

#include "SceneFixtures.h"
#include "TestFolder.h"
#include "codec/CodecError.h"
#include "common/BuildInfo.h"
#include "common/QuantizedPolyline.h"
#include "library/ByteIO.h"
#include "library/LibraryFormat.h"
#include "library/LibraryMerge.h"
#include "library/LibraryReader.h"
#include "library/LibraryWriter.h"
#include "library/PolylineGather.h"
#include "library/RunSettings.h"
#include "library/WorldDecoding.h"
#include "library/WorldRecordEncoder.h"
#include "refine/StoredWorldRefinement.h"
#include "sampler/Sampler.h"
#include "scene/SceneJson.h"
#include "sim/PortableRandom.h"
#include "sim/WorldSimulator.h"

namespace mwb {
namespace {

namespace fs = std::filesystem;

class Library : public ::testing::Test {
protected:
    std::string path(const std::string& name) const { return folder_.path(name); }

    static RunHeader header_for(const Scene& scene, uint64_t base_seed = 9, const std::string& build = "") {
        return RunHeader{scene_to_json(scene), SimulationParameters{}, CodecBounds{}, base_seed, build};
    }

    // Samples worlds [first, first + count) of `scene` into `file`; returns them as simulated.
    static std::map<uint64_t, WorldResult> sample_into(const std::string& file, const Scene& scene, uint64_t first,
                                                       uint64_t count, int threads = 2, const std::string& build = "") {
        const RunHeader header = header_for(scene, 9, build);
        CompiledScene compiled(scene, header.parameters);
        LibraryWriter writer(file, header);
        std::map<uint64_t, WorldResult> worlds;
        sample_worlds(compiled, header.base_seed, first, count, threads, [&](WorldResult&& w) {
            writer.append(w);
            worlds.emplace(w.world_index, std::move(w));
        });
        return worlds;
    }

    static std::vector<uint8_t> read_all(const std::string& file) {
        std::ifstream in(file, std::ios::binary);
        return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), {});
    }
    static void write_all(const std::string& file, const std::vector<uint8_t>& bytes) {
        std::ofstream out(file, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    }

    fixtures::TestFolder folder_{"mwb_library_test"};
};

TEST_F(Library, DecodedMotionStaysWithinTheCodecBoundsForEveryBodyAndFrame) {
    for (const Scene& scene : {fixtures::mesh_ramp_with_joints(), fixtures::pile(20, 48)}) {
        const std::string file = path(scene.name + ".mwb");
        const auto simulated = sample_into(file, scene, 0, 4);
        const LibraryReader reader(file);
        ASSERT_EQ(reader.worlds().size(), 4u);
        EXPECT_TRUE(reader.warnings().empty());
        const CodecBounds bounds = reader.header().bounds;
        for (const StoredWorld& stored : reader.worlds()) {
            const WorldResult& original = simulated.at(stored.world_index);
            ASSERT_EQ(stored.frame_count, original.frame_count);
            const std::vector<double> positions = decode_world_positions(stored);
            const std::vector<double> orientations = decode_world_orientations(stored);
            double worst_position = 0, worst_angle = 0;
            for (size_t k = 0; k < positions.size() / 3; ++k) {
                const Vec3 d{positions[3 * k] - original.positions_m[3 * k], positions[3 * k + 1] - original.positions_m[3 * k + 1],
                             positions[3 * k + 2] - original.positions_m[3 * k + 2]};
                worst_position = std::max(worst_position, norm(d));
                const Quat a{orientations[4 * k], orientations[4 * k + 1], orientations[4 * k + 2], orientations[4 * k + 3]};
                const Quat b{original.orientations[4 * k], original.orientations[4 * k + 1], original.orientations[4 * k + 2],
                             original.orientations[4 * k + 3]};
                worst_angle = std::max(worst_angle, quat_angle_between(a, b));
            }
            EXPECT_LE(worst_position, bounds.position_error_max_m) << scene.name;
            EXPECT_LE(worst_angle, bounds.rotation_error_max_rad) << scene.name;
            EXPECT_GT(worst_position, 0.0) << "lossy coding actually happened";
            // Everything else round-trips exactly.
            ASSERT_EQ(stored.contacts.size(), original.contacts.size());
            for (size_t k = 0; k < stored.contacts.size(); ++k) EXPECT_EQ(stored.contacts[k].time_s, original.contacts[k].time_s);
            const std::vector<Checkpoint> checkpoints = decode_checkpoints(stored);
            ASSERT_EQ(checkpoints.size(), original.checkpoints.size());
            EXPECT_EQ(checkpoints.back().bodies.back().orientation, original.checkpoints.back().bodies.back().orientation);
            EXPECT_EQ(stored.tracks.back().rest_time_s, original.rest_time_s.back());
        }
    }
}

TEST_F(Library, EveryBundledSceneDecodesWithinTheBounds) {
    // The regression the codec promises: on every scene we ship, never a frame beyond the bound.
    for (const char* name : {"scenes/quickstart.json", "scenes/all_shapes_and_joints.json", "bench/chain.json",
                             "bench/pile50.json"}) {
        const Scene scene = load_scene_file(std::string(MWB_TEST_DATA_DIR) + "/" + name);
        const std::string file = path("bundled.mwb");
        fs::remove(file);
        const auto simulated = sample_into(file, scene, 0, 2);
        const LibraryReader reader(file);
        ASSERT_EQ(reader.worlds().size(), 2u) << name;
        for (const StoredWorld& stored : reader.worlds()) {
            const WorldResult& original = simulated.at(stored.world_index);
            const std::vector<double> positions = decode_world_positions(stored);
            const std::vector<double> orientations = decode_world_orientations(stored);
            for (size_t k = 0; k < positions.size() / 3; ++k) {
                const Vec3 d{positions[3 * k] - original.positions_m[3 * k], positions[3 * k + 1] - original.positions_m[3 * k + 1],
                             positions[3 * k + 2] - original.positions_m[3 * k + 2]};
                ASSERT_LE(norm(d), reader.header().bounds.position_error_max_m) << name << " value " << k;
                const Quat a{orientations[4 * k], orientations[4 * k + 1], orientations[4 * k + 2], orientations[4 * k + 3]};
                const Quat b{original.orientations[4 * k], original.orientations[4 * k + 1], original.orientations[4 * k + 2],
                             original.orientations[4 * k + 3]};
                ASSERT_LE(quat_angle_between(a, b), reader.header().bounds.rotation_error_max_rad) << name << " value " << k;
            }
        }
    }
}

TEST_F(Library, ABodyThatStaysStillInOneWorldIsStoredAsItMovesInTheNext) {
    // Still bodies' tracks are encoded once per process (the scenery is the same in every world);
    // a world where the same body is elsewhere, or moves in its last frame only, must not get them.
    const Scene scene = fixtures::pile(3, 48);
    const WorldResult simulated = simulate_world(CompiledScene(scene, SimulationParameters{}), 9, 0);
    const size_t frames = simulated.frame_count;
    ASSERT_GT(frames, 10u);
    const auto with_body0 = [&](double z, double last_z) {
        WorldResult w = simulated;
        for (size_t f = 0; f < frames; ++f) {
            const double at[3] = {1.0, 2.0, f + 1 == frames ? last_z : z};
            std::copy(at, at + 3, &w.positions_m[f * 3]);
            const double identity[4] = {1, 0, 0, 0};
            std::copy(identity, identity + 4, &w.orientations[f * 4]);
        }
        return w;
    };
    const CodecBounds bounds;
    const auto decoded_z = [&](const WorldResult& w, std::vector<uint8_t>* bytes = nullptr) {
        const std::vector<uint8_t> record = encode_world_record(w, bounds, scene.world.gravity);
        if (bytes) *bytes = record;
        const std::vector<double> p =
            decode_world_positions(decode_world_record(record.data(), record.size(), kWorldRecordVersion, "test"));
        return std::make_pair(p[2], p[(frames - 1) * 3 + 2]);  // body 0, first and last frame
    };
    std::vector<uint8_t> first, again;
    const auto still = decoded_z(with_body0(3.0, 3.0), &first);
    EXPECT_NEAR(still.first, 3.0, bounds.position_error_max_m);
    EXPECT_NEAR(still.second, 3.0, bounds.position_error_max_m);
    const auto moved_last = decoded_z(with_body0(3.0, 3.5));
    EXPECT_NEAR(moved_last.first, 3.0, bounds.position_error_max_m);
    EXPECT_NEAR(moved_last.second, 3.5, bounds.position_error_max_m) << "a body that moved was stored as still";
    const auto elsewhere = decoded_z(with_body0(4.0, 4.0));
    EXPECT_NEAR(elsewhere.first, 4.0, bounds.position_error_max_m) << "a still body elsewhere got another's track";
    EXPECT_NEAR(elsewhere.second, 4.0, bounds.position_error_max_m);
    decoded_z(with_body0(3.0, 3.0), &again);
    EXPECT_EQ(again, first) << "the same world encodes to the same bytes";
}

TEST_F(Library, PolylineIsDerivedOnLoadFromTheDecodedPath) {
    const std::string file = path("poly.mwb");
    sample_into(file, fixtures::mesh_ramp_with_joints(), 0, 2);
    const LibraryReader reader(file, ReaderOptions{false, 30});
    for (const StoredWorld& world : reader.worlds()) {
        ASSERT_EQ(world.polyline_stride, 4u);  // 120 Hz down to 30 Hz
        ASSERT_EQ(world.polyline_points, (world.frame_count - 1 + 3) / 4 + 1);
        const std::vector<double> positions = decode_world_positions(world);
        const size_t track = world.tracks.size() - 1;
        const uint16_t* block = world.polyline.data() + track * quantized::block_words(world.polyline_points);
        const quantized::Header header = quantized::header(block);
        for (uint32_t p = 0; p < world.polyline_points; ++p) {
            const size_t frame = std::min<size_t>(p * 4, world.frame_count - 1);
            const Vec3 point = quantized::point(header, block, p);
            // Within half a 16-bit step of its bounding box (and the single-precision header).
            for (int k = 0; k < 3; ++k)
                EXPECT_NEAR(point[k], positions[(track * world.frame_count + frame) * 3 + k],
                            header.step[k] * 0.5 + 1e-6);
        }
    }
}

// A loaded world keeps its checkpoints deflated, as stored; they come back whole when asked for,
// and a damaged block is an error naming the world, not a crash.
TEST_F(Library, CheckpointsAreKeptPackedAndInflateToThoseSimulated) {
    const std::string file = path("checkpoints.mwb");
    const auto simulated = sample_into(file, fixtures::pile(6, 24), 0, 2);
    const LibraryReader reader(file);
    ASSERT_EQ(reader.worlds().size(), 2u);
    for (const StoredWorld& stored : reader.worlds()) {
        const WorldResult& original = simulated.at(stored.world_index);
        const std::vector<Checkpoint> checkpoints = decode_checkpoints(stored);
        ASSERT_GE(original.checkpoints.size(), 2u);
        ASSERT_EQ(checkpoints.size(), original.checkpoints.size());
        EXPECT_EQ(checkpoint_count(stored.checkpoints), original.checkpoints.size());
        for (size_t k = 0; k < checkpoints.size(); ++k) {
            EXPECT_EQ(checkpoints[k].step_index, original.checkpoints[k].step_index);
            for (size_t b = 0; b < checkpoints[k].bodies.size(); ++b) {
                EXPECT_EQ(checkpoints[k].bodies[b].position_m, original.checkpoints[k].bodies[b].position_m);
                EXPECT_EQ(checkpoints[k].bodies[b].angular_velocity, original.checkpoints[k].bodies[b].angular_velocity);
            }
        }
        StoredWorld damaged = stored;
        for (size_t k = damaged.checkpoints.packed.size() / 2; k < damaged.checkpoints.packed.size(); ++k)
            damaged.checkpoints.packed[k] ^= 0x5a;
        try {
            decode_checkpoints(damaged);
            FAIL() << "a damaged checkpoint block must not inflate";
        } catch (const LibraryError& error) {
            EXPECT_NE(std::string(error.what()).find("world " + std::to_string(stored.world_index)), std::string::npos)
                << error.what();
        }
        damaged.checkpoints.packed.resize(1);
        EXPECT_THROW(decode_checkpoints(damaged), LibraryError);
    }
}

// A refined world stores only the bodies it re-simulated; its polyline is put together from
// blocks derived on all cores and blocks copied from its parent. Either way it must be the one
// its completed tracks give, whether the parent was read in the same pass or an earlier one.
TEST_F(Library, ARefinedWorldsPolylineIsTheOneItsOwnTracksGive) {
    const std::string file = path("refined.mwb");
    sample_into(file, fixtures::pile(6, 24), 0, 2);
    const auto refine = [&](uint64_t parent, uint32_t body, double branch_s) {
        LibraryReader reader(file);
        LibraryWriter writer(file, reader.header());
        RefineRequest request;
        request.parent_world = parent;
        request.bodies = {body};
        request.branch_time_s = branch_s;
        request.count = 3;
        return refine_stored_world(reader, request, writer).first_child;
    };
    const uint64_t child = refine(0, 5, 0.5);  // the first box (0 is the ground, 1-4 the walls)
    LibraryReader following(file, ReaderOptions{false, 30});  // the parent and children, read at once
    const uint64_t grandchild = refine(child, 6, 1.0);  // another box, from a refined world
    ASSERT_EQ(following.poll(), 3u);  // the grandchildren, whose parent was read before
    const LibraryReader at_once(file, ReaderOptions{false, 30});
    for (const LibraryReader* reader : std::vector<const LibraryReader*>{&following, &at_once}) {
        ASSERT_EQ(reader->worlds().size(), 8u);
        EXPECT_TRUE(reader->warnings().empty());
        for (const StoredWorld& world : reader->worlds()) {
            StoredWorld alone = world;
            derive_polyline(alone, 30);  // every block from the decoded tracks
            EXPECT_EQ(world.polyline, alone.polyline) << "world " << world.world_index;
            EXPECT_EQ(world.polyline_points, alone.polyline_points);
        }
        // An untouched wall's block is the parent's.
        const auto world_of = [&](uint64_t index) -> const StoredWorld& {
            return *std::find_if(reader->worlds().begin(), reader->worlds().end(),
                                 [&](const StoredWorld& w) { return w.world_index == index; });
        };
        const StoredWorld& parent = world_of(child);
        const StoredWorld& refined = world_of(grandchild);
        const size_t words = quantized::block_words(refined.polyline_points);
        const auto block = [&](const StoredWorld& w, size_t body) {
            return std::vector<uint16_t>(w.polyline.begin() + static_cast<std::ptrdiff_t>(body * words),
                                         w.polyline.begin() + static_cast<std::ptrdiff_t>((body + 1) * words));
        };
        EXPECT_EQ(block(refined, 1), block(parent, 1));
    }
}

// The polylines drawn and queried are kept in 16 bits per coordinate: each point comes back
// within half a step of its path's bounding box, however far from the origin the path is.
TEST(QuantizedPolyline, PointsComeBackWithinHalfAStepOfTheirBoundingBox) {
    PortableRandom random(31);
    for (const double offset : {0.0, -37.0, 1000.0}) {
        const uint32_t n = 301;
        std::vector<double> xyz(3 * n);
        for (double& v : xyz) v = offset + random.uniform(-20, 20);
        std::vector<uint16_t> block(quantized::block_words(n));
        quantized::encode(n, [&](uint32_t k, int a) { return xyz[3 * k + a]; }, block.data());
        const quantized::Header h = quantized::header(block.data());
        ASSERT_FALSE(quantized::absent(block.data()));
        for (int a = 0; a < 3; ++a) EXPECT_LT(h.step[a], 40.0 / 65535 * 1.001) << "a step is 1/65535 of the extent";
        for (uint32_t k = 0; k < n; ++k) {
            const Vec3 p = quantized::point(h, block.data(), k);
            for (int a = 0; a < 3; ++a) ASSERT_LE(std::fabs(p[a] - xyz[3 * k + a]), 0.51 * h.step[a]) << offset << " " << k;
        }
    }
}

TEST(QuantizedPolyline, ABodyAtRestStaysPutAndAnAbsentBodyIsMarked) {
    const std::vector<float> rest{1.25f, -3.5f, 0.75f};
    std::vector<uint16_t> block(quantized::block_words(40));
    quantized::encode(40, [&](uint32_t, int a) { return rest[static_cast<size_t>(a)]; }, block.data());
    for (size_t k = 0; k < 40; ++k) {
        const Vec3 p = quantized::point(quantized::header(block.data()), block.data(), k);
        for (int a = 0; a < 3; ++a) EXPECT_EQ(p[a], rest[static_cast<size_t>(a)]);
    }
    quantized::encode_absent(40, block.data());
    EXPECT_TRUE(quantized::absent(block.data()));
}

TEST_F(Library, RandomAccessPoseEqualsTheFullDecode) {
    const std::string file = path("ramp.mwb");
    sample_into(file, fixtures::mesh_ramp_with_joints(), 0, 1);
    const LibraryReader reader(file);
    const StoredWorld& world = reader.worlds().front();
    const std::vector<double> positions = decode_world_positions(world);
    for (size_t track : {size_t{6}, world.tracks.size() - 1}) {
        for (uint32_t frame : {0u, 1u, world.frame_count / 2, world.frame_count - 1}) {
            const Transform pose = decode_pose(world, track, frame);
            const double* p = &positions[(track * world.frame_count + frame) * 3];
            EXPECT_EQ(pose.location, (Vec3{p[0], p[1], p[2]}));
        }
    }
}

// A goal's orientation parts read a body's rotation at every path point: one parse of the track
// must give what the full decode gives, frame for frame.
TEST_F(Library, RotationsAtChosenFramesEqualTheFullDecode) {
    const std::string file = path("ramp_rotations.mwb");
    sample_into(file, fixtures::mesh_ramp_with_joints(), 0, 1);
    const LibraryReader reader(file);
    const StoredWorld& world = reader.worlds().front();
    const std::vector<double> orientations = decode_world_orientations(world);
    const std::vector<uint32_t> frames = {world.frame_count - 1, 0u, 1u, world.frame_count / 2, 1u};
    for (size_t track : {size_t{6}, world.tracks.size() - 1}) {
        const std::vector<Quat> rotations = decode_rotations(world, track, frames);
        ASSERT_EQ(rotations.size(), frames.size());
        for (size_t k = 0; k < frames.size(); ++k) {
            const double* q = &orientations[(track * world.frame_count + frames[k]) * 4];
            EXPECT_EQ(rotations[k], (Quat{q[0], q[1], q[2], q[3]})) << "track " << track << ", frame " << frames[k];
        }
    }
    EXPECT_THROW(decode_rotations(world, 6, {0u, world.frame_count}), CodecError);
}

TEST_F(Library, RejectedWorldsAreCountedWithTheirReasonAndNeverStoredAsWorlds) {
    Scene scene = fixtures::ball_on_plane();
    scene.bodies[1].variation.linear_velocity_min = {0, 0, -900};
    scene.bodies[1].variation.linear_velocity_max = {0, 0, 0};
    const std::string file = path("mixed.mwb");
    const auto simulated = sample_into(file, scene, 0, 12);
    size_t rejected = 0;
    for (const auto& [index, w] : simulated) rejected += w.status == WorldStatus::Rejected;
    ASSERT_GT(rejected, 0u);
    const LibraryReader reader(file);
    EXPECT_EQ(reader.rejections().size(), rejected);
    EXPECT_EQ(reader.worlds().size(), 12 - rejected);
    EXPECT_NE(reader.rejections().front().reason.find("exploded"), std::string::npos);
}

TEST_F(Library, TruncationAnywhereKeepsEveryCompleteRecord) {
    const std::string file = path("full.mwb");
    sample_into(file, fixtures::pile(6, 24), 0, 3, 1);
    const std::vector<uint8_t> bytes = read_all(file);
    const LibraryReader full(file, ReaderOptions{true, 0});
    ASSERT_EQ(full.raw_records().size(), 3u);
    const uint64_t header_end = full.raw_records().front().offset;
    const std::string cut = path("cut.mwb");
    // Every length from just past the header to the end, in steps that hit every record boundary.
    for (uint64_t length = header_end; length <= bytes.size(); length += 97) {
        write_all(cut, std::vector<uint8_t>(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(length)));
        const LibraryReader reader(cut);
        size_t complete = 0;
        for (const RawRecord& r : full.raw_records())
            complete += r.offset + kRecordHeaderBytes + r.payload.size() <= length;
        ASSERT_EQ(reader.worlds().size(), complete) << "length " << length;
        const bool torn = reader.pending_tail_bytes() > 0;
        EXPECT_EQ(torn, !reader.warnings().empty()) << "a torn tail is reported, length " << length;
        if (torn) {
            EXPECT_NE(reader.warnings().front().find("incomplete"), std::string::npos);
        }
    }
}

TEST_F(Library, BitFlipsNeverCrashAndOnlyTheDamagedRecordIsLost) {
    const std::string file = path("full.mwb");
    sample_into(file, fixtures::pile(6, 24), 0, 4, 1);
    const std::vector<uint8_t> bytes = read_all(file);
    const LibraryReader full(file, ReaderOptions{true, 0});
    const uint64_t header_end = full.raw_records().front().offset;
    PortableRandom random(77);
    const std::string damaged = path("damaged.mwb");
    for (int trial = 0; trial < 300; ++trial) {
        std::vector<uint8_t> copy = bytes;
        const size_t at = header_end + static_cast<size_t>(random.uniform01() * static_cast<double>(bytes.size() - header_end));
        copy[at] ^= static_cast<uint8_t>(1u << (random.next_u64() % 8));
        write_all(damaged, copy);
        const LibraryReader reader(damaged);
        EXPECT_EQ(reader.worlds().size(), 3u) << "flip at byte " << at;
        ASSERT_FALSE(reader.warnings().empty());
        EXPECT_NE(reader.warnings().front().find("byte"), std::string::npos) << reader.warnings().front();
    }
}

TEST_F(Library, HeaderDamageIsAClearErrorNamingTheFile) {
    const std::string file = path("ok.mwb");
    sample_into(file, fixtures::ball_on_plane(), 0, 1);
    const std::vector<uint8_t> bytes = read_all(file);
    auto expect_error = [&](std::vector<uint8_t> copy, const std::string& phrase) {
        const std::string bad = path("bad.mwb");
        write_all(bad, copy);
        try {
            LibraryReader reader(bad);
            ADD_FAILURE() << "accepted a file that should fail with: " << phrase;
        } catch (const LibraryError& error) {
            EXPECT_NE(std::string(error.what()).find(bad), std::string::npos) << error.what();
            EXPECT_NE(std::string(error.what()).find(phrase), std::string::npos) << error.what();
        }
    };
    std::vector<uint8_t> magic = bytes;
    magic[1] = 'X';
    expect_error(magic, "not a Many-Worlds library");
    std::vector<uint8_t> version = bytes;
    version[8] = 99;
    expect_error(version, "format version 99");
    std::vector<uint8_t> header = bytes;
    header[30] ^= 0x20;
    expect_error(header, "checksum");
    expect_error(std::vector<uint8_t>(bytes.begin(), bytes.begin() + 20), "truncated");
    expect_error({}, "not a Many-Worlds library");
}

TEST_F(Library, UnknownRecordVersionsAreSkippedWithAMessage) {
    const std::string file = path("future.mwb");
    sample_into(file, fixtures::ball_on_plane(), 0, 1);
    {
        LibraryWriter writer(file, header_for(fixtures::ball_on_plane()));
        writer.append_record(kRecordTypeWorld, 7, {1, 2, 3});
    }
    const LibraryReader reader(file);
    EXPECT_EQ(reader.worlds().size(), 1u);
    ASSERT_EQ(reader.warnings().size(), 1u);
    EXPECT_NE(reader.warnings()[0].find("version 7"), std::string::npos) << reader.warnings()[0];
}

TEST_F(Library, AppendingAfterACrashCutsTheTornRecordAndKeepsTheRest) {
    const Scene scene = fixtures::pile(6, 24);
    const std::string file = path("crashed.mwb");
    sample_into(file, scene, 0, 2, 1);
    std::vector<uint8_t> bytes = read_all(file);
    bytes.resize(bytes.size() - 50);  // the second record is torn
    write_all(file, bytes);
    LibraryWriter writer(file, header_for(scene));
    ASSERT_EQ(writer.repairs().size(), 1u);
    EXPECT_EQ(writer.existing_world_indices().size(), 1u);
    CompiledScene compiled(scene, SimulationParameters{});
    writer.append(simulate_world(compiled, 9, 5));
    const LibraryReader reader(file);
    EXPECT_EQ(reader.worlds().size(), 2u);
    EXPECT_TRUE(reader.warnings().empty());
}

TEST_F(Library, AppendingToAnotherRunIsRefused) {
    const std::string file = path("run.mwb");
    sample_into(file, fixtures::ball_on_plane(), 0, 1);
    EXPECT_THROW(LibraryWriter(file, header_for(fixtures::ball_on_plane(), 10)), LibraryError);
    EXPECT_THROW(LibraryWriter(file, header_for(fixtures::ball_on_plane(3.0))), LibraryError);
}

TEST_F(Library, TheRunSettingsAPersonChoosesDecideWhichLibraryHoldsTheRun) {
    const Scene scene = fixtures::ball_on_plane();
    RunSettings settings;
    settings.seed = 9;
    // The defaults are the parameters' and bounds' own: a run with them is the default header's.
    EXPECT_EQ(run_hash(run_header_for(scene, settings)), run_hash(header_for(scene)));
    const std::string file = path("held.mwb");
    EXPECT_EQ(library_holding(file, run_header_for(scene, settings)), LibraryHolding::New);
    sample_into(file, scene, 0, 1);
    EXPECT_EQ(library_holding(file, run_header_for(scene, settings)), LibraryHolding::Same);
    RunSettings finer = settings;
    finer.rotation_error_deg = 0.25;
    EXPECT_EQ(library_holding(file, run_header_for(scene, finer)), LibraryHolding::Other);
    // What the writer refuses is what library_holding calls another run.
    EXPECT_THROW(LibraryWriter(file, run_header_for(scene, finer)), OtherRunError);
    EXPECT_EQ(read_run_header(file).base_seed, 9u);
}

TEST_F(Library, ReadingOnlyTheHeaderOfADamagedFileIsAnErrorNamingIt) {
    const std::string file = path("short.mwb");
    sample_into(file, fixtures::ball_on_plane(), 0, 1);
    std::vector<uint8_t> bytes = read_all(file);
    for (size_t cut : {size_t{3}, size_t{12}, size_t{20}, size_t{200}}) {
        write_all(file, std::vector<uint8_t>(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(cut)));
        try {
            read_run_header(file);
            ADD_FAILURE() << "a header cut at byte " << cut << " was read";
        } catch (const LibraryError& error) {
            EXPECT_NE(std::string(error.what()).find("short.mwb"), std::string::npos) << error.what();
        }
    }
}

// The one rule for thinning a path, which Library.polylines gathers by and the add-on draws by.
TEST(PolylineThinning, KeepsEveryStrideThPointAndTheLast) {
    EXPECT_EQ(kept_point_indices(10, 4), (std::vector<uint32_t>{0, 4, 8, 9}));
    EXPECT_EQ(kept_point_indices(9, 4), (std::vector<uint32_t>{0, 4, 8}));
    EXPECT_EQ(kept_point_indices(1, 5), (std::vector<uint32_t>{0}));
    EXPECT_TRUE(kept_point_indices(0, 5).empty());
    for (uint32_t points : {2u, 7u, 100u, 1201u})
        for (uint32_t stride : {1u, 2u, 3u, 16u, 5000u}) {
            const std::vector<uint32_t> kept = kept_point_indices(points, stride);
            EXPECT_EQ(kept.size(), kept_point_count(points, stride));
            EXPECT_EQ(kept.front(), 0u);
            EXPECT_EQ(kept.back(), points - 1);
            EXPECT_TRUE(std::is_sorted(kept.begin(), kept.end()));
        }
}

TEST_F(Library, AReaderFollowsAFileWhileItIsWritten) {
    const Scene scene = fixtures::pile(6, 24);
    const std::string file = path("live.mwb");
    CompiledScene compiled(scene, SimulationParameters{});
    LibraryWriter writer(file, header_for(scene));
    LibraryReader follower(file);
    EXPECT_EQ(follower.worlds().size(), 0u);
    writer.append(simulate_world(compiled, 9, 0));
    EXPECT_EQ(follower.poll(), 1u);
    // Half a record: the follower waits for the rest instead of calling it damaged.
    const std::vector<uint8_t> before = read_all(file);
    writer.append(simulate_world(compiled, 9, 1));
    const std::vector<uint8_t> after = read_all(file);
    write_all(file, std::vector<uint8_t>(after.begin(), after.begin() + static_cast<std::ptrdiff_t>(before.size() + 40)));
    EXPECT_EQ(follower.poll(), 0u);
    EXPECT_TRUE(follower.warnings().empty());
    write_all(file, after);
    EXPECT_EQ(follower.poll(), 1u);
    EXPECT_EQ(follower.worlds().back().world_index, 1u);
}

TEST_F(Library, MergedShardsEqualOneRunOverTheWholeRange) {
    const Scene scene = fixtures::mesh_ramp_with_joints();
    sample_into(path("whole.mwb"), scene, 0, 6, 2);
    sample_into(path("shard_b.mwb"), scene, 3, 3, 1);
    sample_into(path("shard_a.mwb"), scene, 0, 3, 2);
    merge_libraries({path("shard_b.mwb"), path("shard_a.mwb")}, path("merged.mwb"));
    merge_libraries({path("whole.mwb")}, path("whole_sorted.mwb"));
    EXPECT_EQ(read_all(path("merged.mwb")), read_all(path("whole_sorted.mwb")));
}

TEST_F(Library, MergeRefusesCollidingSeedsAndOtherRuns) {
    const Scene scene = fixtures::ball_on_plane();
    sample_into(path("a.mwb"), scene, 0, 3);
    sample_into(path("b.mwb"), scene, 2, 3);
    try {
        merge_libraries({path("a.mwb"), path("b.mwb")}, path("out.mwb"));
        FAIL() << "overlapping shards must not merge";
    } catch (const LibraryError& error) {
        EXPECT_NE(std::string(error.what()).find("world 2 in"), std::string::npos) << error.what();
    }
    EXPECT_FALSE(fs::exists(path("out.mwb")));
    sample_into(path("other.mwb"), fixtures::ball_on_plane(3.0), 10, 1);
    EXPECT_THROW(merge_libraries({path("a.mwb"), path("other.mwb")}, path("out.mwb")), LibraryError);
}

TEST_F(Library, AWorldThatDoesNotReproduceNamesBothBuilds) {
    // Worlds stored under a header they were not made with stand for another build's worlds.
    const Scene scene = fixtures::pile(6, 24);
    const std::string file = path("foreign.mwb");
    {
        CompiledScene compiled(scene, SimulationParameters{});
        LibraryWriter writer(file, header_for(scene, 9, "many-worlds 0.0.9; another build"));
        writer.append(simulate_world(compiled, 10, 0));
    }
    LibraryReader reader(file);
    LibraryWriter writer(file, reader.header());
    RefineRequest request;
    request.parent_world = 0;
    request.bodies = {5};  // the first box (0 is the ground, 1-4 the walls)
    request.branch_time_s = 0.5;
    try {
        refine_stored_world(reader, request, writer, [](WorldResult&&) {});
        FAIL() << "a world that does not reproduce must not be refined";
    } catch (const RefineError& error) {
        const std::string message = error.what();
        EXPECT_NE(message.find("another build"), std::string::npos) << message;
        EXPECT_NE(message.find(engine_build()), std::string::npos) << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << "one line: " << message;
    }
}

TEST_F(Library, TheEngineBuildIsRecordedAndShardsOfOtherBuildsMergeWithAWarning) {
    const Scene scene = fixtures::ball_on_plane();
    sample_into(path("farm.mwb"), scene, 0, 2, 2, "many-worlds 0.1.0; farm build");
    sample_into(path("desk.mwb"), scene, 2, 2, 2, "many-worlds 0.1.0; desk build");
    EXPECT_EQ(LibraryReader(path("farm.mwb")).header().engine_build, "many-worlds 0.1.0; farm build");
    // The build is not part of the run: the shards are one run, and appending keeps the file's build.
    EXPECT_EQ(run_hash(LibraryReader(path("farm.mwb")).header()), run_hash(LibraryReader(path("desk.mwb")).header()));
    EXPECT_EQ(LibraryWriter(path("farm.mwb"), header_for(scene, 9, "another")).header().engine_build,
              "many-worlds 0.1.0; farm build");
    const std::vector<std::string> warnings = merge_libraries({path("farm.mwb"), path("desk.mwb")}, path("all.mwb"));
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("desk build"), std::string::npos) << warnings[0];
    EXPECT_NE(warnings[0].find("farm build"), std::string::npos) << warnings[0];
    EXPECT_EQ(LibraryReader(path("all.mwb")).worlds().size(), 4u);
    // Libraries from before builds were recorded read as an unrecorded build, and merge quietly.
    sample_into(path("old_a.mwb"), scene, 0, 1);
    sample_into(path("old_b.mwb"), scene, 1, 1);
    EXPECT_EQ(LibraryReader(path("old_a.mwb")).header().engine_build, "");
    EXPECT_TRUE(merge_libraries({path("old_a.mwb"), path("old_b.mwb")}, path("old.mwb")).empty());
}

}  // namespace
}  // namespace mwb
