#pragma once
// A fixed, portable pseudo-random generator (xoshiro256**, seeded through splitmix64) and
// distributions built only from integer arithmetic and IEEE operations, so a stream of draws is
// identical on every machine and compiler. std::uniform_real_distribution is not portable.
#include <array>
#include <cstdint>

namespace mwb {

class PortableRandom {
public:
    using State = std::array<uint64_t, 4>;

    explicit PortableRandom(uint64_t seed);
    explicit PortableRandom(const State& state) : state_(state) {}

    uint64_t next_u64();
    /// Uniform in [0, 1) with 53 random bits.
    double uniform01();
    /// Uniform in [lo, hi]; returns lo when lo == hi without consuming less than one draw.
    double uniform(double lo, double hi);

    const State& state() const { return state_; }

private:
    State state_;
};

/// splitmix64 finalizer: a bijective 64-bit mix.
uint64_t mix64(uint64_t value);
/// Seed of world `world_index` in a run with `base_seed`; independent of thread count and sharding.
uint64_t derive_world_seed(uint64_t base_seed, uint64_t world_index);
/// Seed of an independent stream `stream` (initial conditions, perturbations, ...) of one world.
uint64_t derive_stream_seed(uint64_t world_seed, uint64_t stream);

/// The streams of one world: its bodies' initial states, and the perturbations of its impacts.
constexpr uint64_t kInitialStateStream = 0;
constexpr uint64_t kPerturbationStream = 1;

}  // namespace mwb
