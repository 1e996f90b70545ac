#include "sim/ContactGenerator.h"

#include <algorithm>
#include <cmath>
#include <mutex>

#include "sim/BodySleep.h"

namespace mwb {
namespace {

constexpr int kMaxContactsPerPair = 4;

// libode has one scratch cache for triangle-mesh collisions in this build; two threads in it at
// once corrupt each other.
std::mutex g_trimesh_mutex;

// Up to `max` contacts between two geoms, holding the mesh lock when either is a triangle mesh.
int collide(dGeomID a, dGeomID b, bool either_is_mesh, int max, dContactGeom* out) {
    if (!either_is_mesh) return dCollide(a, b, max, out, sizeof(dContactGeom));
    std::lock_guard<std::mutex> lock(g_trimesh_mutex);
    return dCollide(a, b, max, out, sizeof(dContactGeom));
}

}  // namespace

ContactGenerator::ContactGenerator(OdeWorld& world, const BodyActivity& activity) : world_(world), activity_(activity) {}

bool ContactGenerator::stepped(int32_t body) const {
    return body >= 0 && activity_.simulated(static_cast<size_t>(body)) &&
           !(sleep_ && sleep_->asleep(static_cast<size_t>(body)));
}

void ContactGenerator::find_candidate_pairs() {
    broad_phase_.find_pairs(world_.geoms(), pairs_);
    const std::vector<dGeomID>& geoms = world_.geoms();
    candidates_.clear();
    for (const GeomPair& p : pairs_) candidates_.push_back({p.first, p.second, geoms[p.first], geoms[p.second]});
    std::sort(candidates_.begin(), candidates_.end());
    deepest_.assign(world_.bodies().size(), DeepestContact{});
}

void ContactGenerator::create_contacts() {
    for (const CandidatePair& pair : candidates_) collide_pair(pair);
}

bool ContactGenerator::touching(const CandidatePair& pair) const {
    const auto& owners = world_.geom_owners();
    const bool either_is_mesh = owners[pair.first_index].is_mesh || owners[pair.second_index].is_mesh;
    dContactGeom contact;
    return without_sphere_mesh_margin(pair, &contact, collide(pair.first, pair.second, either_is_mesh, 1, &contact)) != 0;
}

void ContactGenerator::collide_pair(const CandidatePair& pair) {
    const auto& owners = world_.geom_owners();
    const GeomOwner& oa = owners[pair.first_index];
    const GeomOwner& ob = owners[pair.second_index];
    if (oa.body == ob.body || oa.ghost || ob.ghost) return;
    if (!stepped(oa.body) && !stepped(ob.body)) return;
    if (world_.collision_disabled(oa.body, ob.body)) return;
    dContactGeom contacts[kMaxContactsPerPair];
    int count = collide(pair.first, pair.second, oa.is_mesh || ob.is_mesh, kMaxContactsPerPair, contacts);
    count = without_sphere_mesh_margin(pair, contacts, count);
    count = without_degenerate_contacts(contacts, count);
    if (count == 0) return;
    const BodyInitialState& ma = world_.initial_states()[oa.body];
    const BodyInitialState& mb = world_.initial_states()[ob.body];
    dSurfaceParameters surface{};
    // Bullet (Blender) combines friction and restitution by multiplication.
    surface.mode = dContactApprox1;
    surface.mu = ma.friction * mb.friction;
    const double bounce = ma.restitution * mb.restitution;
    if (bounce > 0) {
        surface.mode |= dContactBounce;
        surface.bounce = bounce;
        surface.bounce_vel = 0.1;
    }
    dBodyID ba = world_.bodies()[oa.body];
    dBodyID bb = world_.bodies()[ob.body];
    for (int k = 0; k < count; ++k) {
        dContact contact{};
        contact.surface = surface;
        contact.geom = contacts[k];
        dJointID joint = dJointCreateContact(world_.world(), world_.contact_group(), &contact);
        dJointAttach(joint, ba, bb);
        note_contact(oa.body, ob.body, contacts[k]);
        note_contact(ob.body, oa.body, contacts[k]);
    }
}

int ContactGenerator::without_degenerate_contacts(dContactGeom* contacts, int count) {
    // Some of ODE's colliders return a contact with no direction (a zero or NaN normal) when two
    // faces lie exactly on each other; solved, it turns a body's state into NaN.
    int kept = 0;
    for (int k = 0; k < count; ++k) {
        const dContactGeom& c = contacts[k];
        const double n = std::sqrt(c.normal[0] * c.normal[0] + c.normal[1] * c.normal[1] + c.normal[2] * c.normal[2]);
        if (std::isfinite(c.depth) && std::isfinite(c.pos[0]) && std::isfinite(c.pos[1]) && std::isfinite(c.pos[2]) &&
            std::fabs(n - 1) < 1e-3)
            contacts[kept++] = c;
    }
    return kept;
}

int ContactGenerator::without_sphere_mesh_margin(const CandidatePair& pair, dContactGeom* contacts, int count) const {
    // Bullet's sphere-triangle test ignores the mesh's margin that every other shape meets: a
    // sphere touches the mesh itself, so the thickened mesh's contacts are that much shallower.
    const auto& owners = world_.geom_owners();
    const GeomOwner& oa = owners[pair.first_index];
    const GeomOwner& ob = owners[pair.second_index];
    double margin = 0;
    if (dGeomGetClass(pair.second) == dSphereClass) margin = oa.mesh_margin_m;
    if (dGeomGetClass(pair.first) == dSphereClass) margin = ob.mesh_margin_m;
    if (margin <= 0) return count;
    int kept = 0;
    for (int k = 0; k < count; ++k) {
        contacts[k].depth -= margin;
        if (contacts[k].depth > 0) contacts[kept++] = contacts[k];
    }
    return kept;
}

void ContactGenerator::note_contact(int32_t body, int32_t other, const dContactGeom& contact) {
    DeepestContact& slot = deepest_[body];
    if (contact.depth > slot.depth) slot = {other, contact.depth, from_ode(contact.pos), from_ode(contact.normal)};
}

}  // namespace mwb
