#pragma once
// Worlds simulated in this process, kept so that refining them again (as a goal search does, many
// times over) starts from them instead of re-simulating their whole lineage. Bounded in bytes;
// the least recently used worlds go first.
#include <cstdint>
#include <list>
#include <memory>
#include <unordered_map>
#include <vector>

#include "sim/WorldResult.h"

namespace mwb {

class LineageCache {
public:
    explicit LineageCache(size_t max_bytes) : max_bytes_(max_bytes) {}

    /// Keeps a copy of `world` (an exact world of this run, as the simulator made it).
    void keep(const WorldResult& world);
    /// Keeps `world` itself, without a copy.
    void keep(WorldResult&& world);
    /// The start of the exact lineage with root `root_world` and refinements `lineage`, as
    /// simulate_lineage would return it, as far as its worlds are kept (empty: not the root).
    std::vector<WorldResult> kept_start(uint64_t root_world, const std::vector<RefineStep>& lineage);

    size_t bytes() const { return bytes_; }

private:
    struct Entry {
        std::shared_ptr<const WorldResult> world;
        size_t bytes;
        std::list<uint64_t>::iterator use;
    };
    std::shared_ptr<const WorldResult> find(uint64_t world_index);
    // Whether `world` is one to keep and not kept yet; its size, which must fit, in `bytes`.
    bool wanted(const WorldResult& world, size_t& bytes) const;
    void insert(std::shared_ptr<const WorldResult> world, size_t bytes);

    size_t max_bytes_, bytes_ = 0;
    std::unordered_map<uint64_t, Entry> entries_;
    std::list<uint64_t> uses_;  ///< most recently used first
};

}  // namespace mwb
