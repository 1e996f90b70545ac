// ODE's messages (quickstep's "LCP internal error") go with the world that was stepping, and a
// run reports each kind once, naming how many worlds gave it and the first.
#include <gtest/gtest.h>
#include <ode/ode.h>

#include "sampler/Sampler.h"
#include "sim/OdeMessages.h"
#include "sim/OdeWorld.h"

namespace mwb {
namespace {

TEST(OdeMessages, OdesOwnMessageFunctionReachesTheWorldBeingStepped) {
    initialize_ode_once();
    std::vector<OdeMessage> messages;
    {
        OdeMessageCapture capture(messages, 1.25);
        dMessage(d_ERR_LCP, "LCP internal error, s <= 0 (s=%.4e)", -2.0e-5);
        dMessage(d_ERR_LCP, "LCP internal error, s <= 0 (s=%.4e)", -3.0e-5);
        dMessage(d_ERR_IASSERT, "another kind");
    }
    dMessage(d_ERR_LCP, "outside any world: dropped");
    ASSERT_EQ(messages.size(), 2u);
    EXPECT_EQ(messages[0].code, d_ERR_LCP);
    EXPECT_EQ(messages[0].text, "LCP internal error, s <= 0 (s=-2.0000e-05)");
    EXPECT_EQ(messages[0].times, 2u);
    EXPECT_DOUBLE_EQ(messages[0].first_time_s, 1.25);
    EXPECT_EQ(messages[1].text, "another kind");
}

TEST(OdeMessages, AWorkersRecordOfThemReadsBackAndSkipsWhatIsMalformed) {
    const std::vector<OdeMessage> sent{{3, "two\twords\non two lines", 0.125, 4}, {1, "", 2.0, 1}};
    const std::vector<OdeMessage> read = decode_ode_messages(encode_ode_messages(sent));
    ASSERT_EQ(read.size(), 2u);
    EXPECT_EQ(read[0].code, 3);
    EXPECT_EQ(read[0].text, "two words on two lines");
    EXPECT_DOUBLE_EQ(read[0].first_time_s, 0.125);
    EXPECT_EQ(read[0].times, 4u);
    EXPECT_EQ(read[1].text, "");
    EXPECT_TRUE(decode_ode_messages("3\tnot a time\t1\ttext\ngarbage\n\n").empty());
}

TEST(OdeMessages, ARunNamesEachKindOnceWithItsWorldCountAndItsFirstWorld) {
    OdeMessageReports reports;
    note_ode_messages(reports, 12, {{3, "LCP internal error (late)", 2.0, 5}});
    note_ode_messages(reports, 4, {{3, "LCP internal error (early)", 0.5, 1}});
    OdeMessageReports other;
    note_ode_messages(other, 20, {{3, "LCP internal error", 1.0, 1}});
    merge_ode_messages(reports, other);
    ASSERT_EQ(reports.size(), 1u);
    const OdeMessageReport& lcp = reports.at(3);
    EXPECT_EQ(lcp.worlds, 3u);
    EXPECT_EQ(lcp.first_world, 4u);
    EXPECT_EQ(describe_ode_messages(lcp),
              "ODE said \"LCP internal error (early)\" in 3 worlds (first world 4 at 0.5 s); they are stored, "
              "but their contacts at those steps may be off");
}

}  // namespace
}  // namespace mwb
