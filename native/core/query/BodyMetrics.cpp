#include "query/BodyMetrics.h"

namespace mwb {

const std::vector<std::string>& stored_metric_names() {
    static const std::vector<std::string> names{"angular_travel_rad", "time_to_rest_s", "collision_count",
                                                "orientation_change_rad", "path_length_m"};
    return names;
}

std::vector<MetricValues> compute_body_metrics(const WorldResult& world) {
    const size_t n = world.body_count;
    const size_t frames = world.frame_count;
    std::vector<MetricValues> metrics;
    for (const std::string& name : stored_metric_names()) metrics.push_back({name, std::vector<double>(n, 0.0)});
    auto quat_at = [&](size_t b, size_t f) {
        const double* q = &world.orientations[(b * frames + f) * 4];
        return Quat{q[0], q[1], q[2], q[3]};
    };
    auto position_at = [&](size_t b, size_t f) {
        const double* p = &world.positions_m[(b * frames + f) * 3];
        return Vec3{p[0], p[1], p[2]};
    };
    for (size_t b = 0; b < n && frames > 0; ++b) {
        double angular = 0, path = 0;
        for (size_t f = 1; f < frames; ++f) {
            angular += quat_angle_between(quat_at(b, f - 1), quat_at(b, f));
            path += norm(sub(position_at(b, f), position_at(b, f - 1)));
        }
        metrics[0].per_body[b] = angular;
        metrics[1].per_body[b] = b < world.rest_time_s.size() ? world.rest_time_s[b] : 0.0;
        metrics[3].per_body[b] = quat_angle_between(quat_at(b, 0), quat_at(b, frames - 1));
        metrics[4].per_body[b] = path;
    }
    for (const ContactEvent& e : world.contacts)
        if (e.body >= 0 && static_cast<size_t>(e.body) < n) metrics[2].per_body[static_cast<size_t>(e.body)] += 1;
    return metrics;
}

}  // namespace mwb
