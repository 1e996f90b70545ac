// Shapes and margins as Blender gives them to Bullet: a BOX on a flat object, margins on MESH
// shapes and cones. Each test drops a body and checks where it rests against what Bullet does.
#include <gtest/gtest.h>

#include <cmath>

#include "SceneFixtures.h"
#include "scene/SceneValidation.h"
#include "sim/CompiledScene.h"
#include "sim/WorldSimulator.h"

namespace mwb {
namespace {

double final_height(const WorldResult& w, size_t body) {
    return w.positions_m[(body * w.frame_count + w.frame_count - 1) * 3 + 2];
}

SimulationParameters unperturbed() {
    SimulationParameters p;
    p.perturb = false;
    return p;
}

// A 4 m square plane at z = 0 whose BOX shape Blender makes from its flat bounding box.
Body flat_box_ground(const Quat& rotation = {1, 0, 0, 0}) {
    Body ground = fixtures::ground();
    ground.shape.half_extents_m = {2, 2, 0};
    ground.initial.location = {0, 0, 0};
    ground.initial.rotation = rotation;
    return ground;
}

Scene drop_onto(const Body& ground, double speed_mps = 0) {
    Scene s;
    s.world.frame_end = 97;
    s.bodies.push_back(ground);
    s.bodies.push_back(fixtures::box("Box", {0, 0, 1}, {0.1, 0.1, 0.1}));
    s.bodies.back().initial_linear_velocity = {0, 0, -speed_mps};
    return s;
}

TEST(BlenderShapes, ABoxOnAFlatPlaneIsAcceptedAndHoldsWhatLandsOnIt) {
    EXPECT_TRUE(validate_scene(drop_onto(flat_box_ground())).empty());
    for (double speed : {0.0, 20.0}) {
        const WorldResult w = simulate_world(CompiledScene(drop_onto(flat_box_ground(), speed), unperturbed()), 1, 0);
        ASSERT_EQ(w.status, WorldStatus::Ok) << w.reject_reason;
        // Bullet's plate has no thickness: the box rests on the plane's own height.
        EXPECT_NEAR(final_height(w, 1), 0.1, 0.002) << "dropped at " << speed << " m/s";
    }
    // Upside down (its local Z pointing down), the plane still holds from above.
    const WorldResult flipped = simulate_world(CompiledScene(drop_onto(flat_box_ground({0, 1, 0, 0}), 20), unperturbed()), 1, 0);
    EXPECT_NEAR(final_height(flipped, 1), 0.1, 0.002);
}

TEST(BlenderShapes, ABoxWithTwoFlatSidesIsRefusedClearly) {
    Body line = flat_box_ground();
    line.shape.half_extents_m = {2, 0, 0};
    const std::vector<std::string> problems = validate_scene(drop_onto(line));
    ASSERT_EQ(problems.size(), 1u);
    EXPECT_NE(problems[0].find("more than one side of length 0"), std::string::npos) << problems[0];
}

TEST(BlenderShapes, AMeshGroundIsThickenedByItsMarginAsInBullet) {
    Body plane = fixtures::mesh_quad("Plane", {-2, -2, 0, 2, -2, 0, 2, 2, 0, -2, 2, 0});
    for (double margin : {0.04, 0.0}) {
        plane.collision_margin_m = margin;  // applied whether or not use_margin is set
        const WorldResult w = simulate_world(CompiledScene(drop_onto(plane), unperturbed()), 1, 0);
        ASSERT_EQ(w.status, WorldStatus::Ok) << w.reject_reason;
        EXPECT_NEAR(final_height(w, 1), 0.1 + margin, 0.002) << "margin " << margin;
    }
}

TEST(BlenderShapes, AConvexHullOfAPlaneIsAThinSlab) {
    Body plane = fixtures::mesh_quad("Plane", {-2, -2, 0, 2, -2, 0, 2, 2, 0, -2, 2, 0});
    plane.shape.type = ShapeType::ConvexHull;
    const Scene scene = drop_onto(plane);
    EXPECT_TRUE(validate_scene(scene).empty());
    const WorldResult w = simulate_world(CompiledScene(scene, unperturbed()), 1, 0);
    ASSERT_EQ(w.status, WorldStatus::Ok) << w.reject_reason;
    EXPECT_NEAR(final_height(w, 1), 0.1, 0.002);
    // Points on one line still span nothing.
    Body line = plane;
    line.shape.vertices_m = {0, 0, 0, 1, 0, 0, 2, 0, 0, 3, 0, 0};
    const std::vector<std::string> problems = validate_scene(drop_onto(line));
    ASSERT_EQ(problems.size(), 1u);
    EXPECT_NE(problems[0].find("collinear"), std::string::npos) << problems[0];
}

TEST(BlenderShapes, AConeGrowsByItsMargin) {
    Scene s = drop_onto(fixtures::ground());
    Body& cone = s.bodies[1];
    cone.shape.type = ShapeType::Cone;
    cone.shape.radius_m = 0.2;
    cone.shape.height_m = 0.4;
    cone.collision_margin_m = 0.04;
    const WorldResult w = simulate_world(CompiledScene(s, unperturbed()), 1, 0);
    ASSERT_EQ(w.status, WorldStatus::Ok) << w.reject_reason;
    // Resting on its base: the object origin is at half height, the base 4 cm lower than drawn.
    // (The centre of mass sits lower, but the recorded pose is the object origin.)
    EXPECT_NEAR(final_height(w, 1), 0.2 + 0.04, 0.003);
}

}  // namespace
}  // namespace mwb

