// Metric values on scenes whose answers are known from mechanics.
#include <gtest/gtest.h>

#include <cmath>

#include "SceneFixtures.h"
#include "query/BodyMetrics.h"
#include "sim/CompiledScene.h"
#include "sim/WorldSimulator.h"

namespace mwb {
namespace {

double metric(const WorldResult& w, const std::string& name, size_t body) {
    for (const MetricValues& m : compute_body_metrics(w))
        if (m.name == name) return m.per_body[body];
    ADD_FAILURE() << "no metric " << name;
    return 0;
}

SimulationParameters unperturbed() {
    SimulationParameters p;
    p.perturb = false;
    return p;
}

TEST(Metrics, RollingSphereTurnsDistanceOverRadius) {
    Scene scene = fixtures::ball_on_plane(0.5);
    scene.world.frame_end = 49;  // 2 s
    Body& ball = scene.bodies[1];
    ball.linear_damping = ball.angular_damping = 0;
    ball.initial_linear_velocity = {2, 0, 0};
    ball.initial_angular_velocity = {0, 2 / 0.5, 0};  // rolling without slipping
    SimulationParameters p = unperturbed();
    p.stop_at_rest = false;
    CompiledScene compiled(scene, p);
    const WorldResult w = simulate_world(compiled, 1, 0);
    ASSERT_EQ(w.status, WorldStatus::Ok);
    const double distance = metric(w, "path_length_m", 1);
    EXPECT_NEAR(distance, 4.0, 0.1);
    EXPECT_NEAR(metric(w, "angular_travel_rad", 1), distance / 0.5, 0.02 * distance / 0.5);
    EXPECT_EQ(metric(w, "collision_count", 1), 0) << "rolling is not a collision";
}

TEST(Metrics, BouncingBallCountsItsBounces) {
    // Dropped 2.5 m with restitution 0.8: impact speeds 7.0 · 0.8^n m/s; ODE stops bouncing
    // below 0.1 m/s, so the ball hits the ground 20 times (n = 0 .. 19) before it rests.
    const Scene scene = fixtures::ball_on_plane(3.0, 0.8);
    CompiledScene compiled(scene, unperturbed());
    const WorldResult w = simulate_world(compiled, 1, 0);
    ASSERT_EQ(w.status, WorldStatus::Ok);
    const double expected = std::floor(std::log(0.1 / std::sqrt(2 * 9.81 * 2.5)) / std::log(0.8)) + 1;
    EXPECT_NEAR(metric(w, "collision_count", 1), expected, 2);
    EXPECT_EQ(metric(w, "collision_count", 0), 0) << "the passive ground never records impacts";
}

TEST(Metrics, TimeToRestOfADroppedBox) {
    Scene scene;
    scene.world.frame_end = 121;
    scene.bodies.push_back(fixtures::ground());
    scene.bodies.push_back(fixtures::box("Crate", {0, 0, 1.2}));  // bottom 1 m up: lands at 0.45 s
    CompiledScene compiled(scene, unperturbed());
    const WorldResult w = simulate_world(compiled, 1, 0);
    ASSERT_EQ(w.status, WorldStatus::Ok);
    const double rest = metric(w, "time_to_rest_s", 1);
    EXPECT_GE(rest, std::sqrt(2 * 1.0 / 9.81));
    EXPECT_LT(rest, 0.7);
    EXPECT_LT(metric(w, "orientation_change_rad", 1), 0.01) << "a flat drop does not tip (a tip is pi/2)";
}

}  // namespace
}  // namespace mwb
