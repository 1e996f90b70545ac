// The engine's sentences about a run: the add-on and its command line show these as they are,
// so a wrong word here is what every animator reads.
#include <gtest/gtest.h>

#include "RunWords.h"

namespace mwb {
namespace {

SeekOutcome seek_outcome(bool reached, std::vector<uint64_t> found, uint64_t best, uint32_t met, uint32_t parts,
                         uint64_t made, double seconds) {
    SeekOutcome o;
    o.reached = reached;
    o.found = std::move(found);
    o.best_world = best;
    o.best_boxes_met = met;
    o.box_count = parts;
    o.worlds_made = made;
    o.seconds = seconds;
    return o;
}

TEST(RunWords, SamplingProgressCountsTheWorldsDone) {
    EXPECT_EQ(worlds_done_text("sampled", 3, 10), "sampled 3/10 worlds");
    EXPECT_EQ(worlds_done_text("refined", 8, 8), "refined 8/8 worlds");
}

TEST(RunWords, ProgressNamesTheBestWorldAndCountsWithCommas) {
    SeekStatus s;
    s.best_boxes_met = 5;
    s.box_count = 6;
    s.best_world = 418;
    s.worlds_made = 3120;
    EXPECT_EQ(seek_progress_text(s), "best 5 of 6 parts (world 418), 3,120 worlds made");
    s.worlds_rejected = 8;
    s.worlds_meeting_goal = 2;
    s.box_count = 1;
    s.best_boxes_met = 1;
    EXPECT_EQ(seek_progress_text(s), "best 1 of 1 part (world 418), 3,120 worlds made (8 rejected), 2 meet all");
}

TEST(RunWords, OutcomeSaysWhetherTheGoalWasReachedAndByWhichWorlds) {
    EXPECT_EQ(seek_outcome_text(seek_outcome(true, {412, 415, 430}, 412, 6, 6, 1204, 61.2), 3),
              "Goal reached: 3 worlds meet all 6 parts (412, 415, 430); 1,204 worlds made in 61.2 s");
    EXPECT_EQ(seek_outcome_text(seek_outcome(false, {}, 418, 5, 6, 2000, 80.0), 1),
              "Budget spent: best world 418 meets 5 of 6 parts; 2,000 worlds made in 80.0 s");
    EXPECT_EQ(seek_outcome_text(seek_outcome(false, {412}, 412, 6, 6, 2000, 80.0), 3),
              "Budget spent: 1 world meets all 6 parts (412) of 3 wanted; 2,000 worlds made in 80.0 s");
    EXPECT_EQ(seek_outcome_text(seek_outcome(true, {0, 1, 2, 3, 4, 5, 6, 7, 8, 9}, 0, 1, 1, 0, 0.0), 2),
              "Goal reached: 10 worlds meet the goal (0, 1, 2, 3, 4, 5, 6, 7 and 2 more); 0 worlds made in 0.0 s");
    SeekOutcome stopped = seek_outcome(false, {}, 7, 2, 3, 40, 5.0);
    stopped.cancelled = true;
    EXPECT_EQ(seek_outcome_text(stopped, 1), "Cancelled: best world 7 meets 2 of 3 parts; 40 worlds made in 5.0 s");
}

TEST(RunWords, LostWorldsAreCountedCommonestReasonFirst) {
    const std::map<std::string, uint64_t> reasons{{"the simulation crashed (signal 11, Segmentation fault)", 1},
                                                  {"the simulation did not finish within 120 s", 8},
                                                  {"a body flew off (faster than 100 m/s)", 2}};
    EXPECT_EQ(rejections_text(11, reasons),
              "11 rejected (8: the simulation did not finish within 120 s; 2: a body flew off (faster than 100 m/s); "
              "1 for another reason)");
    EXPECT_EQ(rejections_text(0, {}), "");
    SeekOutcome lost = seek_outcome(false, {}, 418, 5, 6, 2000, 80.0);
    lost.worlds_rejected = 11;
    lost.reject_reasons = reasons;
    EXPECT_EQ(seek_outcome_text(lost, 1),
              "Budget spent: best world 418 meets 5 of 6 parts; 2,000 worlds made in 80.0 s, 11 rejected "
              "(8: the simulation did not finish within 120 s; 2: a body flew off (faster than 100 m/s); "
              "1 for another reason)");
}

}  // namespace
}  // namespace mwb
