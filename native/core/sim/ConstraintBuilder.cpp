#include "sim/ConstraintBuilder.h"

#include <utility>

namespace mwb {
namespace {

// ODE parameter ids of axis 1, 2, 3 differ by dParamGroup.
int axis_param(int base, int axis) { return base + dParamGroup * axis; }

void set_limits(dJointID joint, void (*set)(dJointID, int, dReal), int axis, bool enabled, double lower, double upper,
                bool flipped = false) {
    if (!enabled) return;
    // Joint positions are measured from the first attached body; with the bodies swapped they
    // change sign, and so do the limits.
    if (flipped) {
        const double swapped_lower = -upper;
        upper = -lower;
        lower = swapped_lower;
    }
    // ODE ignores stops with lo > hi; set hi first so a raised lo is accepted.
    set(joint, axis_param(dParamHiStop, axis), upper);
    set(joint, axis_param(dParamLoStop, axis), lower);
}

// A spring of stiffness k and damping c on a stop at rest position 0: ODE expresses it through
// the stop's ERP and CFM for step h (ERP = hk/(hk+c), CFM = 1/(hk+c)).
void set_spring(dJointID joint, void (*set)(dJointID, int, dReal), int axis, double k, double c, double h) {
    const double denominator = h * k + c;
    set(joint, axis_param(dParamHiStop, axis), 0);
    set(joint, axis_param(dParamLoStop, axis), 0);
    set(joint, axis_param(dParamStopERP, axis), h * k / denominator);
    set(joint, axis_param(dParamStopCFM, axis), 1.0 / denominator);
}

// Blender hands its motor "max impulse" to Bullet as the motor's maximum force (N, or N·m for an
// angular motor), which Bullet turns into an impulse per step itself; ODE's FMax is that force.
void set_motor(dJointID joint, void (*set)(dJointID, int, dReal), double velocity, double max_impulse) {
    set(joint, dParamVel, velocity);
    set(joint, dParamFMax, max_impulse);
}

}  // namespace

JointGroup build_constraint_joints(dWorldID world, const Constraint& c, dBodyID a, dBodyID b, double step_s) {
    JointGroup group;
    if (!a && !b) return group;  // both static: nothing can move
    // ODE needs the moving body first; Blender measures object A against object B, so limits,
    // springs and motors of a swapped pair change sign.
    const bool flipped = !a;
    if (flipped) std::swap(a, b);
    const double sign = flipped ? -1.0 : 1.0;
    const Vec3& p = c.frame.location;
    const Vec3 x_axis = quat_rotate(c.frame.rotation, {1, 0, 0});
    const Vec3 z_axis = quat_rotate(c.frame.rotation, {0, 0, 1});
    auto add_joint = [&](dJointID joint) {
        dJointAttach(joint, a, b);
        group.joints.push_back(joint);
        return joint;
    };
    switch (c.type) {
        case ConstraintType::Fixed: {
            dJointID j = add_joint(dJointCreateFixed(world, nullptr));
            dJointSetFixed(j);
            break;
        }
        case ConstraintType::Point: {
            dJointID j = add_joint(dJointCreateBall(world, nullptr));
            dJointSetBallAnchor(j, p[0], p[1], p[2]);
            break;
        }
        case ConstraintType::Hinge: {
            dJointID j = add_joint(dJointCreateHinge(world, nullptr));
            dJointSetHingeAnchor(j, p[0], p[1], p[2]);
            dJointSetHingeAxis(j, z_axis[0], z_axis[1], z_axis[2]);
            set_limits(j, dJointSetHingeParam, 0, c.angular_limits.enabled[2], c.angular_limits.lower[2],
                       c.angular_limits.upper[2], flipped);
            break;
        }
        case ConstraintType::Slider: {
            dJointID j = add_joint(dJointCreateSlider(world, nullptr));
            dJointSetSliderAxis(j, x_axis[0], x_axis[1], x_axis[2]);
            // ODE measures the moving body against the other along the axis, as Blender measures
            // object B against object A: a swapped pair keeps the sign (checked against Blender).
            set_limits(j, dJointSetSliderParam, 0, c.linear_limits.enabled[0], c.linear_limits.lower[0],
                       c.linear_limits.upper[0]);
            break;
        }
        case ConstraintType::Piston: {
            dJointID j = add_joint(dJointCreatePiston(world, nullptr));
            dJointSetPistonAnchor(j, p[0], p[1], p[2]);
            dJointSetPistonAxis(j, x_axis[0], x_axis[1], x_axis[2]);
            set_limits(j, dJointSetPistonParam, 0, c.linear_limits.enabled[0], c.linear_limits.lower[0],
                       c.linear_limits.upper[0]);
            set_limits(j, dJointSetPistonParam, 1, c.angular_limits.enabled[0], c.angular_limits.lower[0],
                       c.angular_limits.upper[0], flipped);
            break;
        }
        case ConstraintType::Generic:
        case ConstraintType::GenericSpring: {
            // Validation guarantees locked linear axes: a ball joint plus an Euler angular motor
            // carrying the angular limits and springs.
            dJointID ball = add_joint(dJointCreateBall(world, nullptr));
            dJointSetBallAnchor(ball, p[0], p[1], p[2]);
            dJointID motor = add_joint(dJointCreateAMotor(world, nullptr));
            dJointSetAMotorMode(motor, dAMotorEuler);
            dJointSetAMotorAxis(motor, 0, 1, x_axis[0], x_axis[1], x_axis[2]);
            dJointSetAMotorAxis(motor, 2, b ? 2 : 0, z_axis[0], z_axis[1], z_axis[2]);
            for (int axis = 0; axis < 3; ++axis) {
                const bool spring = c.type == ConstraintType::GenericSpring && c.angular_springs.enabled[axis];
                if (c.angular_limits.enabled[axis]) {
                    set_limits(motor, dJointSetAMotorParam, axis, true, c.angular_limits.lower[axis],
                               c.angular_limits.upper[axis], flipped);
                } else if (spring) {
                    set_spring(motor, dJointSetAMotorParam, axis, c.angular_springs.stiffness[axis],
                               c.angular_springs.damping[axis], step_s);
                }
            }
            break;
        }
        case ConstraintType::Motor: {
            if (c.motor_angular_enabled) {
                dJointID j = add_joint(dJointCreateAMotor(world, nullptr));
                dJointSetAMotorNumAxes(j, 1);
                dJointSetAMotorAxis(j, 0, 1, x_axis[0], x_axis[1], x_axis[2]);
                set_motor(j, dJointSetAMotorParam, sign * c.motor_angular_target_velocity, c.motor_angular_max_impulse);
            }
            if (c.motor_linear_enabled) {
                dJointID j = add_joint(dJointCreateLMotor(world, nullptr));
                dJointSetLMotorNumAxes(j, 1);
                dJointSetLMotorAxis(j, 0, 1, x_axis[0], x_axis[1], x_axis[2]);
                set_motor(j, dJointSetLMotorParam, sign * c.motor_linear_target_velocity, c.motor_linear_max_impulse);
            }
            break;
        }
    }
    if (c.breakable && !group.joints.empty()) {
        group.feedback = std::make_unique<dJointFeedback>();
        dJointSetFeedback(group.joints.front(), group.feedback.get());
        const dReal* p = dBodyGetPosition(a);
        const Vec3 com{p[0], p[1], p[2]};
        const dReal* q = dBodyGetQuaternion(a);
        const Quat to_body = quat_conjugate(Quat{q[0], q[1], q[2], q[3]});
        group.frame_in_body = {quat_rotate(to_body, sub(c.frame.location, com)), quat_multiply(to_body, c.frame.rotation)};
    }
    return group;
}

}  // namespace mwb
