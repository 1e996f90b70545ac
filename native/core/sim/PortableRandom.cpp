#include "sim/PortableRandom.h"

namespace mwb {
namespace {

uint64_t rotate_left(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

}  // namespace

uint64_t mix64(uint64_t value) {
    uint64_t z = value + 0x9E3779B97F4A7C15ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

uint64_t derive_world_seed(uint64_t base_seed, uint64_t world_index) {
    return mix64(mix64(base_seed) ^ rotate_left(mix64(world_index + 0x5851F42D4C957F2Dull), 17));
}

uint64_t derive_stream_seed(uint64_t world_seed, uint64_t stream) {
    return mix64(world_seed ^ mix64(stream * 0xD1B54A32D192ED03ull + 1));
}

PortableRandom::PortableRandom(uint64_t seed) {
    // splitmix64 expansion guarantees a non-zero xoshiro state for every seed.
    uint64_t s = seed;
    for (auto& word : state_) {
        s += 0x9E3779B97F4A7C15ull;
        word = mix64(s - 0x9E3779B97F4A7C15ull);
    }
}

uint64_t PortableRandom::next_u64() {
    const uint64_t result = rotate_left(state_[1] * 5, 7) * 9;
    const uint64_t t = state_[1] << 17;
    state_[2] ^= state_[0];
    state_[3] ^= state_[1];
    state_[1] ^= state_[2];
    state_[0] ^= state_[3];
    state_[2] ^= t;
    state_[3] = rotate_left(state_[3], 45);
    return result;
}

double PortableRandom::uniform01() { return static_cast<double>(next_u64() >> 11) * 0x1.0p-53; }

double PortableRandom::uniform(double lo, double hi) {
    // Always draw, so the stream position does not depend on which ranges are empty.
    const double u = uniform01();
    return lo == hi ? lo : lo + (hi - lo) * u;
}

}  // namespace mwb
