#include "refine/LineageCache.h"

namespace mwb {
namespace {

size_t world_bytes(const WorldResult& w) {
    size_t bytes = sizeof(WorldResult) + (w.positions_m.size() + w.orientations.size()) * sizeof(double) +
                   w.contacts.size() * sizeof(ContactEvent);
    for (const Checkpoint& c : w.checkpoints) bytes += sizeof(Checkpoint) + c.bodies.size() * sizeof(BodyState);
    return bytes;
}

}  // namespace

void LineageCache::keep(const WorldResult& world) {
    if (world.status != WorldStatus::Ok || entries_.count(world.world_index)) return;
    const size_t bytes = world_bytes(world);
    if (bytes > max_bytes_) return;
    while (bytes_ + bytes > max_bytes_ && !uses_.empty()) {
        const auto oldest = entries_.find(uses_.back());
        bytes_ -= oldest->second.bytes;
        entries_.erase(oldest);
        uses_.pop_back();
    }
    uses_.push_front(world.world_index);
    entries_[world.world_index] = {std::make_shared<const WorldResult>(world), bytes, uses_.begin()};
    bytes_ += bytes;
}

std::shared_ptr<const WorldResult> LineageCache::find(uint64_t world_index) {
    const auto it = entries_.find(world_index);
    if (it == entries_.end()) return nullptr;
    uses_.splice(uses_.begin(), uses_, it->second.use);
    return it->second.world;
}

std::vector<WorldResult> LineageCache::kept_start(uint64_t root_world, const std::vector<RefineStep>& lineage) {
    std::vector<WorldResult> chain;
    for (size_t k = 0; k <= lineage.size(); ++k) {
        const auto kept = find(k == 0 ? root_world : lineage[k - 1].world_index);
        if (!kept) break;
        chain.push_back(*kept);
    }
    return chain;
}

}  // namespace mwb
