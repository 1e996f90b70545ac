#pragma once
// Which geoms of a world may touch in a step: the pairs whose bounding boxes overlap, as ODE's
// sweep-and-prune space reports them (x compared in single precision, as it sorts, y and z in
// double), except the pairs of two fixed geoms. Fixed geoms (passive bodies that are not
// animated) never move and never make a contact with each other, yet a sweep over all geoms pays
// for them every step: on the staircase, 99 fixed geoms and 11 moving ones, that sweep was 13% of
// a search's time. Here fixed geoms are sorted once, and each step sorts only the moving ones and
// sweeps them against the fixed.
#include <cstdint>
#include <vector>

#include <ode/ode.h>

namespace mwb {

/// Two geoms whose bounding boxes overlap, by their indices in the list given to BroadPhase.
struct GeomPair {
    uint32_t first, second;  ///< first < second
};

/// One per world run; not thread-safe.
class BroadPhase {
public:
    /// Overlapping pairs of `geoms` with at least one geom moving, in no particular order, into
    /// `out` (cleared first). Geoms may be added at the end between calls; a geom without a body
    /// must not move or change its collision bits once added. Like ODE's spaces, pairs leave out
    /// disabled and zero-sized geoms, geoms of one body, and geoms whose category and collide bits
    /// do not meet.
    void find_pairs(const std::vector<dGeomID>& geoms, std::vector<GeomPair>& out);

private:
    struct Extent {
        float x_min, x_max;  ///< single precision, as ODE's sweep sorts them
        double y_min, y_max, z_min, z_max;
        uint32_t geom;
        dBodyID body;
        unsigned long category, collide;
    };

    static bool starts_before(const Extent& a, const Extent& b) {
        return a.x_min != b.x_min ? a.x_min < b.x_min : a.geom < b.geom;
    }
    static bool finite(const Extent& e);
    static Extent extent_of(dGeomID geom, uint32_t index);
    void add_new_geoms(const std::vector<dGeomID>& geoms);
    void sort_moving();
    static void add_if_pair(const Extent& a, const Extent& b, std::vector<GeomPair>& out);

    size_t geoms_seen_ = 0;
    std::vector<uint32_t> moving_;     ///< geoms with a body (none zero-sized), by x_min last step
    std::vector<Extent> fixed_;        ///< enabled fixed geoms, by x_min
    std::vector<Extent> moving_now_;   ///< this step's enabled moving geoms, by x_min
    std::vector<uint32_t> left_out_;   ///< this step's disabled (or non-finite) moving geoms
};

}  // namespace mwb
