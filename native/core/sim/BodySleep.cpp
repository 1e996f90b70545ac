#include "sim/BodySleep.h"

#include <algorithm>
#include <map>
#include <string>

namespace mwb {

BodySleep::BodySleep(const CompiledScene& compiled, OdeWorld& world, const BodyActivity& activity,
                     ImpactResponse& impacts)
    : compiled_(compiled),
      world_(world),
      activity_(activity),
      impacts_(impacts),
      enabled_(compiled.parameters().sleep),
      asleep_(compiled.bodies().size(), 0),
      jointed_(compiled.bodies().size(), 0) {
    // Bullet puts a body with Deactivation on to sleep after 2 s below its speeds.
    constexpr double kBulletDeactivationTime = 2.0;
    for (const Body& body : compiled.scene().bodies)
        delay_s_.push_back(body.deactivation.enabled ? std::max(compiled.parameters().sleep_delay_s, kBulletDeactivationTime)
                                                     : compiled.parameters().sleep_delay_s);
    std::map<std::string, size_t> index;
    for (size_t i = 0; i < compiled.scene().bodies.size(); ++i) index[compiled.scene().bodies[i].name] = i;
    for (const Constraint& c : compiled.scene().constraints) {
        for (const std::string* name : {&c.body_a, &c.body_b}) {
            const auto found = index.find(*name);
            if (found != index.end() && found->second < jointed_.size()) jointed_[found->second] = 1;
        }
    }
}

bool BodySleep::can_sleep(size_t i, uint64_t step) const {
    return enabled_ && activity_.simulated(i) && !activity_.animated(i, step) && !jointed_[i] &&
           world_.bodies()[i] != nullptr;
}

bool BodySleep::quiet_long_enough(size_t i, double t_s) const {
    const double since = impacts_.quiet_since_s(i);
    return since != ImpactResponse::kNotQuiet && t_s - since >= delay_s_[i];
}

bool BodySleep::moves(int32_t i) const {
    return i >= 0 && world_.bodies()[static_cast<size_t>(i)] != nullptr && !asleep_[static_cast<size_t>(i)];
}

void BodySleep::fall_asleep(size_t i) {
    dBodyID body = world_.bodies()[i];
    // Still means still: woken, it starts from rest rather than from its last crawl.
    dBodySetLinearVel(body, 0, 0, 0);
    dBodySetAngularVel(body, 0, 0, 0);
    dBodyDisable(body);
    asleep_[i] = 1;
}

void BodySleep::enable(size_t i) {
    dBodyEnable(world_.bodies()[i]);
    asleep_[i] = 0;
}

void BodySleep::wake(size_t i, double t_s) {
    enable(i);
    impacts_.restart_quiet(i, t_s);
}

void BodySleep::wake_touched(const ContactGenerator& contacts, uint64_t step) {
    if (!enabled_) return;
    const double t = compiled_.step_time_s(step);
    // Bodies that stopped being simulated (a refinement's replay) are not asleep.
    for (size_t i = 0; i < asleep_.size(); ++i)
        if (asleep_[i] && !can_sleep(i, step)) wake(i, t);
    const auto& owners = world_.geom_owners();
    for (bool woke = true; woke;) {
        woke = false;
        for (const CandidatePair& pair : contacts.candidate_pairs()) {
            const GeomOwner& a = owners[pair.first_index];
            const GeomOwner& b = owners[pair.second_index];
            if (a.ghost || b.ghost || a.body == b.body) continue;
            // Touching, not only overlapping bounds: woken early, a body would start to fall
            // before it is hit.
            const bool a_wakes = a.body >= 0 && asleep_[a.body] && moves(b.body);
            const bool b_wakes = b.body >= 0 && asleep_[b.body] && moves(a.body);
            if ((a_wakes || b_wakes) && contacts.touching(pair)) {
                wake(a_wakes ? a.body : b.body, t);
                woke = true;
            }
        }
    }
    for (uint8_t a : asleep_) sleeping_body_steps_ += a;
}

void BodySleep::settle(uint64_t step, double t_after_s) {
    if (!enabled_) return;
    for (size_t i = 0; i < asleep_.size(); ++i)
        if (!asleep_[i] && can_sleep(i, step) && quiet_long_enough(i, t_after_s)) fall_asleep(i);
}

void BodySleep::restore(uint64_t step, double t_s) {
    if (!enabled_) return;
    // As the previous step's settle() left them (at the start: the bodies set to start asleep).
    const uint64_t previous = step > 0 ? step - 1 : 0;
    for (size_t i = 0; i < asleep_.size(); ++i) {
        if (asleep_[i]) enable(i);
        if (can_sleep(i, previous) && quiet_long_enough(i, t_s)) fall_asleep(i);
    }
}

}  // namespace mwb
