#include "sim/OdeWorld.h"

#include "sim/OdeMessages.h"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <mutex>
#include <string>

namespace mwb {
namespace {

[[noreturn]] void throw_ode_error(int code, const char* message, va_list args) {
    char text[512];
    std::vsnprintf(text, sizeof text, message, args);
    throw OdeError("ODE internal error " + std::to_string(code) + ": " + text);
}

void to_ode_quaternion(const Quat& q, dQuaternion out) {
    for (int k = 0; k < 4; ++k) out[k] = q[k];
}

void set_state(dBodyID body, const BodyState& s) {
    dBodySetPosition(body, s.position_m[0], s.position_m[1], s.position_m[2]);
    dQuaternion q;
    to_ode_quaternion(s.orientation, q);
    dBodySetQuaternion(body, q);
    dBodySetLinearVel(body, s.linear_velocity[0], s.linear_velocity[1], s.linear_velocity[2]);
    dBodySetAngularVel(body, s.angular_velocity[0], s.angular_velocity[1], s.angular_velocity[2]);
}

}  // namespace

void initialize_ode_once() {
    static std::once_flag once;
    std::call_once(once, [] {
        dInitODE2(0);
        // ODE would abort() the whole process; a world that hits an internal error is rejected.
        dSetErrorHandler(throw_ode_error);
        dSetDebugHandler(throw_ode_error);
        // Messages (quickstep's "LCP internal error") go with the world being stepped, for a warning.
        dSetMessageHandler(record_ode_message);
    });
}

void prepare_ode_thread() {
    thread_local bool prepared = false;
    if (!prepared) {
        initialize_ode_once();
        dAllocateODEDataForThread(dAllocateMaskAll);
        prepared = true;
    }
}

OdeWorld::OdeWorld(const CompiledScene& compiled, const std::vector<BodyInitialState>& initial,
                   const std::vector<uint8_t>& present)
    : compiled_(compiled), initial_(initial), present_(present) {
    prepare_ode_thread();
    world_ = dWorldCreate();
    threading_ = dThreadingAllocateSelfThreadedImplementation();
    dWorldSetStepThreadingImplementation(world_, dThreadingImplementationGetFunctions(threading_), threading_);
    const Vec3& g = compiled.scene().world.gravity;
    dWorldSetGravity(world_, g[0], g[1], g[2]);
    dWorldSetQuickStepNumIterations(world_, compiled.scene().world.solver_iterations);
    dWorldSetAutoDisableFlag(world_, 0);
    dWorldSetContactSurfaceLayer(world_, 0.001);
    dWorldSetContactMaxCorrectingVel(world_, 10.0);
    contact_group_ = dJointGroupCreate(0);
    create_bodies();
    create_constraints();
}

OdeWorld::~OdeWorld() {
    dJointGroupDestroy(contact_group_);
    for (dGeomID geom : geoms_) dGeomDestroy(geom);
    for (dTriMeshDataID data : mesh_data_) dGeomTriMeshDataDestroy(data);
    dWorldDestroy(world_);
    dThreadingFreeImplementation(threading_);
}

void OdeWorld::create_bodies() {
    const auto& compiled_bodies = compiled_.bodies();
    bodies_.assign(compiled_bodies.size(), nullptr);
    for (size_t i = 0; i < compiled_bodies.size(); ++i) {
        const CompiledBody& cb = compiled_bodies[i];
        const BodyInitialState& s = initial_[i];
        if (!is_present(static_cast<int>(i))) continue;
        if (cb.dynamic || cb.kinematic) {
            dBodyID body = dBodyCreate(world_);
            bodies_[i] = body;
            const Vec3 com = add(s.pose.location, quat_rotate(s.pose.rotation, cb.body_frame_offset_m));
            dBodySetPosition(body, com[0], com[1], com[2]);
            dQuaternion q;
            to_ode_quaternion(s.pose.rotation, q);
            dBodySetQuaternion(body, q);
            if (cb.dynamic) {
                const double scale_factor = s.mass_kg / compiled_.scene().bodies[i].mass_kg;
                const auto& I = cb.inertia;
                dMass mass;
                dMassSetParameters(&mass, s.mass_kg, 0, 0, 0, I[0] * scale_factor, I[4] * scale_factor,
                                   I[8] * scale_factor, I[1] * scale_factor, I[2] * scale_factor, I[5] * scale_factor);
                dBodySetMass(body, &mass);
                dBodySetLinearVel(body, s.linear_velocity[0], s.linear_velocity[1], s.linear_velocity[2]);
                dBodySetAngularVel(body, s.angular_velocity[0], s.angular_velocity[1], s.angular_velocity[2]);
                // Keyed "Animated": the body follows its animation until its handoff step.
                if (cb.handoff_step > 0) dBodySetKinematic(body);
            } else {
                dBodySetKinematic(body);
            }
        }
        create_geoms(i, cb.parts, bodies_[i], false);
    }
}

void OdeWorld::create_geoms(size_t body_index, const std::vector<CollisionPart>& parts, dBodyID owner, bool ghost) {
    const Body& body = compiled_.scene().bodies[body_index];
    const uint32_t collections = body.collision_collections;
    for (const CollisionPart& part : parts) {
        dGeomID geom = nullptr;
        switch (part.kind) {
            case PartKind::Box:
                geom = dCreateBox(nullptr, 2 * part.half_extents_m[0], 2 * part.half_extents_m[1], 2 * part.half_extents_m[2]);
                break;
            case PartKind::Sphere: geom = dCreateSphere(nullptr, part.radius_m); break;
            case PartKind::Capsule: geom = dCreateCapsule(nullptr, part.radius_m, part.length_m); break;
            case PartKind::Cylinder: geom = dCreateCylinder(nullptr, part.radius_m, part.length_m); break;
            case PartKind::Convex:
                geom = dCreateConvex(nullptr, part.convex_planes.data(), part.convex_plane_count,
                                     part.convex_points.data(), part.convex_point_count, part.convex_polygons.data());
                break;
            case PartKind::TriangleMesh: {
                dTriMeshDataID data = dGeomTriMeshDataCreate();
                mesh_data_.push_back(data);
                dGeomTriMeshDataBuildDouble(data, part.mesh_vertices.data(), 3 * sizeof(double),
                                            static_cast<int>(part.mesh_vertices.size() / 3), part.mesh_indices.data(),
                                            static_cast<int>(part.mesh_indices.size()), 3 * sizeof(uint32_t));
                // Convex-vs-mesh collisions (libccd) need the face angles.
                dGeomTriMeshDataPreprocess2(data, 1u << dTRIDATAPREPROCESS_BUILD_FACE_ANGLES, nullptr);
                geom = dCreateTriMesh(nullptr, data, nullptr, nullptr, nullptr);
                break;
            }
        }
        geoms_.push_back(geom);
        if (ghost) ghost_geoms_[body_index].push_back(geom);
        dGeomSetData(geom, reinterpret_cast<void*>(static_cast<intptr_t>(geom_owners_.size())));
        geom_owners_.push_back({static_cast<int32_t>(body_index), part.kind == PartKind::TriangleMesh, ghost,
                                part.mesh_margin_m});
        // Blender bodies collide when they share a collision collection.
        dGeomSetCategoryBits(geom, collections);
        dGeomSetCollideBits(geom, collections);
        // Every part but a triangle mesh sits at its offset (a convex part's points are about it;
        // one whose offset is zero is placed as the body, as it always was, so its worlds stay).
        const bool primitive = part.kind != PartKind::TriangleMesh &&
                               (part.kind != PartKind::Convex || part.offset.location != Vec3{0, 0, 0});
        dQuaternion q;
        to_ode_quaternion(part.offset.rotation, q);
        if (owner) {
            dGeomSetBody(geom, owner);
            if (primitive) {
                dGeomSetOffsetPosition(geom, part.offset.location[0], part.offset.location[1], part.offset.location[2]);
                dGeomSetOffsetQuaternion(geom, q);
            }
        } else {
            const Transform& pose = initial_[body_index].pose;
            const Transform placed = primitive ? Transform{add(pose.location, quat_rotate(pose.rotation, part.offset.location)),
                                                           quat_multiply(pose.rotation, part.offset.rotation)}
                                               : pose;
            dGeomSetPosition(geom, placed.location[0], placed.location[1], placed.location[2]);
            to_ode_quaternion(placed.rotation, q);
            dGeomSetQuaternion(geom, q);
        }
    }
}

void OdeWorld::create_constraints() {
    const Scene& scene = compiled_.scene();
    joint_groups_.resize(scene.constraints.size());
    for (size_t i = 0; i < scene.constraints.size(); ++i) {
        const Constraint& c = scene.constraints[i];
        const int a = scene.body_index(c.body_a);
        const int b = scene.body_index(c.body_b);
        if (c.disable_collisions) no_collision_pairs_.emplace_back(std::min(a, b), std::max(a, b));
        if (c.enabled && is_present(a) && is_present(b))
            joint_groups_[i] = build_constraint_joints(world_, c, a >= 0 ? bodies_[a] : nullptr,
                                                       b >= 0 ? bodies_[b] : nullptr, compiled_.physics_dt_s());
    }
    std::sort(no_collision_pairs_.begin(), no_collision_pairs_.end());
}

bool OdeWorld::collision_disabled(int32_t a, int32_t b) const {
    const std::pair<int32_t, int32_t> key{std::min(a, b), std::max(a, b)};
    return std::binary_search(no_collision_pairs_.begin(), no_collision_pairs_.end(), key);
}

BodyState OdeWorld::body_state(size_t i) const {
    BodyState s;
    dBodyID body = bodies_[i];
    if (!body) {
        const Transform& pose = initial_[i].pose;
        return {pose.location, pose.rotation, {0, 0, 0}, {0, 0, 0}};
    }
    s.position_m = from_ode(dBodyGetPosition(body));
    const dReal* q = dBodyGetQuaternion(body);
    s.orientation = {q[0], q[1], q[2], q[3]};
    s.linear_velocity = from_ode(dBodyGetLinearVel(body));
    s.angular_velocity = from_ode(dBodyGetAngularVel(body));
    return s;
}

void OdeWorld::set_body_state(size_t i, const BodyState& s) {
    if (bodies_[i]) set_state(bodies_[i], s);
}

void OdeWorld::set_ghost_state(size_t i, const BodyState& s) { set_state(ghost_bodies_[i], s); }

void OdeWorld::set_kinematic(size_t i, bool kinematic) {
    if (!bodies_[i]) return;
    if (kinematic) dBodySetKinematic(bodies_[i]);
    else dBodySetDynamic(bodies_[i]);
}

void OdeWorld::add_ghost(size_t i) {
    ghost_bodies_.resize(bodies_.size(), nullptr);
    ghost_geoms_.resize(bodies_.size());
    if (ghost_bodies_[i]) return;
    dBodyID ghost = dBodyCreate(world_);
    dBodySetKinematic(ghost);
    ghost_bodies_[i] = ghost;
    create_geoms(i, compiled_.bodies()[i].ghost_parts, ghost, true);
}

void OdeWorld::set_ghost_enabled(size_t i, bool enabled) {
    if (i >= ghost_geoms_.size()) return;
    for (dGeomID geom : ghost_geoms_[i]) {
        if (enabled) dGeomEnable(geom);
        else dGeomDisable(geom);
    }
}

void OdeWorld::break_joint(size_t constraint_index) {
    JointGroup& group = joint_groups_[constraint_index];
    for (dJointID joint : group.joints) dJointDisable(joint);
    group.broken = true;
}

void OdeWorld::break_overloaded_joints() {
    const auto& constraints = compiled_.scene().constraints;
    for (size_t i = 0; i < joint_groups_.size(); ++i) {
        const JointGroup& group = joint_groups_[i];
        if (group.broken || !group.feedback) continue;
        // Bullet breaks a constraint when the impulse of any one of its rows (the linear and
        // angular axes of the constraint's frame) reaches the threshold within a step. ODE reports
        // the force and torque on the first body about its centre of mass: the torque is moved
        // to the constraint's pivot, and both are read along the frame's axes.
        const dBodyID body = dJointGetBody(group.joints.front(), 0);
        const dReal* q = dBodyGetQuaternion(body);
        const Quat rotation{q[0], q[1], q[2], q[3]};
        const Vec3 arm = quat_rotate(rotation, group.frame_in_body.location);  // centre of mass to pivot
        const Vec3 force{group.feedback->f1[0], group.feedback->f1[1], group.feedback->f1[2]};
        const Vec3 torque_at_com{group.feedback->t1[0], group.feedback->t1[1], group.feedback->t1[2]};
        const Vec3 torque = sub(torque_at_com, cross(arm, force));
        const Quat to_frame = quat_conjugate(quat_multiply(rotation, group.frame_in_body.rotation));
        const Vec3 f = quat_rotate(to_frame, force), t = quat_rotate(to_frame, torque);
        double largest = 0;
        for (int k = 0; k < 3; ++k) largest = std::max({largest, std::fabs(f[k]), std::fabs(t[k])});
        if (largest * compiled_.physics_dt_s() >= constraints[i].breaking_threshold) break_joint(i);
    }
}

Transform OdeWorld::object_transform(size_t i) const {
    if (!bodies_[i]) return initial_[i].pose;
    const BodyState s = body_state(i);
    const Vec3& offset = compiled_.bodies()[i].body_frame_offset_m;
    return {sub(s.position_m, quat_rotate(s.orientation, offset)), s.orientation};
}

}  // namespace mwb
