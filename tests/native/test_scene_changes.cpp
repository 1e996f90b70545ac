// Bodies added to or removed from sampled worlds: small scenes whose outcome is known.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>

#include "SceneFixtures.h"
#include "TestFolder.h"
#include "WorldCompare.h"
#include "codec/CodecError.h"
#include "common/BuildInfo.h"
#include "library/LibraryFormat.h"
#include "library/LibraryMerge.h"
#include "library/LibraryReader.h"
#include "library/LibraryWriter.h"
#include "library/SceneRevision.h"
#include "library/WorldDecoding.h"
#include "sampler/Sampler.h"
#include "scene/BodyChanges.h"
#include "scene/SceneJson.h"
#include "sim/CompiledScene.h"
#include "sim/WorldSimulator.h"

namespace mwb {
namespace {

constexpr uint32_t kGround = 0, kLower = 1, kUpper = 2, kFar = 3;

using compare::position;
using compare::same_track;

Vec3 final_position(const WorldResult& w, size_t body) { return position(w, body, w.frame_count - 1); }

// Ground, a box resting on another (Lower, Upper: 0.4 m cubes) and a box far away, for 2 s.
Scene stack() {
    Scene s;
    s.name = "stack";
    s.world.frame_end = 49;
    s.bodies.push_back(fixtures::ground());
    s.bodies.push_back(fixtures::box("Lower", {0, 0, 0.2}));
    s.bodies.push_back(fixtures::box("Upper", {0, 0, 0.6}));
    s.bodies.push_back(fixtures::box("Far", {5, 5, 0.2}));
    return s;
}

SimulationParameters full_length() {
    SimulationParameters p;
    p.stop_at_rest = false;  // every world lasts the whole scene, so tracks compare frame by frame
    return p;
}

std::map<uint64_t, WorldResult> children_of(const CompiledScene& compiled, const std::vector<WorldResult>& chain,
                                            const RefineStep& first, size_t count, int threads) {
    std::vector<RefineStep> steps;
    for (size_t k = 0; k < count; ++k) {
        steps.push_back(first);
        steps.back().world_index = first.world_index + k;
    }
    std::map<uint64_t, WorldResult> out;
    refine_worlds(compiled, 7, chain, steps, threads, [&](WorldResult&& w) { out.emplace(w.world_index, std::move(w)); });
    return out;
}

TEST(SceneChanges, RemovingTheLowerBoxDropsTheUpperOneAndKeepsTheRest) {
    CompiledScene compiled(stack(), full_length());
    const std::vector<WorldResult> chain = simulate_lineage(compiled, 7, 0, {});
    const WorldResult& parent = chain.back();
    ASSERT_NEAR(final_position(parent, kUpper)[2], 0.6, 0.01) << "Upper rests on Lower";
    const auto children = children_of(compiled, chain, {0, 20, {}, {}, {kLower}}, 3, 2);
    ASSERT_EQ(children.size(), 3u);
    for (const auto& [index, child] : children) {
        ASSERT_EQ(child.status, WorldStatus::Ok) << child.reject_reason;
        EXPECT_EQ(child.present[kLower], 0);
        EXPECT_EQ(child.changed[kUpper], 1) << "Lower's ghost finds the box it held";
        EXPECT_NEAR(final_position(child, kUpper)[2], 0.2, 0.01) << "Upper falls to the ground";
        EXPECT_EQ(child.changed[kFar], 0);
        EXPECT_TRUE(same_track(child, parent, kFar)) << "Far replays its parent bit for bit";
        for (const ContactEvent& e : child.contacts) EXPECT_NE(e.body, static_cast<int32_t>(kLower));
    }
}

// The bodies a scene gains after sampling are appended; worlds sampled before must not change.
Scene stack_with_ball() {
    Scene s = stack();
    Body ball = fixtures::sphere("Ball", {0, 0, 2.0}, 0.15);
    ball.variation.location_min_m = {-0.02, -0.02, 0};
    ball.variation.location_max_m = {0.02, 0.02, 0};
    s.bodies.push_back(ball);
    return s;
}
constexpr uint32_t kBall = 4;

TEST(SceneChanges, SampledWorldsComeOutTheSameInTheGrownScene) {
    CompiledScene sampled(stack(), full_length());
    CompiledScene grown(stack_with_ball(), full_length(), stack().bodies.size());
    for (uint64_t world : {0, 1, 2}) {
        const WorldResult before = simulate_world(sampled, 7, world);
        const WorldResult after = simulate_world(grown, 7, world);
        ASSERT_EQ(after.frame_count, before.frame_count);
        EXPECT_EQ(after.present[kBall], 0);
        for (uint32_t b = 0; b < before.body_count; ++b) EXPECT_TRUE(same_track(after, before, b)) << b;
        EXPECT_EQ(after.contacts.size(), before.contacts.size());
    }
}

TEST(SceneChanges, AnAddedBallFallsFromTheStartAndWakesTheBoxItHits) {
    CompiledScene compiled(stack_with_ball(), full_length(), stack().bodies.size());
    const std::vector<WorldResult> chain = simulate_lineage(compiled, 7, 0, {});
    const WorldResult& parent = chain.back();
    const auto children = children_of(compiled, chain, {0, 30, {}, {kBall}, {}}, 4, 2);
    std::vector<Vec3> starts;
    for (const auto& [index, child] : children) {
        ASSERT_EQ(child.status, WorldStatus::Ok) << child.reject_reason;
        EXPECT_EQ(child.present[kBall], 1);
        EXPECT_EQ(child.changed[kBall], 1);
        EXPECT_LT(final_position(child, kBall)[2], 1.2) << "the ball fell onto the stack or past it";
        EXPECT_EQ(child.changed[kUpper], 1) << "the ball hits Upper";
        EXPECT_EQ(child.changed[kFar], 0);
        EXPECT_TRUE(same_track(child, parent, kFar));
        starts.push_back(position(child, kBall, 0));
    }
    EXPECT_NE(starts[0], starts[1]) << "each new world draws the ball's start from its own variation";
    // A world with the ball is reproduced from its lineage, and refining it later keeps its past.
    const WorldResult& child = children.begin()->second;
    std::vector<WorldResult> again = simulate_lineage(compiled, 7, 0, child.lineage);
    EXPECT_EQ(hash_world(again.back()), hash_world(child));
    const uint32_t spf = compiled.steps_per_frame();
    const WorldResult grandchild = refine_world(compiled, 7, again, {24 * spf, 40, {kBall}});
    ASSERT_EQ(grandchild.status, WorldStatus::Ok);
    EXPECT_EQ(grandchild.present[kBall], 1);
    for (uint32_t b = 0; b < grandchild.body_count; ++b)
        for (size_t f = 0; f < 25; ++f) EXPECT_EQ(position(grandchild, b, f), position(child, b, f)) << b << " " << f;
}

TEST(SceneChanges, AnAddedWallStopsARollingBall) {
    Scene scene;
    scene.world.frame_end = 73;
    scene.bodies.push_back(fixtures::ground());
    Body ball = fixtures::sphere("Ball", {0, 0, 0.3}, 0.3);
    ball.initial_linear_velocity = {3, 0, 0};
    ball.initial_angular_velocity = {0, 10, 0};
    scene.bodies.push_back(ball);
    const size_t sampled = scene.bodies.size();
    Body wall = fixtures::box("Wall", {2, 0, 0.5}, {0.1, 2, 0.5});
    wall.type = BodyType::Passive;
    scene.bodies.push_back(wall);
    CompiledScene compiled(scene, full_length(), sampled);
    const std::vector<WorldResult> chain = simulate_lineage(compiled, 7, 0, {});
    ASSERT_GT(final_position(chain.back(), 1)[0], 3.0) << "without the wall the ball rolls on";
    const WorldResult child = refine_world(compiled, 7, chain, {0, 10, {}, {2}, {}});
    ASSERT_EQ(child.status, WorldStatus::Ok);
    EXPECT_EQ(child.changed[1], 1) << "the passive wall wakes the ball it touches";
    EXPECT_LT(final_position(child, 1)[0], 1.95) << "and the ball stays in front of it";
}

TEST(SceneChanges, RemovingAnAnchorFreesTheBodyJointedToIt) {
    Scene scene = stack();
    Body anchor = fixtures::box("Anchor", {-3, 0, 2.0});
    Body hung = fixtures::box("Hung", {-3, 0, 1.5});
    scene.bodies.push_back(anchor);
    scene.bodies.push_back(hung);
    Constraint weld;  // Anchor fixed in the air
    weld.name = "Weld";
    weld.body_a = "Anchor";
    weld.frame.location = {-3, 0, 2.0};
    scene.constraints.push_back(weld);
    Constraint link;  // Hung fixed to Anchor
    link.name = "Link";
    link.body_a = "Anchor";
    link.body_b = "Hung";
    link.frame.location = {-3, 0, 1.75};
    scene.constraints.push_back(link);
    CompiledScene compiled(scene, full_length());
    const std::vector<WorldResult> chain = simulate_lineage(compiled, 7, 0, {});
    ASSERT_NEAR(final_position(chain.back(), 5)[2], 1.5, 0.02) << "Hung hangs from Anchor";
    const WorldResult child = refine_world(compiled, 7, chain, {0, 10, {}, {}, {4}});
    ASSERT_EQ(child.status, WorldStatus::Ok);
    EXPECT_EQ(child.changed[5], 1);
    EXPECT_NEAR(final_position(child, 5)[2], 0.2, 0.02) << "without its anchor Hung falls to the ground";
    EXPECT_TRUE(same_track(child, chain.back(), kUpper));
}

TEST(SceneChanges, AddingAndRemovingGiveTheSameWorldsOnAnyThreadCount) {
    CompiledScene compiled(stack_with_ball(), full_length(), stack().bodies.size());
    const std::vector<WorldResult> chain = simulate_lineage(compiled, 7, 1, {});
    for (const RefineStep& step : {RefineStep{0, 50, {}, {kBall}, {}}, RefineStep{0, 60, {}, {kBall}, {kLower}}}) {
        std::map<uint64_t, uint64_t> one, two;
        for (const auto& [index, w] : children_of(compiled, chain, step, 4, 1)) one[index] = hash_world(w);
        for (const auto& [index, w] : children_of(compiled, chain, step, 4, 2)) two[index] = hash_world(w);
        EXPECT_EQ(one, two);
    }
}

TEST(SceneChanges, ImpossibleChangesAreRefusedWithAReason) {
    CompiledScene compiled(stack_with_ball(), full_length(), stack().bodies.size());
    const std::vector<WorldResult> chain = simulate_lineage(compiled, 7, 0, {});
    const uint32_t spf = compiled.steps_per_frame();
    auto reason = [&](const RefineStep& step) {
        try {
            check_refinement(compiled, chain, step);
        } catch (const std::invalid_argument& error) {
            return std::string(error.what());
        }
        return std::string();
    };
    EXPECT_NE(reason({12 * spf, 9, {}, {kBall}, {}}).find("t = 0"), std::string::npos);
    EXPECT_NE(reason({0, 9, {}, {kUpper}, {}}).find("already in world"), std::string::npos);
    EXPECT_NE(reason({0, 9, {}, {}, {kBall}}).find("not in world"), std::string::npos);
    EXPECT_NE(reason({0, 9, {kBall}, {}, {}}).find("not in world"), std::string::npos);
    EXPECT_NE(reason({0, 9, {}, {17}, {}}).find("not in the scene"), std::string::npos);
    EXPECT_NE(reason({0, 9, {}, {kBall, kBall}, {}}).find("listed twice"), std::string::npos);
    EXPECT_EQ(reason({0, 9, {}, {kBall}, {kLower}}), "");
}

TEST(SceneChanges, ChangesOnALibrarySceneKeepIndicesAndGiveChangedObjectsBodiesOfTheirOwn) {
    Scene library = stack();
    const std::vector<uint8_t> sampled_world{1, 1, 1, 1};
    Scene exported = stack_with_ball();
    BodyChanges added = change_bodies(library, sampled_world, exported, {"Ball"}, {}, {});
    EXPECT_EQ(added.added, std::vector<uint32_t>{kBall});
    EXPECT_TRUE(added.scene_grew);
    EXPECT_EQ(library.bodies.size(), 5u);
    // Another world gains the same ball: the same body, the scene does not grow.
    BodyChanges again = change_bodies(library, sampled_world, exported, {"Ball"}, {}, {});
    EXPECT_EQ(again.added, std::vector<uint32_t>{kBall});
    EXPECT_FALSE(again.scene_grew);
    // Upper moved in the export: updating it removes its body and adds one for the new definition.
    exported.bodies[kUpper].initial.location = {1, 0, 0.2};
    const BodyChanges updated = change_bodies(library, {1, 1, 1, 1, 1}, exported, {}, {}, {"Upper"});
    EXPECT_EQ(updated.removed, std::vector<uint32_t>{kUpper});
    ASSERT_EQ(updated.added, std::vector<uint32_t>{5});
    EXPECT_EQ(library.bodies[5].name, "Upper#2");
    EXPECT_EQ(object_of(library.bodies[5]), "Upper");
    EXPECT_EQ(library.bodies[5].initial.location, (Vec3{1, 0, 0.2}));
    // A world that has the new Upper: removing "Upper" removes that body.
    Scene copy = library;
    EXPECT_EQ(change_bodies(copy, {1, 1, 0, 1, 1, 1}, exported, {}, {"Upper"}, {}).removed, std::vector<uint32_t>{5});
    auto problem = [&](const std::vector<uint8_t>& present, const std::vector<std::string>& add,
                       const std::vector<std::string>& remove, const std::vector<std::string>& update) {
        Scene scratch = library;
        try {
            change_bodies(scratch, present, exported, add, remove, update);
        } catch (const SceneChangeError& error) {
            return std::string(error.what());
        }
        return std::string();
    };
    const std::vector<uint8_t> all{1, 1, 1, 1, 1, 0};
    EXPECT_NE(problem(all, {"Upper"}, {}, {}).find("'Upper' is already in the world"), std::string::npos);
    EXPECT_NE(problem(all, {"Nothing"}, {}, {}).find("not in the exported scene"), std::string::npos);
    EXPECT_NE(problem(all, {}, {"Nothing"}, {}).find("'Nothing' is not in the world"), std::string::npos);
    EXPECT_NE(problem(all, {}, {}, {"Far"}).find("'Far' is unchanged"), std::string::npos);
    EXPECT_NE(problem({1, 1, 1, 1, 0, 0}, {}, {}, {"Ball"}).find("add it instead"), std::string::npos);
    Scene jointed = stack_with_ball();
    Constraint c;
    c.name = "ToGhost";
    c.body_a = "Ball";
    c.body_b = "Missing";
    jointed.constraints.push_back(c);
    Scene fresh = stack();
    try {
        change_bodies(fresh, sampled_world, jointed, {"Ball"}, {}, {});
        FAIL() << "a constraint to an unknown body was accepted";
    } catch (const SceneChangeError& error) {
        EXPECT_NE(std::string(error.what()).find("constraint 'ToGhost'"), std::string::npos);
    }
}

TEST(SceneChanges, UpdatingAnObjectMovesItAndWakesWhatItLeft) {
    Scene library = stack();
    Scene exported = stack();
    exported.bodies[kUpper].initial.location = {1, 0, 0.2};
    const BodyChanges changes = change_bodies(library, {1, 1, 1, 1}, exported, {}, {}, {"Upper"});
    CompiledScene compiled(library, full_length(), stack().bodies.size());
    const std::vector<WorldResult> chain = simulate_lineage(compiled, 7, 0, {});
    const WorldResult child = refine_world(compiled, 7, chain, {0, 10, {}, changes.added, changes.removed});
    ASSERT_EQ(child.status, WorldStatus::Ok) << child.reject_reason;
    const uint32_t moved = changes.added.front();
    EXPECT_EQ(child.present[kUpper], 0);
    EXPECT_EQ(child.present[moved], 1);
    EXPECT_LT(norm(sub(final_position(child, moved), {1, 0, 0.2})), 0.01) << "the new Upper stands where it was moved";
    EXPECT_EQ(child.changed[kLower], 1) << "the old Upper's ghost wakes the box it stood on";
    EXPECT_LT(norm(sub(final_position(child, kLower), {0, 0, 0.2})), 0.01) << "which stays where it was";
    EXPECT_TRUE(same_track(child, chain.back(), kFar));
}

class SceneChangeLibrary : public ::testing::Test {
protected:
    std::string path(const std::string& name) const { return folder_.path(name); }
    fixtures::TestFolder folder_{"mwb_scene_change"};
};

// A library sampled with the stack, then a world gains the ball and another loses Lower.
TEST_F(SceneChangeLibrary, WorldsSayWhichBodiesTheyHaveAndStoreOnlyWhatChanged) {
    const RunHeader header{scene_to_json(stack()), full_length(), CodecBounds{}, 7, engine_build()};
    const std::string file = path("changes.mwb");
    {
        CompiledScene sampled(stack(), header.parameters);
        LibraryWriter writer(file, header);
        sample_worlds(sampled, 7, 0, 2, 2, [&](WorldResult&& w) { writer.append(w); });
    }
    CompiledScene grown(stack_with_ball(), header.parameters, stack().bodies.size());
    const std::vector<WorldResult> chain = simulate_lineage(grown, 7, 0, {});
    const WorldResult with_ball = refine_world(grown, 7, chain, {0, 2, {}, {kBall}, {}});
    const WorldResult without_lower = refine_world(grown, 7, chain, {0, 3, {}, {}, {kLower}});
    {
        LibraryWriter writer(file, header);
        writer.append_record(kRecordTypeSceneRevision, kSceneRevisionRecordVersion,
                             encode_scene_revision({1, scene_to_json(stack_with_ball())}));
        writer.append(with_ball);
        writer.append(without_lower);
    }
    const LibraryReader reader(file);
    EXPECT_TRUE(reader.warnings().empty()) << reader.warnings().front();
    EXPECT_EQ(reader.scene_revision(), 1u);
    EXPECT_EQ(reader.scene_body_count(), 5u);
    ASSERT_EQ(reader.worlds().size(), 4u);
    const StoredWorld& sampled0 = reader.worlds()[0].world_index == 0 ? reader.worlds()[0] : reader.worlds()[1];
    EXPECT_EQ(sampled0.tracks.size(), 4u) << "a world sampled before the ball keeps its four bodies";
    const StoredWorld& ball_world = reader.worlds()[2];
    const StoredWorld& removed_world = reader.worlds()[3];
    ASSERT_EQ(ball_world.tracks.size(), 5u);
    EXPECT_TRUE(ball_world.tracks[kBall].present);
    EXPECT_FALSE(ball_world.tracks[kBall].inherited);
    EXPECT_TRUE(ball_world.tracks[kFar].inherited) << "Far is stored once, in the parent";
    EXPECT_FALSE(removed_world.tracks[kLower].present);
    EXPECT_FALSE(removed_world.tracks[kBall].present);
    const std::vector<double> positions = decode_world_positions(removed_world, 5);
    const size_t frames = removed_world.frame_count;
    EXPECT_TRUE(std::isnan(positions[(kLower * frames) * 3]));
    EXPECT_NEAR(positions[(kUpper * frames + frames - 1) * 3 + 2], 0.2, 0.01);
    EXPECT_NEAR(positions[(kFar * frames + frames - 1) * 3 + 0], 5, 1e-3);
    EXPECT_THROW(decode_pose(removed_world, kLower, 0), CodecError);
    const std::vector<double> ball_positions = decode_world_positions(ball_world);
    EXPECT_NEAR(ball_positions[(kBall * ball_world.frame_count) * 3 + 2], 2.0, 1e-3) << "the ball starts where added";
    // Merging keeps the revision ahead of the worlds that need it.
    const std::string merged = path("merged.mwb");
    merge_libraries({file}, merged);
    const LibraryReader again(merged);
    EXPECT_TRUE(again.warnings().empty());
    EXPECT_EQ(again.worlds().size(), 4u);
    EXPECT_EQ(again.scene_body_count(), 5u);
}

TEST_F(SceneChangeLibrary, ABadRevisionIsSkippedWithAMessageAndWorldsThatNeedItToo) {
    const RunHeader header{scene_to_json(stack()), full_length(), CodecBounds{}, 7, engine_build()};
    const std::string file = path("bad.mwb");
    Scene reordered = stack_with_ball();
    std::swap(reordered.bodies[1], reordered.bodies[2]);
    CompiledScene grown(stack_with_ball(), header.parameters, stack().bodies.size());
    const std::vector<WorldResult> chain = simulate_lineage(grown, 7, 0, {});
    {
        LibraryWriter writer(file, header);
        writer.append(simulate_world(CompiledScene(stack(), header.parameters), 7, 0));
        writer.append_record(kRecordTypeSceneRevision, kSceneRevisionRecordVersion,
                             encode_scene_revision({1, scene_to_json(reordered)}));
        writer.append_record(kRecordTypeSceneRevision, kSceneRevisionRecordVersion, encode_scene_revision({1, "{nope"}));
        writer.append(refine_world(grown, 7, chain, {0, 5, {}, {kBall}, {}}));
    }
    const LibraryReader reader(file);
    ASSERT_EQ(reader.warnings().size(), 3u);
    EXPECT_NE(reader.warnings()[0].find("does not keep the earlier bodies"), std::string::npos) << reader.warnings()[0];
    EXPECT_NE(reader.warnings()[1].find("scene revision"), std::string::npos) << reader.warnings()[1];
    EXPECT_NE(reader.warnings()[2].find("a scene revision is missing"), std::string::npos) << reader.warnings()[2];
    EXPECT_EQ(reader.worlds().size(), 1u) << "the sampled world is kept";
    EXPECT_EQ(reader.scene_body_count(), 4u);
}

}  // namespace
}  // namespace mwb
