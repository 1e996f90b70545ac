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

std::vector<WorldResult> LineageCache::chain(uint64_t root_world, const std::vector<RefineStep>& lineage) {
    std::vector<std::shared_ptr<const WorldResult>> found{find(root_world)};
    for (const RefineStep& step : lineage) found.push_back(find(step.world_index));
    std::vector<WorldResult> chain;
    for (const auto& w : found)
        if (!w) return {};
    chain.reserve(found.size());
    for (const auto& w : found) chain.push_back(*w);
    return chain;
}

}  // namespace mwb
