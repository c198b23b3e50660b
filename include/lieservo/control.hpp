// lieservo/control.hpp — umbrella header of the control layer (paper:
// Section 3.3 (sec:se3_feedforward_feedback_control)): PID with feedforward, tactile servoing, pushing,
// dual-arm leader/follower (decentralised, and with a centralised follower) and the paper's
// controller presets (Tables 6–9); the tactile loop that runs a filter and a controller together.
#pragma once
#include <lieservo/detail/options_push.hpp>

#include <lieservo/control/centralised_dual_arm.hpp>
#include <lieservo/control/dual_arm.hpp>
#include <lieservo/control/pid.hpp>
#include <lieservo/control/presets.hpp>
#include <lieservo/control/pushing_controller.hpp>
#include <lieservo/control/tactile_loop.hpp>
#include <lieservo/control/tactile_servo_controller.hpp>

#include <lieservo/detail/options_pop.hpp>
