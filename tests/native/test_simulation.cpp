#include <gtest/gtest.h>

#include <cmath>
#include <ode/ode.h>

#include "SceneFixtures.h"
#include "common/PortableMath.h"
#include "scene/SceneJson.h"
#include "sim/CompiledScene.h"
#include "sim/OdeRandom.h"
#include "sim/WorldSimulator.h"
#include "sim/PoseInterpolation.h"

namespace mwb {
namespace {

// Position of body b at frame f of a recorded world.
Vec3 position(const WorldResult& w, size_t b, size_t f) {
    const double* p = &w.positions_m[(b * w.frame_count + f) * 3];
    return {p[0], p[1], p[2]};
}
Quat orientation(const WorldResult& w, size_t b, size_t f) {
    const double* q = &w.orientations[(b * w.frame_count + f) * 4];
    return {q[0], q[1], q[2], q[3]};
}

SimulationParameters unperturbed() {
    SimulationParameters p;
    p.perturb = false;
    return p;
}

TEST(Simulation, BallDroppedOnPlaneRestsAtItsRadius) {
    for (bool perturb : {false, true}) {
        SimulationParameters parameters;
        parameters.perturb = perturb;
        CompiledScene compiled(fixtures::ball_on_plane(), parameters);
        const WorldResult w = simulate_world(compiled, 1, 0);
        ASSERT_EQ(w.status, WorldStatus::Ok) << w.reject_reason;
        const Vec3 last = position(w, 1, w.frame_count - 1);
        EXPECT_NEAR(last[2], 0.5, 0.01);
        // Unperturbed, a straight drop stays straight; perturbed, the lobe tilts the bounce a little.
        if (!perturb) {
            EXPECT_EQ(last[0], 0.0);
        } else {
            EXPECT_GT(w.impacts_perturbed, 0u);
        }
    }
}

TEST(Simulation, WorldEndsSoonAfterEverythingRests) {
    CompiledScene compiled(fixtures::ball_on_plane(), SimulationParameters{});
    const WorldResult w = simulate_world(compiled, 1, 0);
    ASSERT_EQ(w.status, WorldStatus::Ok);
    // Falling 1.5 m takes 0.55 s; the world stops rest_duration (0.5 s) after rest, far before 10 s.
    EXPECT_GT(w.rest_time_s[1], 0.5);
    EXPECT_LT(w.rest_time_s[1], 1.5);
    EXPECT_LT(w.simulated_time_s, w.rest_time_s[1] + 0.5 + 0.02);
    EXPECT_GE(w.simulated_time_s, w.rest_time_s[1] + 0.5);
    EXPECT_EQ(w.frame_count, static_cast<uint32_t>(std::lround(w.simulated_time_s * 120)) + 1);
}

TEST(Simulation, FreeFlightFollowsTheParabolaAndHasNoImpacts) {
    Scene scene;
    scene.world.frame_end = 25;  // 1 s
    Body b = fixtures::box("Thrown", {0, 0, 10});
    b.initial_linear_velocity = {1, 0, 5};
    b.linear_damping = 0;
    b.angular_damping = 0;
    scene.bodies.push_back(b);
    CompiledScene compiled(scene, SimulationParameters{});
    const WorldResult w = simulate_world(compiled, 7, 0);
    ASSERT_EQ(w.status, WorldStatus::Ok);
    EXPECT_TRUE(w.contacts.empty());
    EXPECT_EQ(w.impacts_perturbed, 0u);
    const Vec3 end = position(w, 0, w.frame_count - 1);
    EXPECT_NEAR(end[0], 1.0, 1e-6);
    EXPECT_NEAR(end[2], 10 + 5 - 0.5 * 9.81, 0.05);  // semi-implicit Euler: O(dt) drift only
}

TEST(Simulation, OffsetCentreOfMassIsConvertedBackToTheOrigin) {
    // A spinning body whose centre of mass is 0.3 m from its origin: the centre of mass must fly
    // straight (no gravity), the recorded origin must circle around it.
    Scene scene;
    scene.world.gravity = {0, 0, 0};
    scene.world.frame_end = 25;
    Body b = fixtures::sphere("Offset", {0, 0, 0}, 0.2);
    b.has_center_of_mass = true;
    b.center_of_mass_local_m = {0.3, 0, 0};
    b.initial_angular_velocity = {0, 0, 3};
    b.angular_damping = 0;
    b.linear_damping = 0;
    scene.bodies.push_back(b);
    CompiledScene compiled(scene, SimulationParameters{});
    const WorldResult w = simulate_world(compiled, 1, 0);
    ASSERT_EQ(w.status, WorldStatus::Ok);
    for (uint32_t f = 0; f < w.frame_count; f += 10) {
        const Vec3 com = add(position(w, 0, f), quat_rotate(orientation(w, 0, f), {0.3, 0, 0}));
        EXPECT_NEAR(com[0], 0.3, 1e-9);
        EXPECT_NEAR(com[1], 0.0, 1e-9);
    }
    EXPECT_GT(norm(sub(position(w, 0, 60), position(w, 0, 0))), 0.2);
}

TEST(Simulation, KinematicBodyFollowsItsAnimation) {
    Scene scene;
    scene.world.frame_end = 49;  // 2 s
    Body platform = fixtures::box("Platform", {0, 0, 0}, {1, 1, 0.1});
    platform.type = BodyType::Passive;
    platform.kinematic = true;
    platform.animation.times_s = {0, 1, 2};
    platform.animation.transforms = {Transform{{0, 0, 0}, {1, 0, 0, 0}}, Transform{{2, 0, 1}, {1, 0, 0, 0}},
                                     Transform{{2, 0, 1}, quat_from_axis_angle({0, 0, 1}, 1.0)}};
    scene.bodies.push_back(platform);
    scene.bodies.push_back(fixtures::box("Rider", {0, 0, 0.35}));
    CompiledScene compiled(scene, SimulationParameters{});
    const WorldResult w = simulate_world(compiled, 1, 0);
    ASSERT_EQ(w.status, WorldStatus::Ok);
    const Vec3 half_way = position(w, 0, 60);
    EXPECT_NEAR(half_way[0], 1.0, 1e-9);
    EXPECT_NEAR(half_way[2], 0.5, 1e-9);
    EXPECT_NEAR(quat_angle_between(orientation(w, 0, w.frame_count - 1), quat_from_axis_angle({0, 0, 1}, 1.0)), 0, 1e-9);
    // The rider is carried up with the platform.
    EXPECT_GT(position(w, 1, 120)[2], 1.0);
}

TEST(Simulation, ExplodingWorldIsRejectedWithAReason) {
    Scene scene = fixtures::ball_on_plane();
    scene.bodies[1].initial_linear_velocity = {0, 0, -900};
    CompiledScene compiled(scene, SimulationParameters{});
    const WorldResult w = simulate_world(compiled, 1, 0);
    EXPECT_EQ(w.status, WorldStatus::Rejected);
    EXPECT_NE(w.reject_reason.find("'Ball'"), std::string::npos) << w.reject_reason;
    EXPECT_NE(w.reject_reason.find("exploded"), std::string::npos) << w.reject_reason;
}

TEST(Simulation, BouncingBallRecordsItsImpactsAndSlowsDown) {
    Scene scene = fixtures::ball_on_plane(3.0, 0.8);
    CompiledScene compiled(scene, unperturbed());
    const WorldResult w = simulate_world(compiled, 1, 0);
    ASSERT_EQ(w.status, WorldStatus::Ok);
    ASSERT_GE(w.contacts.size(), 3u);
    for (size_t k = 1; k < w.contacts.size(); ++k) EXPECT_GE(w.contacts[k].time_s, w.contacts[k - 1].time_s);
    EXPECT_EQ(w.contacts[0].body, 1);
    EXPECT_EQ(w.contacts[0].other, 0);
    // First impact at sqrt(2 * 2.5 / g) = 0.714 s with impulse m * (1 + e) * v, v = sqrt(2 g h).
    EXPECT_NEAR(w.contacts[0].time_s, std::sqrt(2 * 2.5 / 9.81), 0.02);
    EXPECT_GT(w.contacts[0].impulse_ns, 1.0 * std::sqrt(2 * 9.81 * 2.5));
    EXPECT_GT(w.contacts[0].impulse_ns, w.contacts[1].impulse_ns);
}

TEST(Simulation, ResumingFromAnyCheckpointReplaysTheWorldExactly) {
    CompiledScene compiled(fixtures::mesh_ramp_with_joints(), SimulationParameters{});
    const WorldResult original = simulate_world(compiled, 11, 3);
    ASSERT_EQ(original.status, WorldStatus::Ok) << original.reject_reason;
    ASSERT_GE(original.checkpoints.size(), 3u);
    for (const Checkpoint& checkpoint : original.checkpoints) {
        const WorldResult resumed = resume_world(compiled, 11, 3, checkpoint);
        ASSERT_EQ(resumed.status, WorldStatus::Ok);
        ASSERT_EQ(resumed.first_frame + resumed.frame_count, original.frame_count);
        for (uint32_t b = 0; b < original.body_count; ++b) {
            for (uint32_t f = 0; f < resumed.frame_count; ++f) {
                ASSERT_EQ(position(original, b, resumed.first_frame + f), position(resumed, b, f))
                    << "body " << b << " frame " << resumed.first_frame + f;
                ASSERT_EQ(orientation(original, b, resumed.first_frame + f), orientation(resumed, b, f));
            }
        }
        EXPECT_EQ(original.rest_time_s, resumed.rest_time_s);
    }
}

TEST(Simulation, QuickstepDrawsFromThePerWorldRandomState) {
    // If ODE ever stops calling our dRandInt (an upgrade inlining it, a link change), worlds silently
    // lose determinism under threads. This fails first.
    CompiledScene compiled(fixtures::pile(8, 24), SimulationParameters{});
    const uint64_t before = ode_random_calls_on_this_thread();
    const WorldResult w = simulate_world(compiled, 1, 0);
    ASSERT_EQ(w.status, WorldStatus::Ok);
    EXPECT_GT(ode_random_calls_on_this_thread() - before, 1000u);
}

#ifdef MWB_ODE_PER_THREAD_RANDOM
TEST(Simulation, OdeComputesRotationsWithThePortableFunctions) {
    // Our ODE build calls mwb::portable's sin and cos, not the C library's (whose last bits vary
    // between versions). Find angles where the two differ, then check ODE agrees with ours.
    int differing = 0;
    for (double angle = 0.001; angle < 50 && differing < 20; angle += 0.0137) {
        if (portable::cos(angle / 2) == std::cos(angle / 2) && portable::sin(angle / 2) == std::sin(angle / 2))
            continue;
        ++differing;
        dQuaternion q;
        dQFromAxisAndAngle(q, 0, 0, 1, angle);
        EXPECT_EQ(q[0], portable::cos(angle / 2)) << angle;
        EXPECT_EQ(q[3], portable::sin(angle / 2)) << angle;
    }
    EXPECT_GT(differing, 0) << "no angle found where the C library and the portable functions differ";
}
#endif

TEST(Simulation, InvalidSceneIsAnErrorNamingTheBody) {
    Scene scene = fixtures::ball_on_plane();
    scene.bodies[1].mass_kg = 0;
    try {
        CompiledScene compiled(scene, SimulationParameters{});
        FAIL() << "a zero-mass active body must be refused";
    } catch (const SceneError& error) {
        EXPECT_NE(std::string(error.what()).find("Ball"), std::string::npos) << error.what();
        EXPECT_NE(std::string(error.what()).find("mass_kg"), std::string::npos) << error.what();
    }
}

}  // namespace
}  // namespace mwb

