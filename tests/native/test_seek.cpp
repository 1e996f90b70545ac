// Goal files and the goal search on a small library: bad goals are refused in one line, corrupted
// goal files never crash, the search is the same on 1 and 2 threads, a family that stops gaining
// parts gives way to another, the odds of a fresh world follow the goal's order, and cancelling
// keeps worlds.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>

#include "SceneFixtures.h"
#include "TestFolder.h"
#include "common/BuildInfo.h"
#include "library/LibraryReader.h"
#include "library/LibraryWriter.h"
#include "library/WorldDecoding.h"
#include "refine/StoredWorldRefinement.h"
#include "sampler/Sampler.h"
#include "scene/SceneJson.h"
#include "seek/GoalJson.h"
#include "seek/GoalSearch.h"
#include "seek/ScoredWorlds.h"
#include "sim/PortableRandom.h"

namespace mwb {
namespace {

namespace fs = std::filesystem;

// Seen from straight above (orthographic, |x|, |y| <= 2 m on a 400 px view): a box over the
// floor's quarter x > 0, y > 0.
std::string box_json(const std::string& objects, bool negative = false, const std::string& after = "null",
                     const std::string& rect = "[200, 200, 400, 400]") {
    return R"({"view": [1,0,0,0, 0,1,0,0, 0,0,1,-20, 0,0,0,1],
               "projection": [0.5,0,0,0, 0,0.5,0,0, 0,0,-0.05,-1, 0,0,0,1],
               "viewport": [400, 400], "rect": )" +
           rect + R"(, "objects": )" + objects + R"(, "negative": )" + (negative ? "true" : "false") +
           R"(, "time_window": [2.0, 3.0], "after": )" + after + "}";
}

// A negative box seen from above whose depth ends 0.3 m up, on Box0, over the whole run: every
// world breaks it as Box0 lands, at its own moment.
std::string box0_stays_above() {
    std::string low = box_json(R"(["Box0"])", true, "null", "[0, 0, 400, 400]");
    low.replace(low.find("0,0,1,-20"), 9, "0,0,1,-0.3");
    low.replace(low.find("[2.0, 3.0]"), 10, "null");
    return low;
}

std::string goal_json(const std::vector<std::string>& boxes) {
    std::string text = R"({"boxes": [)";
    for (size_t k = 0; k < boxes.size(); ++k) text += (k ? "," : "") + boxes[k];
    return text + "]}";
}

TEST(GoalJson, NamesResolveToBodiesAndBadGoalsAreRefusedInOneLine) {
    const Scene scene = fixtures::pile(4);
    const std::vector<QueryBox> boxes =
        goal_from_json(goal_json({box_json(R"(["Box1", "Box3"])"), box_json(R"(["Box0"])", true, "0")}), scene);
    ASSERT_EQ(boxes.size(), 2u);
    EXPECT_EQ(boxes[0].bodies, (std::vector<uint32_t>{static_cast<uint32_t>(scene.body_index("Box1")),
                                                      static_cast<uint32_t>(scene.body_index("Box3"))}));
    EXPECT_TRUE(boxes[1].negative);
    EXPECT_EQ(boxes[1].after, 0);
    EXPECT_DOUBLE_EQ(boxes[0].window.lo_s, 2.0);
    auto refused = [&](const std::string& text, const std::string& says) {
        try {
            goal_from_json(text, scene);
            ADD_FAILURE() << "accepted: " << text;
        } catch (const GoalError& error) {
            const std::string message = error.what();
            EXPECT_NE(message.find(says), std::string::npos) << message;
            EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        }
    };
    refused(goal_json({}), "no parts");
    refused(goal_json({box_json(R"(["Crate"])")}), "no object 'Crate'");
    refused(goal_json({box_json(R"(["Box0"])", false, "1"), box_json(R"(["Box1"])", false, "0")}), "cycle");
    refused(goal_json({box_json(R"(["Box0"])", false, "0")}), "itself");
    refused(goal_json({box_json(R"(["Box0"])", false, "null", "[10, 10, 10, 50]")}), "empty");
    refused("{\"boxes\": 3}", "no \"boxes\"");
    refused("not json", "not JSON");
}

std::string with_orientations(const std::string& goal, const std::vector<std::string>& parts) {
    std::string text = goal.substr(0, goal.size() - 1) + R"(, "orientations": [)";
    for (size_t k = 0; k < parts.size(); ++k) text += (k ? "," : "") + parts[k];
    return text + "]}";
}

TEST(GoalJson, OrientationPartsFollowTheBoxesAndBadOnesAreRefusedInOneLine) {
    const Scene scene = fixtures::pile(4);
    const std::string goal = goal_json({box_json(R"(["Box1"])")});
    const std::vector<QueryBox> parts = goal_from_json(
        with_orientations(goal, {R"({"objects": ["Box2"], "within_deg": 20, "time_window": [2, 3]})",
                                 R"({"objects": ["Box0"], "within_deg": 45, "axis": [0, 2, 0], "target": [0, 0, -1],
                                     "negative": true, "longer_than_s": 0.5, "after": 0})"}),
        scene);
    ASSERT_EQ(parts.size(), 3u);
    EXPECT_FALSE(parts[0].orientation);
    ASSERT_TRUE(parts[1].orientation && parts[2].orientation);
    EXPECT_EQ(parts[1].bodies, (std::vector<uint32_t>{static_cast<uint32_t>(scene.body_index("Box2"))}));
    EXPECT_EQ(parts[1].orientation->axis, (Vec3{0, 0, 1}));  // upright by default
    EXPECT_NEAR(parts[1].orientation->within_rad, 20 * 3.14159265358979323846 / 180, 1e-12);
    EXPECT_DOUBLE_EQ(parts[1].window.hi_s, 3.0);
    EXPECT_EQ(parts[2].orientation->axis, (Vec3{0, 1, 0}));  // made unit
    EXPECT_TRUE(parts[2].negative);
    EXPECT_DOUBLE_EQ(parts[2].orientation->longer_than_s, 0.5);
    EXPECT_EQ(parts[2].after, 0);
    auto refused = [&](const std::string& part, const std::string& says) {
        try {
            goal_from_json(with_orientations(goal, {part}), scene);
            ADD_FAILURE() << "accepted: " << part;
        } catch (const GoalError& error) {
            const std::string message = error.what();
            EXPECT_NE(message.find("orientation part 1"), std::string::npos) << message;
            EXPECT_NE(message.find(says), std::string::npos) << message;
            EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        }
    };
    refused(R"({"objects": ["Box2"]})", "within_deg");
    refused(R"({"objects": ["Box2"], "within_deg": 0})", "0 to 180");
    refused(R"({"objects": ["Box2"], "within_deg": 190})", "0 to 180");
    refused(R"({"objects": ["Box2"], "within_deg": 10, "axis": [0, 0, 0]})", "zero direction");
    refused(R"({"objects": ["Box2"], "within_deg": 10, "longer_than_s": -1})", "negative duration");
    refused(R"({"objects": ["Box2"], "within_deg": 10, "time_window": [3, 2]})", "ends before");
    refused(R"({"objects": ["Crate"], "within_deg": 10})", "no object 'Crate'");
    refused(R"({"within_deg": 10})", "no bodies");
    refused(R"({"objects": ["Box2"], "within_deg": 10, "target": [1, 2]})", "\"target\" must be 3 numbers");
}

// Truncated and byte-mutated goal files: a GoalError or a goal, never a crash or another error.
TEST(GoalJson, CorruptedGoalFilesAreRefusedCleanly) {
    const Scene scene = fixtures::pile(4);
    const std::string valid = goal_json({box_json(R"(["Box1"])"), box_json(R"(["Box0"])", true, "0")});
    PortableRandom random(7);
    int refused = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        std::string text = valid;
        if (trial % 3 == 0) {
            text.resize(static_cast<size_t>(random.uniform(0, static_cast<double>(text.size()))));
        } else {
            const int edits = 1 + static_cast<int>(random.uniform(0, 4));
            for (int e = 0; e < edits; ++e) {
                const auto at = static_cast<size_t>(random.uniform(0, static_cast<double>(text.size() - 1)));
                text[at] = "0123456789-.,:[]{}\"e ntrufalsBox"[static_cast<size_t>(random.uniform(0, 32))];
            }
        }
        try {
            goal_from_json(text, scene);
        } catch (const GoalError&) {
            ++refused;
        }
    }
    EXPECT_GT(refused, 1000);
}

