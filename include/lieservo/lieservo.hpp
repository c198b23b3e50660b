// lieservo/lieservo.hpp — umbrella header of the whole library (Eigen only):
// status codes, units, Lie groups, estimation, control, real-time utilities, sampling.
// Include the area headers (e.g. <lieservo/groups.hpp>) instead to compile less.
#pragma once
#include <lieservo/detail/options_push.hpp>

#include <lieservo/control.hpp>
#include <lieservo/estimation.hpp>
#include <lieservo/groups.hpp>
#include <lieservo/realtime.hpp>
#include <lieservo/sampling.hpp>
#include <lieservo/status.hpp>
#include <lieservo/units.hpp>

#include <lieservo/detail/options_pop.hpp>
