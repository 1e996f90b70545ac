#pragma once
// The contacts of one world step. They are generated in a fixed order (broad-phase pairs sorted
// by geom index, whatever order the broad phase found them in) so that a restart from a
// checkpoint replays exactly.
#include <cstdint>
#include <vector>

#include <ode/ode.h>

#include "sim/BodyActivity.h"
#include "sim/BroadPhase.h"
#include "sim/OdeWorld.h"

namespace mwb {

class BodySleep;

/// A broad-phase pair, keyed by geom indices (OdeWorld::geom_owners()) so it can be put in a fixed order.
struct CandidatePair {
    intptr_t first_index, second_index;  ///< first_index < second_index
    dGeomID first, second;
    bool operator<(const CandidatePair& other) const {
        return first_index != other.first_index ? first_index < other.first_index : second_index < other.second_index;
    }
};

/// The deepest contact point a body had in the last step, world frame.
struct DeepestContact {
    int32_t other = -1;  ///< the body touched; -1: none
    double depth = -1;   ///< m
    Vec3 point{0, 0, 0};
    Vec3 normal{0, 0, 1};
};

/// One per world run; not thread-safe (a world runs on one thread). Worlds on other threads may
/// collide at the same time: triangle-mesh collisions take a process-wide lock.
class ContactGenerator {
public:
    ContactGenerator(OdeWorld& world, const BodyActivity& activity);

    /// Collects this step's broad-phase pairs in geom-index order and forgets the last step's contacts.
    void find_candidate_pairs();
    const std::vector<CandidatePair>& candidate_pairs() const { return candidates_; }
    /// Sleeping bodies (sim/BodySleep) make no contacts with each other or with fixed bodies.
    void set_sleep(const BodySleep* sleep) { sleep_ = sleep; }
    /// Adds ODE contact joints (to the world's contact group) for every candidate pair with a
    /// simulated body that may collide, at most four per pair, and notes each body's deepest contact.
    void create_contacts();
    /// Whether the geoms of `pair` touch now.
    bool touching(const CandidatePair& pair) const;
    /// Body i's deepest contact in this step's contacts.
    const DeepestContact& deepest_contact(size_t i) const { return deepest_[i]; }

private:
    /// Stepped by ODE in this step: simulated and not asleep.
    bool stepped(int32_t body) const;
    void collide_pair(const CandidatePair& pair);
    /// Drops contacts without a usable normal or depth; returns how many remain.
    static int without_degenerate_contacts(dContactGeom* contacts, int count);
    /// Drops Blender's mesh margin from sphere-mesh contacts; returns how many contacts remain.
    int without_sphere_mesh_margin(const CandidatePair& pair, dContactGeom* contacts, int count) const;
    void note_contact(int32_t body, int32_t other, const dContactGeom& contact);

    OdeWorld& world_;
    const BodyActivity& activity_;
    BroadPhase broad_phase_;
    std::vector<GeomPair> pairs_;
    std::vector<CandidatePair> candidates_;
    const BodySleep* sleep_ = nullptr;
    std::vector<DeepestContact> deepest_;  ///< per body
};

}  // namespace mwb