class Seek : public ::testing::Test {
protected:
    void SetUp() override {
        scene_ = fixtures::pile(6, 96);
        const RunHeader header{scene_to_json(scene_), SimulationParameters{}, CodecBounds{}, 3, engine_build()};
        const CompiledScene compiled(scene_, header.parameters);
        LibraryWriter writer(path("start.mwb"), header);
        sample_worlds(compiled, header.base_seed, 0, 6, 2, [&](WorldResult&& w) { writer.append(w); });
    }
    std::string path(const std::string& name) const { return folder_.path(name); }
    std::string copy_of_start(const std::string& name) const {
        fs::copy_file(path("start.mwb"), path(name));
        return path(name);
    }

    // Box0 and Box5 end in the quarter x > 0, y > 0 of the floor (negative: Box2 stays out of it);
    // `in_order`: Box5 gets there after Box0 (the beam then weighs each family's pace too).
    SeekRequest request(int threads, bool in_order = false) const {
        SeekRequest r;
        r.boxes = goal_from_json(goal_json({box_json(R"(["Box0"])"), box_json(R"(["Box5"])", false, in_order ? "0" : "null"),
                                            box_json(R"(["Box2"])", true)}),
                                 scene_);
        r.want = 1000;  // never met: the budget ends it
        r.budget_worlds = 40;
        r.seed = 5;
        r.threads = threads;
        r.children_per_branch = 4;
        r.beam_width = 2;
        return r;
    }

