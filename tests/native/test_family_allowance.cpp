// How long a family keeps its place in a goal search without meeting more parts: the long
// allowance while its best world is whole, the short one while its best world broke a negative
// part, whichever of its worlds was refined.
#include <gtest/gtest.h>

#include "seek/FamilyAllowance.h"

namespace mwb {
namespace {

using Verdict = FamilyAllowance::Verdict;

// Eight children no better than `parts` parts, all broken or all whole.
std::vector<FamilyWorld> no_gain(double parts, bool broken) {
    return std::vector<FamilyWorld>(8, FamilyWorld{parts + 0.5, broken});
}

TEST(FamilyAllowance, AFamilyWhoseBestWorldIsWholeKeepsItsPlaceWhileItRefinesItsBrokenWorlds) {
    // The staircase's leader: its best world meets 20 of 21 parts unbroken; its next best went over
    // the string (broken), and the search refines those too.
    FamilyAllowance allowance(1024, 64);
    ASSERT_EQ(allowance.note(334, {20.9, false}, no_gain(19, true), 8), Verdict::Keep);
    for (int k = 0; k < 100; ++k)
        ASSERT_EQ(allowance.note(334, {19.8, true}, no_gain(19, true), 8), Verdict::Keep) << "after " << 8 * (k + 2);
    // 808 worlds without a gain so far; the long allowance ends at 1,024.
    Verdict verdict = Verdict::Keep;
    uint64_t made = 808;
    while (verdict == Verdict::Keep) {
        verdict = allowance.note(334, {19.8, true}, no_gain(19, true), 8);
        made += 8;
    }
    EXPECT_EQ(verdict, Verdict::SetAside);
    EXPECT_EQ(made, 1024u);
}

TEST(FamilyAllowance, AFamilyWhoseBestWorldBrokeGetsTheShortTrial) {
    FamilyAllowance allowance(1024, 64);
    uint64_t made = 0;
    Verdict verdict = Verdict::Keep;
    while (verdict == Verdict::Keep && made < 2000) {
        verdict = allowance.note(7, {12.3, true}, no_gain(11, true), 8);
        made += 8;
    }
    EXPECT_EQ(verdict, Verdict::BrokenStart);
    EXPECT_EQ(made, 64u);
}

TEST(FamilyAllowance, AWholeChildBetterThanTheBrokenBestGivesTheFamilyTheLongAllowance) {
    // Its best world broke; a refinement mends it at the same parts (no gain in parts), but the
    // mended world is now the family's best, so the short trial no longer applies.
    FamilyAllowance allowance(1024, 64);
    std::vector<FamilyWorld> children = no_gain(11, true);
    children[3] = {12.8, false};
    EXPECT_EQ(allowance.note(7, {12.3, true}, children, 8), Verdict::Keep);
    for (int k = 0; k < 20; ++k)
        ASSERT_EQ(allowance.note(7, {12.3, true}, no_gain(11, true), 8), Verdict::Keep) << "after " << 8 * (k + 2);
}

TEST(FamilyAllowance, AGainStartsTheCountAgainAndFamiliesCountApart) {
    FamilyAllowance allowance(48, 16);
    for (int k = 0; k < 5; ++k) ASSERT_EQ(allowance.note(1, {5.2, false}, no_gain(4, false), 8), Verdict::Keep);
    // A child meets a part more than any before: 40 worlds forgotten.
    std::vector<FamilyWorld> gained = no_gain(4, false);
    gained[0] = {6.1, false};
    ASSERT_EQ(allowance.note(1, {5.2, false}, gained, 8), Verdict::Keep);
    for (int k = 0; k < 5; ++k) ASSERT_EQ(allowance.note(1, {6.1, false}, no_gain(5, false), 8), Verdict::Keep);
    // Another family's worlds do not count against this one.
    for (int k = 0; k < 5; ++k) ASSERT_EQ(allowance.note(2, {6.0, false}, no_gain(5, false), 8), Verdict::Keep);
    EXPECT_EQ(allowance.note(1, {6.1, false}, no_gain(5, false), 8), Verdict::SetAside);
    EXPECT_EQ(allowance.note(2, {6.0, false}, no_gain(5, false), 8), Verdict::SetAside);
}

}  // namespace
}  // namespace mwb
