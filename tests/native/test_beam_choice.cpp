// Which worlds a goal search refines next: one place per family, best first; a family far behind
// the leader gives its place to the leader's next best worlds, unless it is well ahead of the
// leader's pace on an ordered goal; the beam is filled whenever there are worlds to fill it.
#include <gtest/gtest.h>

#include "seek/BeamChoice.h"

namespace mwb {
namespace {

using Beam = std::vector<uint64_t>;

BeamRule rule(uint32_t width, uint32_t per_family) {
    BeamRule r;
    r.width = width;
    r.per_family = per_family;
    return r;
}

TEST(BeamChoice, OnePlacePerFamilyBestFirst) {
    // Family 1 holds the two best worlds; families 2 and 3 are a part behind.
    const std::vector<BeamCandidate> worlds = {{10, 1, 5.6}, {11, 1, 5.5}, {20, 2, 4.9}, {30, 3, 4.2}, {21, 2, 4.1}};
    EXPECT_EQ(choose_beam(worlds, rule(3, 1)), (Beam{10, 20, 30}));
    // Wider than the families: the best of the rest fill it.
    EXPECT_EQ(choose_beam(worlds, rule(4, 1)), (Beam{10, 20, 30, 11}));
    EXPECT_EQ(choose_beam(worlds, rule(2, 2)), (Beam{10, 11}));
}

TEST(BeamChoice, AFamilyFarBehindGivesItsPlaceToTheLeadersNextBest) {
    // The staircase's shape: the leader at 20 of 21 parts, one family 2 parts behind, two 10 behind.
    const std::vector<BeamCandidate> worlds = {{450, 334, 20.73}, {545, 334, 20.72}, {867, 334, 20.70},
                                               {523, 341, 18.60}, {530, 15, 10.61}, {409, 10, 10.56}};
    EXPECT_EQ(choose_beam(worlds, rule(4, 1)), (Beam{450, 523, 545, 867}));
    // Exactly `reach` parts behind is within reach; closeness does not count, only whole parts.
    const std::vector<BeamCandidate> edge = {{1, 1, 13.99}, {2, 1, 13.5}, {3, 2, 10.01}, {4, 3, 9.99}};
    EXPECT_EQ(choose_beam(edge, rule(3, 1)), (Beam{1, 3, 2}));
}

TEST(BeamChoice, FamiliesFarBehindStillFillABeamTheLeadersCannot) {
    // The leader has one open world left: the others, however far behind, are refined rather
    // than nothing.
    const std::vector<BeamCandidate> worlds = {{7, 7, 20.2}, {8, 8, 9.5}, {9, 9, 8.5}};
    EXPECT_EQ(choose_beam(worlds, rule(4, 1)), (Beam{7, 8, 9}));
    EXPECT_TRUE(choose_beam({}, rule(4, 1)).empty());
    EXPECT_TRUE(choose_beam(worlds, rule(0, 1)).empty());
}

TEST(BeamChoice, AFamilyWellAheadOfTheLeadersPaceTakesTheLastPlace) {
    // The staircase from base seed 0: four slow families met 7, 6, 5 and 4 steps by 37-38 s of 40;
    // a start 8 parts behind met 3 by 4.9 s, when the leader had met 1.
    const std::vector<double> leader = {2.3, 5.7, 11.7, 19.0, 24.7, 32.9, 38.2}, second = {2.0, 7.5, 17.4, 26.1, 32.1, 38.2},
                              third = {1.8, 8.4, 20.7, 28.4, 38.6}, fourth = {1.9, 10.4, 24.2, 36.7},
                              quick = {1.4, 2.6, 4.9}, first_step_sooner = {1.3};
    const std::vector<BeamCandidate> worlds = {
        {1060, 650, 16.54, &leader}, {2622, 29, 15.48, &second}, {1910, 1910, 14.45, &third},
        {2187, 2187, 13.47, &fourth}, {1349, 1349, 9.12, &quick}, {1614, 1614, 8.07, &first_step_sooner}};
    EXPECT_EQ(pace_lead(worlds[4], worlds[0]), 2);
    EXPECT_EQ(pace_lead(worlds[5], worlds[0]), 1);
    EXPECT_EQ(pace_lead(worlds[3], worlds[0]), 4 - 6);
    EXPECT_EQ(choose_beam(worlds, rule(4, 1)), (Beam{1060, 2622, 1910, 1349}));
    // One step ahead is not enough: a sooner first step is common among fresh worlds.
    const std::vector<BeamCandidate> without_quick = {worlds[0], worlds[1], worlds[2], worlds[3], worlds[5]};
    EXPECT_EQ(choose_beam(without_quick, rule(4, 1)), (Beam{1060, 2622, 1910, 2187}));
    // Off, or a beam with room for every world: as before.
    BeamRule off = rule(4, 1);
    off.pace_lead_parts = 0;
    EXPECT_EQ(choose_beam(worlds, off), (Beam{1060, 2622, 1910, 2187}));
    EXPECT_EQ(choose_beam(worlds, rule(6, 1)), (Beam{1060, 2622, 1910, 2187, 1349, 1614}));
    // A goal without order has no pace: nothing changes.
    std::vector<BeamCandidate> unordered = worlds;
    for (BeamCandidate& c : unordered) c.ordered_met_s = nullptr;
    EXPECT_EQ(choose_beam(unordered, rule(4, 1)), (Beam{1060, 2622, 1910, 2187}));
}

}  // namespace
}  // namespace mwb
