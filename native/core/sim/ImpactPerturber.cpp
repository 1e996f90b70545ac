#include "sim/ImpactPerturber.h"

#include <cmath>

#include "common/PortableMath.h"

namespace mwb {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Any unit vector perpendicular to the unit `axis`, chosen stably from its smallest component.
Vec3 perpendicular(const Vec3& axis) {
    const Vec3 helper = std::fabs(axis[0]) < 0.6 ? Vec3{1, 0, 0}
                        : std::fabs(axis[1]) < 0.6 ? Vec3{0, 1, 0}
                                                  : Vec3{0, 0, 1};
    const Vec3 t = cross(axis, helper);
    return scale(t, 1.0 / norm(t));
}

}  // namespace

Vec3 ImpactPerturber::sample_lobe_direction(const Vec3& axis, PortableRandom& random) const {
    // Inverse-CDF sampling of p(θ) ∝ cos^n θ sin θ on the hemisphere around the axis.
    const double cos_theta = portable::pow(random.uniform01(), 1.0 / (lobe_exponent_ + 1.0));
    const double phi = 2.0 * kPi * random.uniform01();
    const double sin_theta = std::sqrt(std::fmax(0.0, 1.0 - cos_theta * cos_theta));
    const Vec3 t1 = perpendicular(axis);
    const Vec3 t2 = cross(axis, t1);
    return add(add(scale(t1, sin_theta * portable::cos(phi)), scale(t2, sin_theta * portable::sin(phi))),
               scale(axis, cos_theta));
}

Vec3 ImpactPerturber::perturbation(const Vec3& delta, PortableRandom& random) const {
    const double delta_norm = norm(delta);
    const Vec3 axis = delta_norm > 0 ? scale(delta, 1.0 / delta_norm) : Vec3{0, 0, 1};
    const Vec3 direction = sample_lobe_direction(axis, random);
    const double limit = alpha_ * delta_norm;
    const double magnitude = random.uniform(-limit, limit);
    return scale(direction, magnitude);
}

}  // namespace mwb
