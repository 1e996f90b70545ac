#include "refine/LineageCache.h"

namespace mwb {
namespace {

// The memory a kept world holds, spare room included: a world kept without a copy keeps the room
// its vectors grew into.
size_t world_bytes(const WorldResult& w) {
    size_t bytes = sizeof(WorldResult) + (w.positions_m.capacity() + w.orientations.capacity()) * sizeof(double) +
                   w.contacts.capacity() * sizeof(ContactEvent) + w.checkpoints.capacity() * sizeof(Checkpoint);
    for (const Checkpoint& c : w.checkpoints) bytes += c.bodies.capacity() * sizeof(BodyState);
    return bytes;
}

}  // namespace

bool LineageCache::wanted(const WorldResult& world, size_t& bytes) const {
    if (world.status != WorldStatus::Ok || entries_.count(world.world_index)) return false;
    bytes = world_bytes(world);
    return bytes <= max_bytes_;
}

void LineageCache::keep(const WorldResult& world) {
    size_t bytes = 0;
    if (wanted(world, bytes)) insert(std::make_shared<const WorldResult>(world), bytes);
}

void LineageCache::keep(WorldResult&& world) {
    size_t bytes = 0;
    if (wanted(world, bytes)) insert(std::make_shared<const WorldResult>(std::move(world)), bytes);
}

void LineageCache::insert(std::shared_ptr<const WorldResult> world, size_t bytes) {
    while (bytes_ + bytes > max_bytes_ && !uses_.empty()) {
        const auto oldest = entries_.find(uses_.back());
        bytes_ -= oldest->second.bytes;
        entries_.erase(oldest);
        uses_.pop_back();
    }
    const uint64_t index = world->world_index;
    uses_.push_front(index);
    entries_[index] = {std::move(world), bytes, uses_.begin()};
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
