#pragma once
// Plausible perturbation of post-impact velocities (Twigg & James 2007, §2): a direction from a
// cos^n lobe around the impulse direction and a magnitude uniform in ±alpha·|Δ|.
#include "common/Math.h"
#include "sim/PortableRandom.h"

namespace mwb {

class ImpactPerturber {
public:
    /// `alpha` scales the largest perturbation relative to the velocity jump; `lobe_exponent` is n.
    ImpactPerturber(double alpha, double lobe_exponent) : alpha_(alpha), lobe_exponent_(lobe_exponent) {}

    /// Perturbation to add to the post-impact velocity for an impact that changed it by `delta`
    /// (gravity removed). |result| <= alpha·|delta|. Consumes exactly three draws.
    Vec3 perturbation(const Vec3& delta, PortableRandom& random) const;

    /// A unit direction from the cos^n lobe around the unit `axis`. Consumes exactly two draws.
    Vec3 sample_lobe_direction(const Vec3& axis, PortableRandom& random) const;

private:
    double alpha_;
    double lobe_exponent_;
};

}  // namespace mwb
