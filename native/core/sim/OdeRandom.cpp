#include "sim/OdeRandom.h"

#ifdef MWB_ODE_PER_THREAD_RANDOM

#include <ode/misc.h>

// Defined by native/ode/per-thread-random.patch.
extern "C" unsigned long long dRandIntCallsOnThisThread();

namespace mwb {

OdeRandomScope::OdeRandomScope(uint64_t& world_state) : world_state_(world_state) {
    dRandSetSeed(static_cast<unsigned long>(world_state_ & 0xffffffffull));
}

OdeRandomScope::~OdeRandomScope() { world_state_ = dRandGetSeed(); }

uint64_t ode_random_calls_on_this_thread() { return dRandIntCallsOnThisThread(); }

}  // namespace mwb

#else  // the system's libode: replace its generator

namespace mwb {
namespace {

thread_local uint64_t t_ode_random_state = 0;
thread_local uint64_t t_call_count = 0;

// The same 32-bit linear congruential recurrence as ODE's own generator.
uint32_t next_state() {
    t_ode_random_state = (1664525ull * t_ode_random_state + 1013904223ull) & 0xffffffffull;
    return static_cast<uint32_t>(t_ode_random_state);
}

}  // namespace

OdeRandomScope::OdeRandomScope(uint64_t& world_state) : world_state_(world_state) {
    t_ode_random_state = world_state_;
}

OdeRandomScope::~OdeRandomScope() { world_state_ = t_ode_random_state; }

uint64_t ode_random_calls_on_this_thread() { return t_call_count; }

}  // namespace mwb

// Replacements for libode's definitions (same C signatures as <ode/misc.h>). Default visibility
// so they also take effect when this code lives in a Python extension built with hidden symbols.
extern "C" {

__attribute__((visibility("default"))) unsigned long dRand(void) { return mwb::next_state(); }

__attribute__((visibility("default"))) unsigned long dRandGetSeed(void) {
    return static_cast<unsigned long>(mwb::t_ode_random_state);
}

__attribute__((visibility("default"))) void dRandSetSeed(unsigned long seed) {
    mwb::t_ode_random_state = seed & 0xffffffffull;
}

__attribute__((visibility("default"))) int dRandInt(int n) {
    ++mwb::t_call_count;
    if (n <= 1) return 0;
    // Multiply-shift maps the 32-bit draw to [0, n) without modulo bias worth caring about here.
    return static_cast<int>((static_cast<uint64_t>(mwb::next_state()) * static_cast<uint64_t>(n)) >> 32);
}

}  // extern "C"

#endif