    // Each world's motion, by index.
    static std::map<uint64_t, std::vector<double>> motion(const std::string& file) {
        std::map<uint64_t, std::vector<double>> out;
        const LibraryReader reader(file);
        for (const StoredWorld& w : reader.worlds()) out[w.world_index] = decode_world_positions(w);
        return out;
    }

    fixtures::TestFolder folder_{"mwb_seek_test"};
    Scene scene_;
};

TEST_F(Seek, TheSameLibraryGoalBudgetAndSeedGiveTheSameWorldsOnOneAndTwoThreads) {
    for (const bool in_order : {false, true}) {
        SCOPED_TRACE(in_order ? "Box5 after Box0" : "no order");
        const std::string one = copy_of_start(in_order ? "one_ordered.mwb" : "one.mwb"),
                          two = copy_of_start(in_order ? "two_ordered.mwb" : "two.mwb");
        const SeekOutcome a = seek_goal(one, request(1, in_order));
        const SeekOutcome b = seek_goal(two, request(2, in_order));
        EXPECT_EQ(a.worlds_made, 40u);
        EXPECT_GT(a.refinements, 0u);
        EXPECT_EQ(a.worlds_made, b.worlds_made);
        EXPECT_EQ(a.best_world, b.best_world);
        EXPECT_EQ(a.found, b.found);
        EXPECT_DOUBLE_EQ(a.best_value, b.best_value);
        const auto worlds_one = motion(one), worlds_two = motion(two);
        EXPECT_EQ(worlds_one.size(), 6u + 40u - LibraryReader(one).rejections().size());
        ASSERT_EQ(worlds_one.size(), worlds_two.size());
        for (const auto& [index, positions] : worlds_one) {
            ASSERT_TRUE(worlds_two.count(index)) << "world " << index;
            EXPECT_EQ(positions, worlds_two.at(index)) << "world " << index;
        }
        // Every world it made is an ordinary world of the library: refined ones with their lineage,
        // the rest sampled (this goal's parts are common, see the next test).
        const LibraryReader reader(one);
        size_t refined = 0;
        for (const StoredWorld& w : reader.worlds()) refined += !w.lineage.empty();
        EXPECT_GT(refined, 0u);
    }
}

TEST_F(Seek, WhereFreshWorldsOftenMeetEveryPartItSamplesAfreshOnceARefinementReproducedTheLibrary) {
    // Each of the goal's parts is met by a quarter or more of fresh worlds: sampling meets the
    // whole goal sooner than refinement would make its best world meet the parts it misses. The
    // search still refines first: that proves this build reproduces the library's worlds before
    // any world of its making goes in.
    const std::string file = copy_of_start("common.mwb");
    const SeekOutcome outcome = seek_goal(file, request(2));
    const LibraryReader reader(file);
    std::map<uint64_t, bool> refined;  // by index, the worlds the search made
    for (const StoredWorld& w : reader.worlds())
        if (w.world_index >= 6) refined[w.world_index] = !w.lineage.empty();
    ASSERT_FALSE(refined.empty());
    EXPECT_TRUE(refined.begin()->second) << "the first world it made should be refined";
    size_t sampled = 0;
    for (const auto& [index, was_refined] : refined) sampled += !was_refined;
    EXPECT_GE(sampled, 16u) << "of " << refined.size() << " worlds made";
    EXPECT_GE(outcome.refinements, 1u);
}

