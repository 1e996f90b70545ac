// Which worlds a goal search refines next: one place per family, best first; a family far behind
// the leader gives its place to the leader's next best worlds; the beam is filled whenever there
// are worlds to fill it.
#include <gtest/gtest.h>

#include "seek/BeamChoice.h"

namespace mwb {
namespace {

using Beam = std::vector<uint64_t>;

TEST(BeamChoice, OnePlacePerFamilyBestFirst) {
    // Family 1 holds the two best worlds; families 2 and 3 are a part behind.
    const std::vector<BeamCandidate> worlds = {{10, 1, 5.6}, {11, 1, 5.5}, {20, 2, 4.9}, {30, 3, 4.2}, {21, 2, 4.1}};
    EXPECT_EQ(choose_beam(worlds, 3, 1, 3), (Beam{10, 20, 30}));
    // Wider than the families: the best of the rest fill it.
    EXPECT_EQ(choose_beam(worlds, 4, 1, 3), (Beam{10, 20, 30, 11}));
    EXPECT_EQ(choose_beam(worlds, 2, 2, 3), (Beam{10, 11}));
}

TEST(BeamChoice, AFamilyFarBehindGivesItsPlaceToTheLeadersNextBest) {
    // The staircase's shape: the leader at 20 of 21 parts, one family 2 parts behind, two 10 behind.
    const std::vector<BeamCandidate> worlds = {{450, 334, 20.73}, {545, 334, 20.72}, {867, 334, 20.70},
                                               {523, 341, 18.60}, {530, 15, 10.61}, {409, 10, 10.56}};
    EXPECT_EQ(choose_beam(worlds, 4, 1, 3), (Beam{450, 523, 545, 867}));
    // Exactly `reach` parts behind is within reach; closeness does not count, only whole parts.
    const std::vector<BeamCandidate> edge = {{1, 1, 13.99}, {2, 1, 13.5}, {3, 2, 10.01}, {4, 3, 9.99}};
    EXPECT_EQ(choose_beam(edge, 3, 1, 3), (Beam{1, 3, 2}));
}

TEST(BeamChoice, FamiliesFarBehindStillFillABeamTheLeadersCannot) {
    // The leader has one open world left: the others, however far behind, are refined rather
    // than nothing.
    const std::vector<BeamCandidate> worlds = {{7, 7, 20.2}, {8, 8, 9.5}, {9, 9, 8.5}};
    EXPECT_EQ(choose_beam(worlds, 4, 1, 3), (Beam{7, 8, 9}));
    EXPECT_TRUE(choose_beam({}, 4, 1, 3).empty());
    EXPECT_TRUE(choose_beam(worlds, 0, 1, 3).empty());
}

}  // namespace
}  // namespace mwb
