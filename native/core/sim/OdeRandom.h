#pragma once
// ODE's quickstep reorders constraints with dRandInt, which in libode draws from one process-wide
// seed: results would depend on thread interleaving and on what ran before. This program defines
// dRand/dRandInt/dRandGetSeed/dRandSetSeed itself (libode.so calls them through its symbol table,
// so these definitions win) and backs them with a thread-local state that each world loads
// before it steps and saves after. Tests check the override is really reached.
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

/// Number of dRandInt calls on this thread that reached our definition (not libode's).
uint64_t ode_random_calls_on_this_thread();

}  // namespace mwb
