// Golden hashes: the first worlds of each bundled test scene must come out bit for bit as they
// were recorded. A change here means every user's saved seeds now give different worlds: update
// tests/scenes/golden_hashes.txt (MWB_UPDATE_GOLDEN=1) only when that is intended, and say why.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>

#include "scene/SceneJson.h"
#include "sim/CompiledScene.h"
#include "sim/WorldSimulator.h"

namespace mwb {
namespace {

const std::string kDataDir = MWB_TEST_DATA_DIR;
const std::string kGoldenFile = kDataDir + "/scenes/golden_hashes.txt";

std::map<std::string, std::string> read_golden() {
    std::map<std::string, std::string> golden;
    std::ifstream in(kGoldenFile);
    std::string name, hash;
    while (in >> name >> hash) golden[name] = hash;
    return golden;
}

std::string hash_of_first_worlds(const std::string& scene_file) {
    CompiledScene compiled(load_scene_file(kDataDir + "/" + scene_file), SimulationParameters{});
    std::ostringstream text;
    for (uint64_t world = 0; world < 3; ++world) text << std::hex << hash_world(simulate_world(compiled, 1, world));
    return text.str();
}

TEST(Golden, BundledScenesReproduceTheirRecordedWorlds) {
#ifndef MWB_ODE_PER_THREAD_RANDOM
    // MWB_SYSTEM_ODE: the system's libode computes its sin, cos and atan2 with the C library, whose
    // last bits differ from the portable functions the hashes were recorded with.
    GTEST_SKIP() << "the golden hashes are recorded with the bundled ODE; this build links the system's libode";
#endif
    const std::vector<std::string> scenes{"scenes/quickstart.json", "scenes/all_shapes_and_joints.json",
                                          "bench/chain.json"};
    std::map<std::string, std::string> golden = read_golden();
    if (std::getenv("MWB_UPDATE_GOLDEN")) {
        std::ofstream out(kGoldenFile);
        for (const std::string& scene : scenes) out << scene << " " << hash_of_first_worlds(scene) << "\n";
        GTEST_SKIP() << "rewrote " << kGoldenFile;
    }
    for (const std::string& scene : scenes) {
        ASSERT_TRUE(golden.count(scene)) << scene << " has no golden hash in " << kGoldenFile;
        EXPECT_EQ(hash_of_first_worlds(scene), golden[scene]) << scene;
    }
}

}  // namespace
}  // namespace mwb