namespace mwb {
namespace {

// How bake and preview pose a recorded world between frames: one rule, the engine's.
TEST(RecordedPoses, BetweenFramesAndSignContinuousAndClamped) {
    // One body, three frames: x = 0, 1, 2; the second quaternion recorded with the other sign.
    const std::vector<double> positions{0, 0, 0, 1, 0, 0, 2, 0, 0};
    const std::vector<double> orientations{1, 0, 0, 0, -1, 0, 0, 0, -0.8, -0.6, 0, 0};
    const std::vector<double> at{0, 1, 1.5, 2, 7, -3};
    std::vector<double> loc(at.size() * 3), rot(at.size() * 4);
    sample_recorded_poses(positions.data(), orientations.data(), 1, 3, at, loc.data(), rot.data());
    EXPECT_DOUBLE_EQ(loc[2 * 3], 1.5);
    EXPECT_DOUBLE_EQ(loc[4 * 3], 2.0);  // past the end: the last pose
    EXPECT_DOUBLE_EQ(loc[5 * 3], 0.0);  // before the start: the first
    EXPECT_DOUBLE_EQ(rot[1 * 4], 1.0);  // -q is the same rotation: it continues as +q
    EXPECT_NEAR(rot[3 * 4], 0.8, 1e-12);
    EXPECT_NEAR(rot[3 * 4 + 1], 0.6, 1e-12);
    const double norm = std::hypot(1.8, 0.6);
    EXPECT_NEAR(rot[2 * 4], 1.8 / norm, 1e-12);
    EXPECT_NEAR(rot[2 * 4 + 1], 0.6 / norm, 1e-12);
}

}  // namespace
}  // namespace mwb
