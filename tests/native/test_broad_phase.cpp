// The engine's broad phase against ODE's own sweep-and-prune space: the same pairs, except those of
// two fixed geoms, on scenes built to hit its edges (boxes that only touch, gaps below single
// precision, shared bodies, collision bits, disabled and zero-sized geoms, geoms added late).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <utility>
#include <vector>

#include <ode/ode.h>

#include "sim/BroadPhase.h"
#include "sim/OdeWorld.h"
#include "sim/PortableRandom.h"

namespace mwb {
namespace {

using PairSet = std::set<std::pair<uint32_t, uint32_t>>;

struct Geoms {
    dWorldID world = dWorldCreate();
    std::vector<dGeomID> list;
    ~Geoms() {
        for (dGeomID g : list) dGeomDestroy(g);
        dWorldDestroy(world);
    }
    dGeomID add(dGeomID geom) {
        dGeomSetData(geom, reinterpret_cast<void*>(static_cast<intptr_t>(list.size())));
        list.push_back(geom);
        return geom;
    }
};

void near_pair(void* data, dGeomID a, dGeomID b) {
    auto ia = static_cast<uint32_t>(reinterpret_cast<intptr_t>(dGeomGetData(a)));
    auto ib = static_cast<uint32_t>(reinterpret_cast<intptr_t>(dGeomGetData(b)));
    static_cast<PairSet*>(data)->insert({std::min(ia, ib), std::max(ia, ib)});
}

// What ODE's sweep and prune reports, less the pairs of two geoms without a body.
PairSet ode_pairs(const std::vector<dGeomID>& geoms) {
    const dSpaceID space = dSweepAndPruneSpaceCreate(nullptr, dSAP_AXES_XYZ);
    dSpaceSetCleanup(space, 0);
    for (dGeomID g : geoms) dSpaceAdd(space, g);
    PairSet all;
    dSpaceCollide(space, &all, near_pair);
    dSpaceDestroy(space);
    PairSet kept;
    for (const auto& p : all)
        if (dGeomGetBody(geoms[p.first]) || dGeomGetBody(geoms[p.second])) kept.insert(p);
    return kept;
}

PairSet engine_pairs(BroadPhase& broad_phase, const std::vector<dGeomID>& geoms) {
    std::vector<GeomPair> found;
    broad_phase.find_pairs(geoms, found);
    PairSet set;
    for (const GeomPair& p : found) {
        EXPECT_LT(p.first, p.second);
        EXPECT_TRUE(set.insert({p.first, p.second}).second) << "pair " << p.first << "-" << p.second << " twice";
    }
    return set;
}

TEST(BroadPhase, FindsWhatOdesSweepFindsLessPairsOfFixedGeoms) {
    initialize_ode_once();
    prepare_ode_thread();
    Geoms g;
    PortableRandom random(7);
    const auto uniform = [&](double lo, double hi) { return lo + (hi - lo) * random.uniform01(); };
    // A floor and a wall of unit boxes whose faces touch: fixed pairs only, and moving boxes
    // landing exactly on them.
    g.add(dCreateBox(nullptr, 20, 20, 1));
    dGeomSetPosition(g.list.back(), 0, 0, -0.5);
    for (int k = 0; k < 10; ++k) {
        g.add(dCreateBox(nullptr, 1, 1, 1));
        dGeomSetPosition(g.list.back(), k + 0.5, 3.5, 0.5);
    }
    // A fixed box whose right face is 1e-12 m left of a moving box's left face: apart in double,
    // the same x in single precision, so ODE's sweep pairs them.
    g.add(dCreateBox(nullptr, 1, 1, 1));
    dGeomSetPosition(g.list.back(), -5.5, -5.5, 0.5);
    std::vector<dBodyID> bodies;
    const auto body_at = [&](double x, double y, double z) {
        dBodyID b = dBodyCreate(g.world);
        dBodySetPosition(b, x, y, z);
        bodies.push_back(b);
        return b;
    };
    dGeomSetBody(g.add(dCreateBox(nullptr, 1, 1, 1)), body_at(-4.5 + 1e-12, -5.3, 0.7));
    // A unit box that will stand beside the wall, touching it in y.
    dGeomSetBody(g.add(dCreateBox(nullptr, 1, 1, 1)), body_at(-3, 0, 3));
    // Moving shapes of every kind, some sharing a body, some in other collision collections.
    for (int k = 0; k < 40; ++k) {
        dGeomID geom = nullptr;
        switch (k % 4) {
            case 0: geom = dCreateBox(nullptr, uniform(0.2, 2), uniform(0.2, 2), uniform(0.2, 2)); break;
            case 1: geom = dCreateSphere(nullptr, uniform(0.1, 1)); break;
            case 2: geom = dCreateCapsule(nullptr, uniform(0.1, 0.5), uniform(0.2, 2)); break;
            default: geom = dCreateCylinder(nullptr, uniform(0.1, 0.5), uniform(0.2, 2)); break;
        }
        g.add(geom);
        if (k % 5 == 4) dGeomSetBody(geom, bodies.back());
        else dGeomSetBody(geom, body_at(uniform(-6, 6), uniform(-6, 6), uniform(-1, 3)));
        if (k % 7 == 3) {
            dGeomSetCategoryBits(geom, 2);
            dGeomSetCollideBits(geom, 2);
        }
    }
    // Fixed shapes scattered among them, and geoms ODE leaves out: disabled, zero-sized.
    for (int k = 0; k < 30; ++k) {
        g.add(dCreateSphere(nullptr, uniform(0.2, 1.5)));
        dGeomSetPosition(g.list.back(), uniform(-6, 6), uniform(-6, 6), uniform(-1, 3));
    }
    const dGeomID switched = g.add(dCreateSphere(nullptr, 1));  // disabled and enabled in turn, as a ghost is
    dGeomDisable(switched);
    dGeomSetBody(switched, body_at(0, 0, 0));
    dGeomSetBody(g.add(dCreateBox(nullptr, 1, 0, 1)), body_at(1, 1, 0.5));

    BroadPhase broad_phase;
    size_t pairs_seen = 0;
    for (int step = 0; step < 30; ++step) {
        const PairSet expected = ode_pairs(g.list);
        const PairSet found = engine_pairs(broad_phase, g.list);
        EXPECT_EQ(found, expected) << "step " << step;
        pairs_seen += expected.size();
        if (step == 0) {
            EXPECT_TRUE(expected.count({11, 12})) << "the gap below single precision";
        }
        // Move every body (the two unit boxes onto the wall's top and against its side, their
        // faces on the wall's), add a geom now and then.
        const double along = std::floor(uniform(0, 10)) + 0.5;
        dBodySetPosition(bodies[0], along, 3.5, 1.5);
        dBodySetPosition(bodies[1], along, 4.5, 0.5);
        for (size_t b = 2; b < bodies.size(); ++b)
            dBodySetPosition(bodies[b], uniform(-6, 6), uniform(-6, 6), uniform(-1, 3));
        if (step % 4 == 2) {
            if (dGeomIsEnabled(switched)) dGeomDisable(switched);
            else dGeomEnable(switched);
        }
        if (step % 10 == 5) {
            g.add(dCreateBox(nullptr, 1, 1, 1));
            dGeomSetPosition(g.list.back(), uniform(-6, 6), uniform(-6, 6), uniform(-1, 3));
            dGeomSetBody(g.add(dCreateSphere(nullptr, 0.7)), body_at(uniform(-6, 6), uniform(-6, 6), uniform(-1, 3)));
        }
    }
    EXPECT_GT(pairs_seen, 300u) << "too few overlaps to compare";
}

}  // namespace
}  // namespace mwb
