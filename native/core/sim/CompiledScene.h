#pragma once
// A scene prepared once per run for fast world construction: validated, shapes flattened into
// collision parts with hulls computed, mass properties and stepping rates derived. Read-only and
// shared by all worlds of a run on all threads.
#include <cstdint>
#include <cstddef>
#include <vector>

#include "scene/Scene.h"
#include "sim/SimulationParameters.h"

namespace mwb {

enum class PartKind { Box, Sphere, Capsule, Cylinder, Convex, TriangleMesh };

/// One collision geometry of a body, in the body's frame (centre of mass for dynamic bodies,
/// object origin otherwise). TriangleMesh data are already in that frame; Convex data are about the
/// part's offset, which ODE needs inside every face of the hull.
struct CollisionPart {
    PartKind kind = PartKind::Box;
    Vec3 half_extents_m{0, 0, 0};
    double radius_m = 0;
    double length_m = 0;  ///< Capsule: cylinder part only (ODE's convention); Cylinder: full
    Transform offset;     ///< primitives; Convex: a translation only; TriangleMesh: unused
    std::vector<double> convex_points;          ///< (n, 3), about offset.location
    std::vector<double> convex_planes;          ///< (f, 4): unit outward normal, distance from offset.location (> 0)
    std::vector<unsigned int> convex_polygons;  ///< ODE layout: count, indices..., per face
    unsigned int convex_plane_count = 0, convex_point_count = 0;
    std::vector<double> mesh_vertices;   ///< (n, 3), thickened by mesh_margin_m
    double mesh_margin_m = 0;            ///< Blender's margin the mesh was thickened by
    std::vector<uint32_t> mesh_indices;  ///< (m, 3)
};

struct CompiledBody {
    bool dynamic = false;    ///< simulated: ACTIVE, enabled and not animated
    bool kinematic = false;  ///< follows its animation track
    /// Dynamic bodies whose "Animated" is keyed off: the step from which they are simulated; until
    /// then they follow their animation track. 0: simulated from the start.
    uint64_t handoff_step = 0;
    Vec3 body_frame_offset_m{0, 0, 0};  ///< centre of mass in the object frame (0 if not dynamic)
    std::array<double, 9> inertia{};    ///< about the centre of mass, object axes, for mass_kg
    double bounding_radius_m = 0;       ///< of all parts about the body frame origin
    std::vector<CollisionPart> parts;
    /// The same parts grown by 1 cm, for refinement ghosts.
    std::vector<CollisionPart> ghost_parts;
    bool has_mesh = false;
};

class CompiledScene {
public:
    /// Validates and prepares `scene`. Throws SceneError naming every problem. Bodies from
    /// `sampled_body_count` on were added after sampling: they exist only in worlds whose lineage
    /// adds them (default: every body was sampled).
    CompiledScene(Scene scene, const SimulationParameters& parameters, size_t sampled_body_count = SIZE_MAX);

    const Scene& scene() const { return scene_; }
    const SimulationParameters& parameters() const { return parameters_; }
    const std::vector<CompiledBody>& bodies() const { return bodies_; }
    /// Bodies every sampled world has: scene bodies [0, sampled_body_count()).
    size_t sampled_body_count() const { return sampled_body_count_; }

    /// Simulation steps per second of animation time (a multiple of record_hz).
    double step_hz() const { return step_hz_; }
    /// Animation time at the start of step `step`, seconds.
    double step_time_s(uint64_t step) const { return static_cast<double>(step) / step_hz_; }
    /// Physics time advanced per step, seconds (animation step × Blender's time scale).
    double physics_dt_s() const { return scene_.world.time_scale / step_hz_; }
    uint32_t steps_per_frame() const { return steps_per_frame_; }
    uint64_t total_steps() const { return total_steps_; }
    uint64_t steps_per_checkpoint() const { return steps_per_checkpoint_; }
    double duration_s() const { return duration_s_; }

private:
    Scene scene_;
    SimulationParameters parameters_;
    std::vector<CompiledBody> bodies_;
    double step_hz_ = 240;
    uint32_t steps_per_frame_ = 2;
    uint64_t total_steps_ = 0;
    uint64_t steps_per_checkpoint_ = 120;
    double duration_s_ = 0;
    size_t sampled_body_count_ = 0;
};

}  // namespace mwb