// A goal with an orientation part: Box1 on the floor, and Box0 turned square to the walls (its
// x axis within 2° of the world's, where the boxes' spin leaves them up to 40° off) over the
// window. The search is as deterministic as with boxes, and every world it reports meets the
// part by the record's own rotations.
TEST_F(Seek, OrientationPartsAreSearchedForDeterministicallyAndHoldInTheWorldsFound) {
    SeekRequest r = request(1);
    r.boxes = goal_from_json(with_orientations(goal_json({box_json(R"(["Box1"])", false, "null", "[0, 0, 400, 400]")}),
                                               {R"({"objects": ["Box0"], "within_deg": 2, "axis": [1, 0, 0],
                                                   "target": [1, 0, 0], "time_window": [2.0, 3.0]})"}),
                             scene_);
    r.want = 1;
    r.budget_worlds = 200;
    const std::string one = copy_of_start("orient_one.mwb"), two = copy_of_start("orient_two.mwb");
    const SeekOutcome a = seek_goal(one, r);
    r.threads = 2;
    const SeekOutcome b = seek_goal(two, r);
    EXPECT_EQ(a.worlds_made, b.worlds_made);
    EXPECT_EQ(a.found, b.found);
    EXPECT_EQ(a.best_world, b.best_world);
    EXPECT_DOUBLE_EQ(a.best_value, b.best_value);
    EXPECT_EQ(motion(one), motion(two));
    EXPECT_EQ(a.box_count, 2u);
    EXPECT_GT(a.refinements, 0u);  // the first worlds did not meet it
    ASSERT_TRUE(a.reached) << "best " << a.best_value;
    const LibraryReader reader(one);
    const auto box0 = static_cast<size_t>(scene_.body_index("Box0"));
    for (const StoredWorld& w : reader.worlds()) {
        if (std::find(a.found.begin(), a.found.end(), w.world_index) == a.found.end()) continue;
        // A world at rest before the window holds its last pose through it.
        for (uint32_t frame = 240; frame <= 360; frame += 4) {
            const uint32_t held = std::min<uint32_t>(frame, w.frame_count - 1);
            const Vec3 x = quat_rotate(decode_pose(w, box0, held).rotation, {1, 0, 0});
            EXPECT_GE(x[0], std::cos(2.0 * 3.14159265358979323846 / 180)) << "world " << w.world_index << " frame " << frame;
        }
    }
}

TEST_F(Seek, AFamilyWhoseRefinementsStopMeetingMorePartsGivesWayToAnother) {
    // Box0, Box1 and Box3 each in a corner it never reaches (beyond the walls): no refinement
    // meets a part, though children come slightly closer, and no fresh world would (so the
    // search soon stops sampling). With a beam of one, the family of the world that came nearest
    // keeps it until every branch point of its worlds is spent; with an allowance of 48 worlds,
    // it gives way to another family once its refinements made 48 without a part more.
    const std::string corner = "[396, 396, 400, 400]";
    const auto most_refined_in_one_family = [&](const std::string& name, uint64_t allowance, size_t& families) {
        const std::string file = copy_of_start(name);
        SeekRequest r = request(2);
        r.boxes = goal_from_json(goal_json({box_json(R"(["Box0"])", false, "null", corner),
                                            box_json(R"(["Box1"])", false, "null", corner),
                                            box_json(R"(["Box3"])", false, "null", corner)}),
                                 scene_);
        r.beam_width = 1;
        r.children_per_branch = 8;
        r.budget_worlds = 400;
        r.family_stall_worlds = allowance;
        EXPECT_FALSE(seek_goal(file, r).reached);
        std::map<uint64_t, uint64_t> refined_per_family;
        const LibraryReader reader(file);
        for (const StoredWorld& w : reader.worlds())
            if (!w.lineage.empty()) ++refined_per_family[w.root_world];
        uint64_t most = 0;
        for (const auto& [family, worlds] : refined_per_family) most = std::max(most, worlds);
        families = refined_per_family.size();
        return most;
    };
    size_t families_kept = 0, families_set_aside = 0;
    EXPECT_GT(most_refined_in_one_family("kept.mwb", 400, families_kept), 48u + 8u)
        << "without an allowance one family should take more: the goal does not test it";
    EXPECT_LE(most_refined_in_one_family("set_aside.mwb", 48, families_set_aside), 48u + 8u);
    EXPECT_GE(families_set_aside, 2u) << "the worlds an allowance saves go to other families";
}

