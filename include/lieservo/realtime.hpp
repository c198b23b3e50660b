// lieservo/realtime.hpp — the real-time layer between the controllers and a robot's
// 1 kHz command loop (Eigen + std only; noexcept; allocation-free per step).
//   velocity_smoother.hpp    jerk-limited Cartesian twist smoother (paper Section 4.4 (sec:software))
//   latest_value_channel.hpp lock-free latest-value hand-over between threads
//   watchdog.hpp             command-timeout / contact-loss stop policy
//   frames.hpp               sensor body twist → base twist of the EE origin (Ad of SE3)
//   velocity_pipeline.hpp    all of the above as one 1 kHz callback body
#pragma once
#include <lieservo/detail/options_push.hpp>

#include <lieservo/realtime/frames.hpp>
#include <lieservo/realtime/latest_value_channel.hpp>
#include <lieservo/realtime/velocity_pipeline.hpp>
#include <lieservo/realtime/velocity_smoother.hpp>
#include <lieservo/realtime/watchdog.hpp>

#include <lieservo/detail/options_pop.hpp>
