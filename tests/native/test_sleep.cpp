// Sleeping: bodies at rest stop being stepped, and the motion stays what it would have been
// (within the codec's error bound); a sleeping body wakes when something reaches it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "SceneFixtures.h"
#include "WorldCompare.h"
#include "scene/SceneJson.h"
#include "sim/CompiledScene.h"
#include "sim/WorldRun.h"
#include "sim/WorldSimulator.h"

namespace mwb {
namespace {

using compare::position;

SimulationParameters with_sleep(bool sleep) {
    SimulationParameters p;
    p.sleep = sleep;
    p.stop_at_rest = false;  // sleeping must save steps in worlds that go on
    return p;
}

double distance(const Vec3& a, const Vec3& b) { return norm(sub(a, b)); }

/// The largest distance between the two worlds' positions of any body over their common frames.
double largest_difference(const WorldResult& a, const WorldResult& b) {
    double worst = 0;
    const uint32_t frames = std::min(a.frame_count, b.frame_count);
    for (uint32_t body = 0; body < a.body_count; ++body)
        for (uint32_t f = 0; f < frames; ++f) worst = std::max(worst, distance(position(a, body, f), position(b, body, f)));
    return worst;
}

/// Boxes dropped apart onto the floor: nothing but the floor ever touches them.
Scene boxes_apart() {
    Scene s;
    s.name = "boxes_apart";
    s.world.frame_end = 1 + 4 * 24;
    s.bodies.push_back(fixtures::ground());
    for (int i = 0; i < 6; ++i) s.bodies.push_back(fixtures::box("Box" + std::to_string(i), {-2.5 + i, 0, 0.5 + 0.2 * i}));
    return s;
}

TEST(Sleep, RestingBodiesSleepAndEndWhereTheyWouldHaveRested) {
    CompiledScene awake(boxes_apart(), with_sleep(false));
    CompiledScene sleepy(boxes_apart(), with_sleep(true));
    const WorldResult reference = simulate_world(awake, 1, 0);
    WorldRun run(sleepy, 1, 0);
    const WorldResult slept = run.run();
    ASSERT_EQ(slept.status, WorldStatus::Ok);
    // 6 boxes over 4 s settle within about a second: most of their body-steps are skipped.
    const double body_steps = 6.0 * sleepy.total_steps();
    EXPECT_GT(run.sleeping_body_steps() / body_steps, 0.5);
    // Within the codec's error bound (1 mm) of the world that never slept.
    EXPECT_LT(largest_difference(reference, slept), 1e-3);
}

TEST(Sleep, ASleepingBodyWakesWhenSomethingFallsOnIt) {
    // A box rests (and sleeps) on the floor; a heavy ball dropped from high up reaches it after
    // about 1.6 s and knocks it away, as it does when nothing sleeps.
    Scene s = boxes_apart();
    s.bodies.resize(2);
    s.bodies[1].initial.location = {0, 0, 0.2};
    Body ball = fixtures::sphere("Ball", {0.15, 0, 13.0}, 0.15);
    ball.mass_kg = 5;
    s.bodies.push_back(ball);
    CompiledScene awake(s, with_sleep(false));
    CompiledScene sleepy(s, with_sleep(true));
    const WorldResult reference = simulate_world(awake, 1, 0);
    WorldRun run(sleepy, 1, 0);
    const WorldResult slept = run.run();
    ASSERT_EQ(slept.status, WorldStatus::Ok);
    EXPECT_GT(run.sleeping_body_steps(), 0u) << "the box never slept before the ball came";
    const uint32_t last = slept.frame_count - 1;
    const double moved = distance(position(slept, 1, last), position(slept, 1, 0));
    const double moved_awake = distance(position(reference, 1, last), position(reference, 1, 0));
    EXPECT_GT(moved_awake, 0.02) << "the scene must knock the box away";
    EXPECT_GT(moved, 0.5 * moved_awake) << "the sleeping box did not wake when hit (moved " << moved << " m)";
}

TEST(Sleep, AnAnimatedBodyPushesASleepingBodyAway) {
    // A keyed paddle stands still for 1.5 s (the box falls asleep beside it), then sweeps through
    // where the box rests. ODE does not wake bodies for a kinematic one: the engine must.
    Scene s = boxes_apart();
    s.world.frame_end = 1 + 3 * 24;
    s.bodies.resize(2);
    s.bodies[1].initial.location = {0, 0, 0.2};
    Body paddle = fixtures::box("Paddle", {-0.6, 0, 0.3}, {0.1, 0.5, 0.3});
    paddle.type = BodyType::Passive;
    paddle.kinematic = true;
    paddle.animation.times_s = {0, 1.5, 2.5};
    paddle.animation.transforms = {Transform{{-0.6, 0, 0.3}, {1, 0, 0, 0}}, Transform{{-0.6, 0, 0.3}, {1, 0, 0, 0}},
                                   Transform{{1.0, 0, 0.3}, {1, 0, 0, 0}}};
    s.bodies.push_back(paddle);
    CompiledScene sleepy(s, with_sleep(true));
    WorldRun run(sleepy, 1, 0);
    const WorldResult w = run.run();
    ASSERT_EQ(w.status, WorldStatus::Ok);
    EXPECT_GT(run.sleeping_body_steps(), 0u) << "the box never slept before the paddle moved";
    // Pushed ahead of the paddle, whose front face ends at x = 1.1.
    EXPECT_GT(position(w, 1, w.frame_count - 1)[0], 1.0);
}

TEST(Sleep, BlenderStartDeactivatedKeepsATowerStandingUntilSomethingHitsIt) {
    // Blender's Deactivation with Start Deactivated: the blocks sleep from the first step (as in
    // Bullet), so nothing creeps, until the ball knocks the top blocks off.
    Scene s;
    s.name = "tower";
    s.world.frame_end = 1 + 3 * 24;
    s.bodies.push_back(fixtures::ground());
    for (int k = 0; k < 6; ++k) {
        Body block = fixtures::box("Block" + std::to_string(k), {0, 0, 0.2 + 0.4 * k});
        block.deactivation.enabled = true;
        block.deactivation.start_deactivated = true;
        s.bodies.push_back(block);
    }
    Body ball = fixtures::sphere("Ball", {-3.0, 0, 2.67}, 0.2);  // reaches block 5 after 0.47 s
    ball.initial_linear_velocity = {6, 0, 1.3};
    s.bodies.push_back(ball);
    CompiledScene compiled(s, with_sleep(true));
    WorldRun run(compiled, 1, 0);
    const WorldResult w = run.run();
    ASSERT_EQ(w.status, WorldStatus::Ok);
    // Before the ball arrives (about 0.4 s) no block has moved at all.
    for (uint32_t b = 1; b <= 5; ++b) EXPECT_EQ(position(w, b, 0), position(w, b, 36)) << "block " << b;
    double knocked = 0;
    for (uint32_t b = 1; b <= 6; ++b) knocked = std::max(knocked, distance(position(w, b, w.frame_count - 1), position(w, b, 0)));
    EXPECT_GT(knocked, 0.3) << "no block woke when the ball hit the tower";
    // A sleeping body in its scene JSON round trip keeps its settings.
    const Scene again = scene_from_json(scene_to_json(s));
    EXPECT_TRUE(again.bodies[1].deactivation.start_deactivated);
    EXPECT_EQ(again.bodies[1].deactivation.linear_speed, 0.4);
}

TEST(Sleep, ARestartFromAnyCheckpointSleepsAndWakesAsTheWorldDid) {
    // The same world resumed from each checkpoint: bit for bit the same motion afterwards.
    CompiledScene compiled(fixtures::pile(10, 96), with_sleep(true));
    WorldRun first(compiled, 4, 2);
    const WorldResult original = first.run();
    ASSERT_EQ(original.status, WorldStatus::Ok);
    ASSERT_GT(first.sleeping_body_steps(), 0u);
    for (const Checkpoint& checkpoint : original.checkpoints) {
        WorldRun again(compiled, 4, 2);
        again.restore(checkpoint);
        const WorldResult resumed = again.run();
        for (uint32_t b = 0; b < original.body_count; ++b)
            for (uint32_t f = 0; f < resumed.frame_count; ++f)
                ASSERT_EQ(position(original, b, resumed.first_frame + f), position(resumed, b, f))
                    << "body " << b << " frame " << resumed.first_frame + f << " after step " << checkpoint.step_index;
    }
}

}  // namespace
}  // namespace mwb
