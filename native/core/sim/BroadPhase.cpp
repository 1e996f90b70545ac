#include "sim/BroadPhase.h"

#include <algorithm>
#include <cmath>

namespace mwb {
namespace {

// ODE leaves a geom with a zero dimension out of every space's pairs.
bool zero_sized(dGeomID geom) {
    switch (dGeomGetClass(geom)) {
        case dBoxClass: {
            dVector3 lengths;
            dGeomBoxGetLengths(geom, lengths);
            return lengths[0] == 0 || lengths[1] == 0 || lengths[2] == 0;
        }
        case dSphereClass: return dGeomSphereGetRadius(geom) == 0;
        case dCapsuleClass: {
            dReal radius, length;
            dGeomCapsuleGetParams(geom, &radius, &length);
            return radius == 0;
        }
        case dCylinderClass: {
            dReal radius, length;
            dGeomCylinderGetParams(geom, &radius, &length);
            return radius == 0 || length == 0;
        }
        default: return false;
    }
}

}  // namespace

bool BroadPhase::finite(const Extent& e) {
    return std::isfinite(e.x_min) && std::isfinite(e.x_max) && std::isfinite(e.y_min) && std::isfinite(e.y_max) &&
           std::isfinite(e.z_min) && std::isfinite(e.z_max);
}

BroadPhase::Extent BroadPhase::extent_of(dGeomID geom, uint32_t index) {
    dReal box[6];
    dGeomGetAABB(geom, box);
    return {static_cast<float>(box[0]), static_cast<float>(box[1]), box[2], box[3], box[4], box[5], index,
            dGeomGetBody(geom), dGeomGetCategoryBits(geom), dGeomGetCollideBits(geom)};
}

void BroadPhase::add_new_geoms(const std::vector<dGeomID>& geoms) {
    bool fixed_added = false;
    for (; geoms_seen_ < geoms.size(); ++geoms_seen_) {
        const dGeomID geom = geoms[geoms_seen_];
        const auto index = static_cast<uint32_t>(geoms_seen_);
        // A geom's size never changes here, so a zero-sized one is left out for good.
        if (zero_sized(geom)) continue;
        if (dGeomGetBody(geom)) {
            moving_.push_back(index);
            continue;
        }
        const Extent e = extent_of(geom, index);
        if (dGeomIsEnabled(geom) && finite(e)) {
            fixed_.push_back(e);
            fixed_added = true;
        }
    }
    if (fixed_added) std::sort(fixed_.begin(), fixed_.end(), starts_before);
}

void BroadPhase::sort_moving() {
    // From one step to the next the moving geoms keep nearly the same order in x, so an insertion
    // sort from last step's order costs about one pass. The order is total (ties by geom), so any
    // sort gives the same.
    for (size_t i = 1; i < moving_now_.size(); ++i) {
        const Extent e = moving_now_[i];
        size_t j = i;
        for (; j > 0 && starts_before(e, moving_now_[j - 1]); --j) moving_now_[j] = moving_now_[j - 1];
        moving_now_[j] = e;
    }
    size_t k = 0;
    for (const Extent& e : moving_now_) moving_[k++] = e.geom;
}

void BroadPhase::add_if_pair(const Extent& a, const Extent& b, std::vector<GeomPair>& out) {
    // x overlaps already (the sweep); y and z inclusively, as ODE's sweep tests them.
    if (!(a.y_max >= b.y_min && b.y_max >= a.y_min && a.z_max >= b.z_min && b.z_max >= a.z_min)) return;
    if (a.body && a.body == b.body) return;
    if (!((a.category & b.collide) || (b.category & a.collide))) return;
    out.push_back({std::min(a.geom, b.geom), std::max(a.geom, b.geom)});
}

void BroadPhase::find_pairs(const std::vector<dGeomID>& geoms, std::vector<GeomPair>& out) {
    out.clear();
    add_new_geoms(geoms);
    moving_now_.clear();
    left_out_.clear();
    for (uint32_t i : moving_) {
        // A body gone non-finite is rejected after this step (ImpactResponse); until then it
        // touches nothing, and it must not reach the sort.
        if (dGeomIsEnabled(geoms[i])) {
            const Extent e = extent_of(geoms[i], i);
            if (finite(e)) {
                moving_now_.push_back(e);
                continue;
            }
        }
        left_out_.push_back(i);
    }
    sort_moving();
    std::copy(left_out_.begin(), left_out_.end(), moving_.begin() + static_cast<std::ptrdiff_t>(moving_now_.size()));
    // Every pair whose x ranges overlap (closed intervals) is found once: from the one of the two
    // that starts first in x, scanning those that start within its range; a fixed geom and a
    // moving one starting at the same x are found from the moving one.
    for (size_t i = 0; i < moving_now_.size(); ++i) {
        const Extent& a = moving_now_[i];
        for (size_t j = i + 1; j < moving_now_.size() && moving_now_[j].x_min <= a.x_max; ++j)
            add_if_pair(a, moving_now_[j], out);
        auto f = std::lower_bound(fixed_.begin(), fixed_.end(), a.x_min,
                                  [](const Extent& e, float x) { return e.x_min < x; });
        for (; f != fixed_.end() && f->x_min <= a.x_max; ++f) add_if_pair(a, *f, out);
    }
    size_t first_after = 0;  // the first moving geom starting after the fixed one, in x
    for (const Extent& f : fixed_) {
        while (first_after < moving_now_.size() && !(moving_now_[first_after].x_min > f.x_min)) ++first_after;
        for (size_t j = first_after; j < moving_now_.size() && moving_now_[j].x_min <= f.x_max; ++j)
            add_if_pair(f, moving_now_[j], out);
    }
}

}  // namespace mwb