namespace mwb {
namespace {

// A ball keyed "Animated" while it is carried sideways at 2 m/s for 1 s, then let go at 1 s.
Scene thrown_ball() {
    Scene s;
    s.world.frame_end = 49;  // 2 s
    s.bodies.push_back(fixtures::ground());
    Body ball = fixtures::sphere("Ball", {0, 0, 3}, 0.2);
    ball.linear_damping = ball.angular_damping = 0;
    ball.animated_until_s = 1.0;
    for (int k = 0; k <= 24; ++k) {
        ball.animation.times_s.push_back(k / 24.0);
        ball.animation.transforms.push_back(Transform{{2.0 * k / 24.0, 0, 3}, {1, 0, 0, 0}});
    }
    s.bodies.push_back(ball);
    return s;
}

TEST(KeyedAnimated, ABodyFollowsItsKeysThenFliesOnWithTheirVelocity) {
    const CompiledScene compiled(thrown_ball(), unperturbed());
    const WorldResult w = simulate_world(compiled, 1, 0);
    ASSERT_EQ(w.status, WorldStatus::Ok) << w.reject_reason;
    auto at = [&](uint32_t frame, int axis) { return w.positions_m[(1 * w.frame_count + frame) * 3 + axis]; };
    EXPECT_NEAR(at(60, 0), 1.0, 1e-9) << "follows its keys while animated";
    EXPECT_NEAR(at(60, 2), 3.0, 1e-9);
    // Free from 1 s: 0.25 s later it is 0.5 m further along and has fallen g·t²/2.
    EXPECT_NEAR(at(150, 0), 2.5, 0.01);
    EXPECT_NEAR(at(150, 2), 3.0 - 0.5 * 9.81 * 0.25 * 0.25, 0.01);
    EXPECT_TRUE(w.contacts.empty() || w.contacts.front().time_s > 1.0) << "no impacts while driven";
}

TEST(KeyedAnimated, ResumingBeforeOrAfterTheHandoffReplaysExactly) {
    const CompiledScene compiled(thrown_ball(), SimulationParameters{});
    const WorldResult original = simulate_world(compiled, 5, 2);
    ASSERT_EQ(original.status, WorldStatus::Ok) << original.reject_reason;
    ASSERT_GE(original.checkpoints.size(), 3u);
    for (const Checkpoint& checkpoint : original.checkpoints) {
        const WorldResult resumed = resume_world(compiled, 5, 2, checkpoint);
        ASSERT_EQ(resumed.first_frame + resumed.frame_count, original.frame_count);
        for (uint32_t f = 0; f < resumed.frame_count; ++f)
            for (int axis = 0; axis < 3; ++axis)
                ASSERT_EQ(original.positions_m[(original.frame_count + resumed.first_frame + f) * 3 + axis],
                          resumed.positions_m[(resumed.frame_count + f) * 3 + axis])
                    << "checkpoint at step " << checkpoint.step_index << ", frame " << f;
    }
}

}  // namespace
}  // namespace mwb
