#pragma once
// Refinement inside a world run: from a branch step on, the chosen bodies (and whatever they
// touch) are simulated anew while every other dynamic body replays the world being refined, its
// parent. Ghosts of the chosen and removed bodies follow their old paths to find the bodies they
// used to touch. At the end the parent's record is spliced in before the branch.
#include <cstdint>
#include <vector>

#include "sim/BodyActivity.h"
#include "sim/CompiledScene.h"
#include "sim/ContactGenerator.h"
#include "sim/ImpactResponse.h"
#include "sim/OdeWorld.h"
#include "sim/WorldResult.h"

namespace mwb {

/// One per world run; not thread-safe (a world runs on one thread). The parent worlds must
/// outlive it.
class RefinementReplay {
public:
    RefinementReplay(const CompiledScene& compiled, uint64_t base_seed, OdeWorld& world, BodyActivity& activity,
                     ImpactResponse& impacts);

    /// Refinements to apply on the way: at steps[k].branch_step the run switches to simulating
    /// steps[k].bodies while the other bodies replay *parents[k], which must be full-length.
    /// Branch steps must increase.
    void plan(const std::vector<RefineStep>& steps, const std::vector<const WorldResult*>& parents);
    /// Switches to the planned refinement that branches at `step`, if there is one.
    void begin_due(uint64_t step);
    /// Whether a refinement has begun: bodies that are not simulated replay its parent.
    bool active() const { return parent_ != nullptr; }
    /// When the parent world ends, s: replayed bodies are defined until then.
    double parent_end_s() const { return parent_->simulated_time_s; }

    /// Puts the replayed bodies and the ghosts on the parent's paths at `t_s`.
    void drive_replayed_bodies(double t_s);
    /// Before step `step`: a replayed body that a simulated body, a ghost or an added passive body
    /// touches (among this step's candidate pairs) is simulated from now on.
    void activate_touched_bodies(const ContactGenerator& contacts, uint64_t step);
    /// Object pose of body i at frame `f` of the parent (its last frame after its end).
    Transform parent_frame(size_t i, uint32_t f) const;

    /// Completes a refined `result` (its own frames from its first frame on): the parent's frames
    /// before that, which bodies changed, and the parent's events and rest times where they hold.
    void finish(WorldResult& result) const;

private:
    void begin(size_t k, uint64_t step);
    void activate(uint32_t i, uint64_t step);
    void activate_joint_partners(uint32_t i, bool live_only, uint64_t step);
    Transform parent_pose(size_t i, double t_s) const;
    BodyState parent_state(size_t i, double t_s) const;
    void splice_parent_frames(WorldResult& result) const;
    void splice_parent_events(WorldResult& result) const;

    const CompiledScene& compiled_;
    uint64_t base_seed_;
    OdeWorld& world_;
    BodyActivity& activity_;
    ImpactResponse& impacts_;
    std::vector<RefineStep> steps_;
    std::vector<const WorldResult*> parents_;
    size_t next_ = 0;                     ///< the next planned refinement
    const WorldResult* parent_ = nullptr;  ///< the world being refined, once a refinement began
    double branch_time_s_ = 0;
    std::vector<uint32_t> ghosts_;        ///< bodies whose ghost follows the parent
    std::vector<uint8_t> activator_;      ///< per body: a passive body added now, waking what it touches
    std::vector<double> activated_at_s_;  ///< per body: when it started being simulated anew
    std::vector<uint8_t> changed_;        ///< per body: simulated anew
};

}  // namespace mwb
