#pragma once
// Which bodies a world has, and what moves each of them now: ODE, its keyed animation, or (in a
// refinement) the record of the world being refined. Shared by the parts of one world run.
#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include "sim/CompiledScene.h"

namespace mwb {

/// One per world run; not thread-safe (a world runs on one thread).
class BodyActivity {
public:
    /// `present`: per scene body, 1 if this world has it. Every present dynamic body starts simulated.
    BodyActivity(const CompiledScene& compiled, std::vector<uint8_t> present)
        : compiled_(compiled), present_(std::move(present)) {
        for (size_t i = 0; i < present_.size(); ++i)
            simulated_.push_back(compiled.bodies()[i].dynamic && present_[i] ? 1 : 0);
    }

    bool present(size_t i) const { return present_[i] != 0; }
    /// Stepped by ODE now: not fixed, kinematic or replayed. A keyed body counts as simulated
    /// while it still follows its animation (see animated()).
    bool simulated(size_t i) const { return simulated_[i] != 0; }
    /// A dynamic body of this world that follows the record of the world being refined.
    bool replayed(size_t i) const { return compiled_.bodies()[i].dynamic && present_[i] && !simulated_[i]; }
    /// Whether body i follows its keyed animation during step `step` (before its handoff).
    bool animated(size_t i, uint64_t step) const { return step < compiled_.bodies()[i].handoff_step; }

    /// Refinement: no body is simulated until it is chosen or touched.
    void stop_simulating() { std::fill(simulated_.begin(), simulated_.end(), 0); }
    void set_simulated(size_t i) { simulated_[i] = 1; }

private:
    const CompiledScene& compiled_;
    std::vector<uint8_t> present_;
    std::vector<uint8_t> simulated_;
};

}  // namespace mwb