TEST_F(Seek, AFamilyWhoseBestWorldBrokeANegativePartGivesWayToAFreshBatchSoon) {
    // Box0 must stay above 0.3 m (a negative box seen from above whose depth ends there), which
    // every world breaks as Box0 lands, at its own moment; and Box1 must reach a corner beyond
    // the walls, which none does. Every family's best world is broken, so after 64 worlds without
    // a gain the family gives its place up and a fresh batch is sampled, though the allowance for
    // families that stop paying (1,024 worlds) is far off.
    const std::string file = copy_of_start("broken.mwb");
    const std::string low = box0_stays_above();
    SeekRequest r = request(2);
    r.boxes = goal_from_json(goal_json({box_json(R"(["Box1"])", false, "null", "[396, 396, 400, 400]"), low}), scene_);
    r.beam_width = 1;
    r.children_per_branch = 8;
    r.budget_worlds = 400;
    ASSERT_EQ(r.family_stall_worlds, 1024u);
    EXPECT_FALSE(seek_goal(file, r).reached);
    std::map<uint64_t, uint64_t> refined_per_family;
    uint64_t sampled = 0;
    const LibraryReader reader(file);
    for (const StoredWorld& w : reader.worlds()) {
        if (!w.lineage.empty()) ++refined_per_family[w.root_world];
        else if (w.world_index >= 6) ++sampled;
    }
    uint64_t most = 0;
    for (const auto& [family, worlds] : refined_per_family) most = std::max(most, worlds);
    EXPECT_LE(most, 64u + 8u) << "a broken family kept its place";
    EXPECT_GE(refined_per_family.size(), 3u);
    EXPECT_GE(sampled, 32u * (refined_per_family.size() - 1)) << "one fresh batch per family given up";
}

TEST_F(Seek, ABrokenFamilyThatMetAPositivePartFirstKeepsTheLongAllowance) {
    // The goal above, plus Box1 anywhere in view in the first 0.2 s, which every world meets
    // before Box0 lands: a refinement before the break keeps that part, a fresh world need not,
    // so the family keeps its place past 64 worlds.
    const std::string file = copy_of_start("broken_after_a_part.mwb");
    const std::string low = box0_stays_above();
    std::string seen = box_json(R"(["Box1"])", false, "null", "[0, 0, 400, 400]");
    seen.replace(seen.find("[2.0, 3.0]"), 10, "[0.0, 0.2]");
    SeekRequest r = request(2);
    r.boxes = goal_from_json(goal_json({box_json(R"(["Box1"])", false, "null", "[396, 396, 400, 400]"), low, seen}), scene_);
    r.beam_width = 1;
    r.children_per_branch = 8;
    r.budget_worlds = 400;
    EXPECT_FALSE(seek_goal(file, r).reached);
    std::map<uint64_t, uint64_t> refined_per_family;
    LibraryReader reader(file, ReaderOptions{false, 30});
    ScoredWorlds scored(reader, scene_, r.boxes, 1);
    scored.take_new_worlds();
    for (const StoredWorld& w : reader.worlds()) {
        if (w.lineage.empty()) continue;
        ++refined_per_family[w.root_world];
        // Every world the search made meets the early part and breaks the negative one after it.
        ASSERT_TRUE(scored.has(w.world_index));
        const GoalScore& s = scored.score(w.world_index);
        ASSERT_TRUE(std::isfinite(s.violation_time_s));
        ASSERT_EQ(s.positive_parts_before_violation, 1u);
    }
    uint64_t most = 0;
    for (const auto& [family, worlds] : refined_per_family) most = std::max(most, worlds);
    EXPECT_GT(most, 2u * (64u + 8u)) << "a family that met a part before it broke gave its place up as soon";
}

