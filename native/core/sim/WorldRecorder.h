#pragma once
// Records one world run: every body's object pose at each recorded frame, and the simulator's
// state at each checkpoint, so the run can later be resumed bit for bit.
#include <cstdint>
#include <vector>

#include "sim/BodyActivity.h"
#include "sim/CompiledScene.h"
#include "sim/ImpactResponse.h"
#include "sim/OdeWorld.h"
#include "sim/RefinementReplay.h"
#include "sim/WorldResult.h"

namespace mwb {

/// One per world run; not thread-safe (a world runs on one thread).
class WorldRecorder {
public:
    WorldRecorder(const CompiledScene& compiled, OdeWorld& world, const BodyActivity& activity, const ImpactResponse& impacts,
                  const RefinementReplay& replay);

    /// The run resumes at `checkpoint` (which must outlive the recorder): recording starts at its
    /// frame, and the checkpoint is kept as it was stored.
    void resume_from(const Checkpoint& checkpoint);
    /// Records every body's object pose at the start of step `step`, a frame boundary.
    void record_frame(uint64_t step);
    /// Saves the simulator's state at the start of step `step`; `ode_random_state` is ODE's
    /// constraint-ordering generator.
    void save_checkpoint(uint64_t step, uint64_t ode_random_state);
    /// Moves the recorded frames (body by body) and checkpoints into `result`.
    void finish(WorldResult& result);

private:
    const CompiledScene& compiled_;
    OdeWorld& world_;
    const BodyActivity& activity_;
    const ImpactResponse& impacts_;
    const RefinementReplay& replay_;
    const Checkpoint* restored_ = nullptr;
    uint32_t first_frame_ = 0;
    std::vector<Transform> frames_;  ///< frame by frame, each every body's pose
    std::vector<Checkpoint> checkpoints_;
};

}  // namespace mwb
