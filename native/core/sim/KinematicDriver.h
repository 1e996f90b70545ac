#pragma once
// Bodies that follow their animation: Blender's "Animated" bodies for the whole world, and keyed
// ones until their handoff step, when they are let go with the velocity their animation gave them.
#include <cstdint>

#include "sim/BodyActivity.h"
#include "sim/CompiledScene.h"
#include "sim/OdeWorld.h"

namespace mwb {

/// One per world run; not thread-safe (a world runs on one thread).
class KinematicDriver {
public:
    KinematicDriver(const CompiledScene& compiled, OdeWorld& world, const BodyActivity& activity);

    /// Before step `step` (animation time `t_s`): lets go the keyed bodies whose handoff it is,
    /// and puts every body still following its animation on its pose at `t_s`, with the
    /// velocities that take it to its pose one step later.
    void drive(uint64_t step, double t_s);
    /// A run resumed at `step`: the keyed bodies handed over before it are simulated again.
    void resume_at(uint64_t step);
    /// Whether an animated body's animation still plays at `t_s` (a world is not at rest until
    /// every animation has ended).
    bool animation_playing(double t_s) const;

private:
    const CompiledScene& compiled_;
    OdeWorld& world_;
    const BodyActivity& activity_;
};

}  // namespace mwb
