#pragma once
// ODE's quickstep reorders constraints with dRandInt. In stock libode that draws from one
// process-wide seed, so results would depend on thread interleaving and on what ran before. Each
// world therefore keeps its own generator state and loads it into the stepping thread:
// - our ODE build (native/ode) keeps the generator's state per thread, so loading is dRandSetSeed;
// - with the system's libode (MWB_SYSTEM_ODE), this program defines dRand/dRandInt/dRandGetSeed/
//   dRandSetSeed itself (libode.so calls them through its symbol table, so these definitions win).
// Both draw the same numbers. Tests check quickstep really draws from the world's state.
#include <cstdint>

namespace mwb {

/// Loads a world's ODE random state into this thread for the scope's lifetime and writes the
/// advanced state back on exit. Worlds must step inside such a scope.
class OdeRandomScope {
public:
    explicit OdeRandomScope(uint64_t& world_state);
    ~OdeRandomScope();
    OdeRandomScope(const OdeRandomScope&) = delete;
    OdeRandomScope& operator=(const OdeRandomScope&) = delete;

private:
    uint64_t& world_state_;
};

/// Number of dRandInt calls on this thread that drew from the per-thread state.
uint64_t ode_random_calls_on_this_thread();

}  // namespace mwb