TEST_F(Seek, TheOddsOfAFreshWorldCountAnOrderedPartOnlyAmongWorldsMeetingThePartBefore) {
    // Of the 6 sampled worlds none has Box1 in the far corner (beyond the walls), and all have it
    // somewhere on the floor. Each part's share is smoothed, (met + 0.5) / (counted + 1).
    const std::string corner = "[396, 396, 400, 400]", floor = "[0, 0, 400, 400]";
    LibraryReader reader(path("start.mwb"), ReaderOptions{false, 30});
    const auto odds = [&](const std::string& after) {
        const std::vector<QueryBox> goal =
            goal_from_json(goal_json({box_json(R"(["Box1"])", false, "null", corner),
                                      box_json(R"(["Box1"])", false, after, floor)}),
                           scene_);
        ScoredWorlds worlds(reader, scene_, goal, 1);
        worlds.take_new_worlds();
        return worlds.sampled_goal_odds();
    };
    // Unordered: the corner 0.5 of 7, the floor 6.5 of 7.
    EXPECT_NEAR(odds("null"), (0.5 / 7) * (6.5 / 7), 1e-12);
    // The floor after the corner: no world met the corner, so nothing is known of what follows
    // it (0.5 of 1); counted among all 6 it would be 0.5 of 7, and the odds 7 times too low.
    EXPECT_NEAR(odds("0"), (0.5 / 7) * (0.5 / 1), 1e-12);
}

TEST_F(Seek, CancellingKeepsEveryWorldMadeSoFar) {
    const std::string file = copy_of_start("cancel.mwb");
    SamplingProgress progress;
    SeekRequest r = request(2);
    r.budget_worlds = 1000;
    uint64_t made_when_cancelled = 0;
    const SeekOutcome outcome = seek_goal(file, r,
                                          [&](const SeekStatus& s) {
                                              if (s.worlds_made >= 12 && !progress.cancel) {
                                                  made_when_cancelled = s.worlds_made;
                                                  progress.cancel = true;
                                              }
                                          },
                                          &progress);
    EXPECT_TRUE(outcome.cancelled);
    EXPECT_FALSE(outcome.reached);
    EXPECT_EQ(outcome.worlds_made, made_when_cancelled);
    // The file holds the first worlds and every world made, each readable.
    const LibraryReader reader(file);
    EXPECT_TRUE(reader.warnings().empty());
    EXPECT_EQ(reader.worlds().size() + reader.rejections().size(), 6u + made_when_cancelled);
    for (const StoredWorld& w : reader.worlds()) EXPECT_FALSE(decode_world_positions(w).empty());
}

TEST_F(Seek, AGoalMetAlreadyIsFoundWithoutNewWorldsAndBadRequestsAreRefused) {
    const std::string file = copy_of_start("met.mwb");
    SeekRequest r = request(2);
    // A box every world meets: Box1 anywhere on the floor, seen from above.
    r.boxes = goal_from_json(goal_json({box_json(R"(["Box1"])", false, "null", "[0, 0, 400, 400]")}), scene_);
    r.want = 3;
    const SeekOutcome outcome = seek_goal(file, r);
    EXPECT_TRUE(outcome.reached);
    EXPECT_EQ(outcome.worlds_made, 0u);
    EXPECT_EQ(outcome.found.size(), 6u);
    SeekRequest none = request(2);
    none.boxes.clear();
    EXPECT_THROW(seek_goal(file, none), GoalError);
    SeekRequest broke = request(2);
    broke.budget_worlds = 0;
    EXPECT_THROW(seek_goal(file, broke), GoalError);
    EXPECT_EQ(LibraryReader(file).worlds().size(), 6u);
}

TEST_F(Seek, ALibraryOfAnotherBuildStopsTheSearchWithOneLineNamingBothBuilds) {
    // Worlds stored under a header they were not made with (another base seed) stand for another
    // build's worlds: none comes out as stored.
    const std::string file = path("foreign.mwb");
    {
        const RunHeader header{scene_to_json(scene_), SimulationParameters{}, CodecBounds{}, 3,
                               "many-worlds 0.0.9; another build"};
        const CompiledScene compiled(scene_, header.parameters);
        LibraryWriter writer(file, header);
        sample_worlds(compiled, header.base_seed + 1, 0, 6, 2, [&](WorldResult&& w) { writer.append(w); });
    }
    try {
        seek_goal(file, request(2));
        FAIL() << "a search must not go on in a library whose worlds this build cannot reproduce";
    } catch (const RefineError& error) {
        const std::string message = error.what();
        EXPECT_NE(message.find("another build"), std::string::npos) << message;
        EXPECT_NE(message.find(engine_build()), std::string::npos) << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << "one line: " << message;
    }
    // Nothing of this build's making went into the other build's file.
    const LibraryReader reader(file);
    EXPECT_EQ(reader.worlds().size() + reader.rejections().size(), 6u);
}

}  // namespace
}  // namespace mwb
