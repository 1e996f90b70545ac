#pragma once
// A reorder window: worlds finish in whatever order threads or worker processes get to them, but a
// library's records are written in the order the worlds were asked for, so that a re-run, on any
// number of threads, writes the same file byte for byte.
#include <cstddef>
#include <functional>
#include <map>
#include <optional>
#include <utility>

namespace mwb {

/// Hands items to a callback in position order (0, 1, 2, ...) whatever order they arrive in.
/// Not thread-safe: callers serialize arrive, skip and flush.
template <typename Item>
class InOrderDelivery {
public:
    explicit InOrderDelivery(std::function<void(Item&&)> deliver) : deliver_(std::move(deliver)) {}

    /// Holds `item` for `position`, then delivers every held item that is now next in order.
    void arrive(size_t position, Item&& item) {
        held_.emplace(position, std::move(item));
        deliver_ready();
    }

    /// `position` will never arrive (its task was refused or cancelled): later ones need not wait.
    void skip(size_t position) {
        held_.emplace(position, std::nullopt);
        deliver_ready();
    }

    /// Delivers everything held, in position order, gaps and all: what a cancelled run finished
    /// is kept, though not where an uninterrupted run would put it.
    void flush() {
        auto held = std::move(held_);
        held_.clear();
        for (auto& [position, item] : held) {
            next_ = position + 1;
            if (item) deliver_(std::move(*item));
        }
    }

    /// The first position not yet delivered or skipped.
    size_t next() const { return next_; }
    size_t held() const { return held_.size(); }

private:
    void deliver_ready() {
        for (auto it = held_.begin(); it != held_.end() && it->first == next_; it = held_.erase(it)) {
            ++next_;
            if (it->second) deliver_(std::move(*it->second));
        }
    }

    std::function<void(Item&&)> deliver_;
    std::map<size_t, std::optional<Item>> held_;
    size_t next_ = 0;
};

}  // namespace mwb
